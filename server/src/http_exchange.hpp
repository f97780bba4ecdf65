#pragma once
// Small pieces of reading requests and writing answers shared by the routes.
#include <map>
#include <string>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "http_errors.hpp"

namespace oer::server {

void send_json(httplib::Response& response, int status, const nlohmann::json& body);
void send_problem(httplib::Response& response, const ErrorAnswer& answer);
// The answer to an upload (environments, meshes): the asset's JSON with `cached`, and 201 with
// Location when it is new, 200 when these bytes (and options) were there already.
void send_upload(httplib::Response& response, nlohmann::json asset, bool cached,
                 const std::string& location);

// The Content-Type's media type, lowercase, without parameters ("" when absent).
std::string media_type(const httplib::Request& request);

// The query parameters, each at most once and each one of `allowed` (else 422 naming it).
std::map<std::string, std::string> single_query(const httplib::Request& request,
                                                const std::vector<std::string>& allowed);

// Throws 401 (with WWW-Authenticate: Bearer) unless the request carries
// "Authorization: Bearer <key>"; the comparison takes the same time wherever they differ.
void require_api_key(const httplib::Request& request, const std::string& key);

// Whether If-None-Match lists etag (or is "*").
bool etag_matches(const httplib::Request& request, const std::string& etag);

}  // namespace oer::server
