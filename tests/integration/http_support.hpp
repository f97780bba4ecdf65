#pragma once
// What the integration tests share: a real Service on a loopback port with its own temporary
// data folder, HTTP helpers that hold every answer to api/openapi.yaml (status listed for the
// route, Content-Type, body schema, declared headers), a Prometheus text parser, raw sockets
// for hostile clients, and the synthetic assets the tests upload.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <httplib.h>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "oer/core/image.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/lighting/sh.hpp"
#include "oer/server/problem_json.hpp"
#include "oer/server/service.hpp"
#include "oer/server/service_config.hpp"

namespace oer::itest {

using Json = nlohmann::json;

// A fresh folder under the system's temporary directory (removed with everything in it):
// root/data is the service's data folder, so that a test can check that nothing appeared
// beside it.
class TempRoot {
  public:
    TempRoot();
    ~TempRoot();
    TempRoot(const TempRoot&) = delete;
    TempRoot& operator=(const TempRoot&) = delete;
    const std::filesystem::path& root() const { return root_; }
    std::filesystem::path data() const { return root_ / "data"; }

  private:
    std::filesystem::path root_;
};

// The configuration the tests start from: loopback, port 0, small and fast.
server::ServiceConfig test_config(const std::filesystem::path& data_dir);

// A started Service; its log lines are kept (and printed when a test fails).
class TestServer {
  public:
    explicit TestServer(server::ServiceConfig config);
    ~TestServer();
    void stop();
    int port() const;
    int admin_port() const;  // -1: no admin listener
    const server::ServiceConfig& config() const { return config_; }
    // A client on the loopback port with generous timeouts (no test may hang forever).
    std::unique_ptr<httplib::Client> client(int read_timeout_seconds = 120) const;
    std::vector<std::string> log_lines() const;

  private:
    server::ServiceConfig config_;
    std::unique_ptr<server::Service> service_;
    mutable std::mutex log_mutex_;
    std::vector<std::string> log_;
};

// 127.0.1.1, 127.0.1.2, ...: one loopback address per client (index 0 to 63749), so that
// per-address limits (the server's, a proxy's) see each client as another.
std::string client_address(int index);
// A client of the loopback port on its own keep-alive connection from client_address(index),
// with TCP_NODELAY (as browsers and load generators), as the load tests' clients are.
std::unique_ptr<httplib::Client> load_client(int port, int index, int read_timeout_seconds);

// Checks an answer against the spec: the route and method exist, the status is listed for
// them, the Content-Type is one the response declares, a JSON body matches its schema, and
// each declared header that is present matches its schema. `route` is the spec's path
// template ("/v1/environments/{id}"). Returns the parsed JSON body (null for other bodies).
Json expect_conforms(const std::string& method, const std::string& route,
                     const httplib::Result& result);

// The answer is problem+json of this kind (its status, its type and title), conforming to the
// spec, with a non-empty detail; when `parameter` is given, the body's `parameter` equals it.
void expect_problem(const std::string& method, const std::string& route,
                    const httplib::Result& result, server::ProblemKind kind,
                    const std::optional<std::string>& parameter = std::nullopt);

// Numbers within rel of each other (relative to the larger magnitude), everything else equal,
// members and elements alike; where names the document in failures.
void expect_json_near(const Json& got, const Json& expected, double rel, const std::string& where);

// Prometheus text: every sample as name{labels} -> value.
struct Sample {
    std::string name;
    std::map<std::string, std::string> labels;
    double value = 0.0;
};
struct Metrics {
    std::vector<Sample> samples;
    std::map<std::string, std::string> types;  // family -> counter|gauge|histogram
    // The sum of the samples of `name` whose labels include every one of `labels`.
    double sum(const std::string& name,
               const std::map<std::string, std::string>& labels = {}) const;
    bool has(const std::string& name) const;
};
Metrics parse_prometheus(const std::string& text);  // fails the test on a malformed line
Metrics scrape(httplib::Client& client);
// The transfers the server has baked so far (oer_transfers_computed_total).
double transfers_computed(httplib::Client& client);

// The body of an answer as bytes, and images decoded from it.
std::vector<std::uint8_t> bytes_of(const httplib::Result& result);
Rgba8Image decode_image(const httplib::Result& result);

// How two frames of one size differ over the columns [first_column, last_column) (every column
// by default), channel by channel (RGB and alpha), in 8-bit steps.
struct FrameDifference {
    std::size_t differing = 0;  // channel values that differ
    int largest = 0;            // 0 to 255
    double mean = 0.0;          // per channel value
};
FrameDifference frame_difference(const Rgba8Image& a, const Rgba8Image& b, int first_column = 0,
                                 int last_column = -1);

// Raw TCP to the loopback port, for clients that httplib would not let us be.
class RawSocket {
  public:
    // From source (another loopback address such as "127.0.0.2", to be another client) when
    // given.
    explicit RawSocket(int port, const char* source = nullptr);
    ~RawSocket();
    RawSocket(const RawSocket&) = delete;
    RawSocket& operator=(const RawSocket&) = delete;
    bool ok() const { return fd_ >= 0; }
    int fd() const { return fd_; }
    // false once the peer has closed or reset the connection.
    bool send_all(const std::string& bytes);
    // Whatever arrives within the timeout (empty on timeout); nullopt when the peer closed.
    std::optional<std::string> receive(std::chrono::milliseconds timeout);
    // Reads until "\r\n\r\n" and Content-Length bytes of body, or until the deadline.
    std::optional<std::string> receive_response(std::chrono::milliseconds timeout);

  private:
    int fd_ = -1;
};

// Polls `condition` every 10 ms until it holds or the deadline passes; whether it held.
bool eventually(const std::function<bool()>& condition, std::chrono::milliseconds deadline);

// Assets built in the tests.
// A dim sky with three small bright discs (the lights), as an RGBA float EXR in memory.
struct SyntheticEnvironment {
    HdrImage image;
    std::vector<glm::dvec3> light_directions;
};
SyntheticEnvironment three_disc_environment(int width = 256, int height = 128);
std::string exr_bytes(const HdrImage& image);
std::string hdr_bytes(const HdrImage& image);  // Radiance RGBE, through a temporary file
// An axis-aligned box as OBJ text: positions, flat normals, 12 triangles, no material.
std::string box_obj(glm::dvec3 low, glm::dvec3 high);
// The same box as a binary glTF (positions, normals, indices; one primitive, no material), or,
// given a PNG's bytes, with texture coordinates and a dielectric material whose base colour is
// that image, embedded (each face shows all of it).
// texture_maps (1 to 4): the image is also the metallic-roughness, normal and occlusion
// texture, in that order, each its own copy.
std::string box_glb(glm::dvec3 low, glm::dvec3 high, const std::vector<std::uint8_t>& png = {},
                    int texture_maps = 1);
// box_glb with a side x side texture of noise from seed (a PNG of about 3.7 side^2 bytes: noise
// does not compress), for uploads whose store write lasts long enough to be interrupted while
// the mesh stays quick to load and draw.
std::string noise_box_glb(unsigned seed, int side);
// A square grid of n x n quads on y = 0 (2 n^2 triangles) as OBJ text: about 45 n^2 bytes, for
// uploads and transfer bakes that take a while.
std::string grid_obj(int n);

// An answer kept past its connection (for a request made on another thread, or one whose
// server is killed meanwhile): the status (0 without an answer), ETag and body.
struct Answer {
    int status = 0;
    std::string etag;
    std::string body;
};
Answer answer_of(const httplib::Result& result);

// Uploads and renders, checked to succeed (fatal failures inside; check HasFatalFailure).
Json upload_environment(httplib::Client& client, const std::string& bytes,
                        const std::string& content_type, const std::string& query = "");
Json upload_mesh(httplib::Client& client, const std::string& bytes,
                 const std::string& content_type);
// Waits (up to 2 minutes) until the bakes an upload of mesh_id started have ended (GET
// /v1/meshes/{id}/preparation neither queued nor baking, on the floor nor without it), so that
// their CPU is not taken for what a test measures next; returns the state the first frames'
// bake ended in.
std::string wait_for_preparation(httplib::Client& client, const std::string& mesh_id);
// A server-sent event stream (GET .../events) read to its end, or until the client's read
// timeout: the answer's status and Content-Type, each `progress` event's data (an event of
// another type fails the test), and whether the server ended the stream (the chunked body's
// last chunk came).
struct EventStream {
    int status = 0;
    std::string content_type;
    std::vector<Json> events;
    bool ended = false;
};
EventStream follow_events(httplib::Client& client, const std::string& path);
httplib::Result post_json(httplib::Client& client, const std::string& path, const Json& body,
                          const httplib::Headers& headers = {});
// GET /v1/render with this path and query, checked to succeed and to conform to the spec: the
// frame decoded (an empty image after a failure).
Rgba8Image get_frame(httplib::Client& client, const std::string& path_and_query);

// The value below which `fraction` of values lie (0.5: the median, 0.99: p99), by rank; 0 for
// no values.
double percentile(std::vector<double> values, double fraction);

// Seconds of the steady clock since `start`.
double seconds_since(std::chrono::steady_clock::time_point start);
// The three numbers of `name=x,y,z` in an X-Oer-Camera header (a failure of the test without
// them).
glm::dvec3 camera_vector(const std::string& header, const std::string& name);

// SH coefficients as the API writes them (an array of [r, g, b], l (l + 1) + m order).
ShRgb sh_of(const Json& coefficients);

}  // namespace oer::itest
