#pragma once
// Small pieces of reading requests and writing answers shared by the routes.
#include <chrono>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "http_errors.hpp"
#include "oer/mesh/look_at_camera.hpp"

namespace oer::server {

void send_json(httplib::Response& response, int status, const nlohmann::json& body);
void send_problem(httplib::Response& response, const ErrorAnswer& answer);
// The answer to an upload (environments, meshes): the asset's JSON with `cached`, and 201 with
// Location when it is new, 200 when these bytes (and options) were there already.
void send_upload(httplib::Response& response, nlohmann::json asset, bool cached,
                 const std::string& location);

// What an upload's errors call the file: the name the client sent it by (?filename=, as the
// user's file was named: 1 to 255 bytes of UTF-8 without control characters, else 422 naming
// `filename`), or "the uploaded .<extension> file". Only messages use it: the store names
// every file by its content.
std::string upload_file_name(const std::map<std::string, std::string>& query,
                             const std::string& extension);

// X-Oer-Camera, and the `camera` of the hotspots' and the pick's answers: the camera a frame is
// seen from, in the query's notation, so that a client can continue from the automatic framing
// (zoom from its distance, say) without a jump, or draw an asset camera's frame again
// explicitly: `eye=0,1.2,3.4; target=0,0.8,0; up=0,1,0; fov_y=45`. Nine significant digits:
// every float reads back as itself, so the same camera given explicitly draws the same pixels.
std::string camera_header(const Camera& camera);

// The Content-Type's media type, lowercase, without parameters ("" when absent).
std::string media_type(const httplib::Request& request);

// Throws 415 unless the body is application/json, naming `what` ("a render request").
void require_json_body(const httplib::Request& request, const std::string& what);

// The query parameters, each at most once and each one of `allowed` (else 422 naming it).
std::map<std::string, std::string> single_query(const httplib::Request& request,
                                                const std::vector<std::string>& allowed);

// A listing's query (GET /v1/environments, GET /v1/meshes, GET /v1/jobs): ?limit= entries a
// page (1 to the listing's max_limit, kDefaultListLimit when absent) and ?after= (the id a page
// starts after, as the previous page's `next` gives it); each at most once, any other parameter
// unknown.
inline constexpr std::size_t kDefaultListLimit = 100;
inline constexpr std::size_t kMaxListLimit = 1000;
struct ListingForm {
    bool (*is_id)(std::string_view text);   // whether `after` can be an id of the listing
    std::string_view id_form;               // what an id is, for the 422: "64 lowercase ..."
    std::size_t max_limit = kMaxListLimit;  // kDefaultListLimit or more
};
struct ListingQuery {
    std::string after;  // "" for the first page
    std::size_t limit = kDefaultListLimit;
};
// Throws InvalidParameter (422) naming the parameter at fault.
ListingQuery listing_query(const httplib::Request& request, const ListingForm& form);

// 200 with {"<member>": entries, "next": "<path>?limit=..&after=.."}, `next` present only when
// next_after is (more entries follow).
void send_listing(httplib::Response& response, const std::string& path, const std::string& member,
                  nlohmann::json entries, const std::optional<std::string>& next_after,
                  std::size_t limit);

// RFC 3339 in UTC to the second: "2026-12-01T09:30:00Z".
std::string rfc3339(std::chrono::system_clock::time_point time);

// Throws 401 (with WWW-Authenticate: Bearer) unless the request carries
// "Authorization: Bearer <key>"; the comparison takes the same time wherever they differ.
void require_api_key(const httplib::Request& request, const std::string& key);

// Whether If-None-Match lists etag (or is "*").
bool etag_matches(const httplib::Request& request, const std::string& etag);

}  // namespace oer::server
