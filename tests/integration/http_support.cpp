#include "http_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <glm/vec2.hpp>

#include "json_schema.hpp"
#include "oer/image/image_io.hpp"
#include "openapi_spec.hpp"
#include "synthetic_maps.hpp"

namespace oer::itest {

namespace {

std::string lowercase(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

// "text/plain; version=0.0.4; charset=utf-8" -> ("text/plain", {"version=0.0.4", ...})
std::pair<std::string, std::vector<std::string>> media_type(const std::string& header) {
    std::vector<std::string> parts;
    std::stringstream in(header);
    for (std::string part; std::getline(in, part, ';');) {
        parts.push_back(lowercase(testing::trim(part)));
    }
    if (parts.empty()) {
        return {"", {}};
    }
    return {parts[0], std::vector<std::string>(parts.begin() + 1, parts.end())};
}

const Json& resolve(const Json& node) {
    const Json& root = testing::openapi_spec().json();
    const Json* current = &node;
    for (int depth = 0; depth < 16 && current->is_object() && current->contains("$ref"); ++depth) {
        current = &root.at(Json::json_pointer(current->at("$ref").get<std::string>().substr(1)));
    }
    return *current;
}

std::string describe(const httplib::Result& result) {
    if (!result) {
        return "no answer (" + httplib::to_string(result.error()) + ")";
    }
    std::string body = result->body.substr(0, 400);
    for (char& c : body) {
        if (static_cast<unsigned char>(c) < 32 && c != '\n') {
            c = '.';
        }
    }
    return std::to_string(result->status) + " " + result->get_header_value("Content-Type") + ": " +
           body;
}

}  // namespace

TempRoot::TempRoot() {
    std::random_device random;
    root_ = std::filesystem::temp_directory_path() /
            ("oer-itest-" + std::to_string(::getpid()) + "-" + std::to_string(random()));
    std::filesystem::create_directories(root_ / "data");
}

TempRoot::~TempRoot() {
    std::error_code ignored;
    std::filesystem::remove_all(root_, ignored);
}

server::ServiceConfig test_config(const std::filesystem::path& data_dir) {
    server::ServiceConfig config;
    config.host = "127.0.0.1";
    config.port = 0;
    config.data_dir = data_dir;
    config.render_workers = 1;
    // Test servers do not warm the default scene before they are ready: the studio's prefilter
    // took 1.4 s under the sanitizers, the bake 0.5 s, for each of some 100 servers; the frames
    // that need them make them. The smallest transfer budget (64 rays a point) keeps every
    // bake to a fraction of a second, under the sanitizers too (at the default budget the
    // default scene's took about 13 s there).
    config.transfer_ray_budget = 100'000;
    config.warm_default_scene = false;
    // The tests render many uncached frames from one address; the per-client share of
    // rendering is tested where it is set (render_budget_test.cpp).
    config.client_render_rate = 0.0;
    config.access_log = true;
    return config;
}

TestServer::TestServer(server::ServiceConfig config) : config_(std::move(config)) {
    service_ = std::make_unique<server::Service>(config_, [this](std::string_view line) {
        std::lock_guard lock(log_mutex_);
        log_.emplace_back(line);
    });
    service_->start();
}

TestServer::~TestServer() {
    stop();
    if (::testing::Test::HasFailure()) {
        std::lock_guard lock(log_mutex_);
        std::string tail;
        for (std::size_t i = log_.size() > 40 ? log_.size() - 40 : 0; i < log_.size(); ++i) {
            tail += "  " + log_[i] + "\n";
        }
        std::cerr << "service log (last lines):\n" << tail;
    }
}

void TestServer::stop() {
    if (service_) {
        service_->stop();
        service_.reset();
    }
}

int TestServer::port() const {
    return service_->port();
}

int TestServer::admin_port() const {
    return service_->admin_port();
}

std::unique_ptr<httplib::Client> TestServer::client(int read_timeout_seconds) const {
    auto client = std::make_unique<httplib::Client>("127.0.0.1", port());
    client->set_connection_timeout(5, 0);
    client->set_read_timeout(read_timeout_seconds, 0);
    client->set_write_timeout(30, 0);
    return client;
}

// 127.0.1.1, 127.0.1.2, ...: one loopback address per client.
std::string client_address(int index) {
    return "127.0." + std::to_string(1 + index / 250) + "." + std::to_string(1 + index % 250);
}

// A client on its own keep-alive connection from its own loopback address.
std::unique_ptr<httplib::Client> load_client(int port, int index, int read_timeout_seconds) {
    auto client = std::make_unique<httplib::Client>("127.0.0.1", port);
    client->set_connection_timeout(5, 0);
    client->set_read_timeout(read_timeout_seconds, 0);
    client->set_write_timeout(30, 0);
    client->set_keep_alive(true);
    // Headers and body in separate writes: without it, Nagle's algorithm holds an upload's body
    // for the server's delayed ACK (40 ms).
    client->set_tcp_nodelay(true);
    const std::string address = client_address(index);
    // Called before connect: the connection leaves from the client's own address.
    client->set_socket_options([address](socket_t sock) {
        sockaddr_in source{};
        source.sin_family = AF_INET;
        ::inet_pton(AF_INET, address.c_str(), &source.sin_addr);
        if (::bind(sock, reinterpret_cast<const sockaddr*>(&source), sizeof source) != 0) {
            ADD_FAILURE() << "cannot bind a client socket to " << address;
        }
    });
    return client;
}

std::vector<std::string> TestServer::log_lines() const {
    std::lock_guard lock(log_mutex_);
    return log_;
}

Json expect_conforms(const std::string& method, const std::string& route,
                     const httplib::Result& result) {
    if (!result) {
        ADD_FAILURE() << method << " " << route << ": " << describe(result);
        return nullptr;
    }
    const Json& root = testing::openapi_spec().json();
    const Json& paths = root.at("paths");
    if (!paths.contains(route) || !paths.at(route).contains(lowercase(method))) {
        ADD_FAILURE() << method << " " << route << " is not in api/openapi.yaml";
        return nullptr;
    }
    const Json& responses = paths.at(route).at(lowercase(method)).at("responses");
    const std::string status = std::to_string(result->status);
    if (!responses.contains(status)) {
        ADD_FAILURE() << method << " " << route << " answered " << describe(result)
                      << ", a status api/openapi.yaml does not list for it";
        return nullptr;
    }
    const Json& response = resolve(responses.at(status));
    const std::string where = method + " " + route + " " + status;

    const Json headers = response.value("headers", Json::object());
    for (const auto& [name, declared] : headers.items()) {
        const Json& header = resolve(declared);
        if (!result->has_header(name)) {
            // OpenAPI 3.1, Header Object: `required` defaults to false.
            if (header.value("required", false)) {
                ADD_FAILURE() << where << ": the required header " << name << " is missing";
            }
            continue;
        }
        const Json& schema = header.at("schema");
        const std::string text = result->get_header_value(name);
        Json value = text;
        if (resolve(schema).value("type", "") == "integer") {
            char* end = nullptr;
            const long long number = std::strtoll(text.c_str(), &end, 10);
            value = (end && *end == '\0' && !text.empty()) ? Json(number) : Json(text);
        }
        for (const std::string& error : testing::schema_errors(value, schema, root)) {
            ADD_FAILURE() << where << ": header " << name << ": " << error;
        }
    }

    if (!response.contains("content")) {
        EXPECT_TRUE(result->body.empty())
            << where << " declares no body, got " << result->body.size() << " bytes";
        return nullptr;
    }
    const auto [actual, actual_parameters] = media_type(result->get_header_value("Content-Type"));
    for (const auto& [declared_type, content] : response.at("content").items()) {
        const auto [type, parameters] = media_type(declared_type);
        if (type != actual) {
            continue;
        }
        for (const std::string& parameter : parameters) {
            EXPECT_NE(std::find(actual_parameters.begin(), actual_parameters.end(), parameter),
                      actual_parameters.end())
                << where << ": Content-Type " << result->get_header_value("Content-Type")
                << " lacks " << parameter;
        }
        if (type.size() >= 4 && type.substr(type.size() - 4) == "json") {
            const Json body = Json::parse(result->body, nullptr, false);
            if (body.is_discarded()) {
                ADD_FAILURE() << where << ": the body is not JSON: " << describe(result);
                return nullptr;
            }
            for (const std::string& error :
                 testing::schema_errors(body, content.at("schema"), root)) {
                ADD_FAILURE() << where << ": body" << error << "\n  body: " << body.dump();
            }
            return body;
        }
        return nullptr;
    }
    ADD_FAILURE() << where << ": Content-Type \"" << result->get_header_value("Content-Type")
                  << "\" is not one of " << response.at("content").dump().substr(0, 300);
    return nullptr;
}

void expect_problem(const std::string& method, const std::string& route,
                    const httplib::Result& result, server::ProblemKind kind,
                    const std::optional<std::string>& parameter) {
    const server::ProblemType& type = server::problem_type(kind);
    const int status = type.status;
    ASSERT_TRUE(result) << method << " " << route << ": " << describe(result);
    ASSERT_EQ(result->status, status) << method << " " << route << ": " << describe(result);
    EXPECT_EQ(media_type(result->get_header_value("Content-Type")).first,
              "application/problem+json")
        << describe(result);
    const Json body = expect_conforms(method, route, result);
    ASSERT_TRUE(body.is_object()) << describe(result);
    EXPECT_EQ(body.value("status", 0), status) << body.dump();
    EXPECT_EQ(body.value("type", ""), type.type) << body.dump();
    EXPECT_EQ(body.value("title", ""), type.title) << body.dump();
    EXPECT_FALSE(body.value("detail", std::string()).empty()) << "no detail: " << body.dump();
    if (parameter) {
        EXPECT_EQ(body.value("parameter", std::string("<absent>")), *parameter) << body.dump();
    }
}

void expect_json_near(const Json& got, const Json& expected, double rel, const std::string& where) {
    if (got.is_number() && expected.is_number()) {
        const double a = got.get<double>(), b = expected.get<double>();
        EXPECT_LE(std::abs(a - b), rel * std::max(std::abs(a), std::abs(b)) + 1e-12)
            << where << ": " << a << " vs " << b;
        return;
    }
    ASSERT_EQ(got.type(), expected.type())
        << where << ": " << got.dump() << " vs " << expected.dump();
    if (got.is_object()) {
        for (const auto& [key, value] : expected.items()) {
            ASSERT_TRUE(got.contains(key)) << where << " lacks " << key;
            expect_json_near(got.at(key), value, rel, where + "/" + key);
        }
        for (const auto& [key, value] : got.items()) {
            EXPECT_TRUE(expected.contains(key)) << where << " has unexpected " << key;
        }
    } else if (got.is_array()) {
        ASSERT_EQ(got.size(), expected.size()) << where;
        for (std::size_t i = 0; i < got.size(); ++i) {
            expect_json_near(got[i], expected[i], rel, where + "/" + std::to_string(i));
        }
    } else {
        EXPECT_EQ(got, expected) << where;
    }
}

double Metrics::sum(const std::string& name,
                    const std::map<std::string, std::string>& labels) const {
    double total = 0.0;
    for (const Sample& sample : samples) {
        if (sample.name != name) {
            continue;
        }
        bool matches = true;
        for (const auto& [key, value] : labels) {
            const auto found = sample.labels.find(key);
            matches = matches && found != sample.labels.end() && found->second == value;
        }
        if (matches) {
            total += sample.value;
        }
    }
    return total;
}

bool Metrics::has(const std::string& name) const {
    return std::any_of(samples.begin(), samples.end(),
                       [&](const Sample& sample) { return sample.name == name; });
}

Metrics parse_prometheus(const std::string& text) {
    Metrics metrics;
    std::stringstream in(text);
    for (std::string line; std::getline(in, line);) {
        if (line.empty()) {
            continue;
        }
        if (line.rfind("# TYPE ", 0) == 0) {
            std::stringstream words(line.substr(7));
            std::string family, type;
            words >> family >> type;
            metrics.types[family] = type;
            continue;
        }
        if (line[0] == '#') {
            continue;
        }
        Sample sample;
        std::size_t i = 0;
        while (i < line.size() && line[i] != '{' && line[i] != ' ') {
            ++i;
        }
        sample.name = line.substr(0, i);
        if (i < line.size() && line[i] == '{') {
            ++i;
            while (i < line.size() && line[i] != '}') {
                const std::size_t equals = line.find('=', i);
                if (equals == std::string::npos || equals + 1 >= line.size() ||
                    line[equals + 1] != '"') {
                    ADD_FAILURE() << "malformed labels: " << line;
                    return metrics;
                }
                const std::string key = line.substr(i, equals - i);
                std::string value;
                std::size_t j = equals + 2;
                for (; j < line.size() && line[j] != '"'; ++j) {
                    if (line[j] == '\\' && j + 1 < line.size()) {
                        ++j;
                        value += line[j] == 'n' ? '\n' : line[j];
                    } else {
                        value += line[j];
                    }
                }
                sample.labels[key] = value;
                i = j + 1;
                if (i < line.size() && line[i] == ',') {
                    ++i;
                }
            }
            ++i;  // '}'
        }
        const std::string rest = testing::trim(line.substr(std::min(i, line.size())));
        char* end = nullptr;
        const std::string number = rest.substr(0, rest.find(' '));
        sample.value = number == "+Inf"   ? HUGE_VAL
                       : number == "-Inf" ? -HUGE_VAL
                                          : std::strtod(number.c_str(), &end);
        if (number.empty() || (end && *end != '\0' && number != "+Inf" && number != "-Inf")) {
            ADD_FAILURE() << "malformed sample: " << line;
            return metrics;
        }
        metrics.samples.push_back(std::move(sample));
    }
    return metrics;
}

Metrics scrape(httplib::Client& client) {
    const auto result = client.Get("/metrics");
    if (!result || result->status != 200) {
        ADD_FAILURE() << "GET /metrics: " << describe(result);
        return {};
    }
    return parse_prometheus(result->body);
}

double transfers_computed(httplib::Client& client) {
    return scrape(client).sum("oer_transfers_computed_total");
}

std::vector<std::uint8_t> bytes_of(const httplib::Result& result) {
    return std::vector<std::uint8_t>(result->body.begin(), result->body.end());
}

Rgba8Image decode_image(const httplib::Result& result) {
    return decode_8bit(bytes_of(result));
}

FrameDifference frame_difference(const Rgba8Image& a, const Rgba8Image& b, int first_column,
                                 int last_column) {
    FrameDifference result;
    if (a.width != b.width || a.height != b.height || a.pixels.size() != b.pixels.size()) {
        ADD_FAILURE() << "frames of " << a.width << "x" << a.height << " and " << b.width << "x"
                      << b.height;
        result.largest = 255;
        return result;
    }
    const int last = last_column < 0 ? a.width : std::min(last_column, a.width);
    double sum = 0.0;
    std::size_t count = 0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = std::max(first_column, 0); x < last; ++x) {
            for (std::size_t c = 0; c < 4; ++c) {
                const std::size_t i =
                    4 * (std::size_t(y) * std::size_t(a.width) + std::size_t(x)) + c;
                const int delta = std::abs(int(a.pixels[i]) - int(b.pixels[i]));
                result.differing += delta > 0 ? 1 : 0;
                result.largest = std::max(result.largest, delta);
                sum += delta;
                ++count;
            }
        }
    }
    result.mean = count > 0 ? sum / double(count) : 0.0;
    return result;
}

RawSocket::RawSocket(int port, const char* source) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd_ < 0) {
        return;
    }
    if (source) {
        sockaddr_in local{};
        local.sin_family = AF_INET;
        if (::inet_pton(AF_INET, source, &local.sin_addr) != 1 ||
            ::bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
            ::close(fd_);
            fd_ = -1;
            return;
        }
    }
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(std::uint16_t(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
        ::close(fd_);
        fd_ = -1;
        return;
    }
    const int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    timeval timeout{2, 0};  // a send that cannot make progress for 2 s fails
    ::setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
}

RawSocket::~RawSocket() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

bool RawSocket::send_all(const std::string& bytes) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) {
            return false;
        }
        sent += std::size_t(n);
    }
    return true;
}

std::optional<std::string> RawSocket::receive(std::chrono::milliseconds timeout) {
    pollfd poll_fd{fd_, POLLIN, 0};
    if (::poll(&poll_fd, 1, int(timeout.count())) <= 0) {
        return std::string();
    }
    char buffer[65536];
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
    if (n <= 0) {
        return std::nullopt;
    }
    return std::string(buffer, std::size_t(n));
}

std::optional<std::string> RawSocket::receive_response(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::string received;
    while (std::chrono::steady_clock::now() < deadline) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        const auto chunk = receive(std::max(left, std::chrono::milliseconds(1)));
        if (!chunk) {
            return received.empty() ? std::nullopt : std::optional<std::string>(received);
        }
        received += *chunk;
        const std::size_t end = received.find("\r\n\r\n");
        if (end != std::string::npos) {
            const std::string head = lowercase(received.substr(0, end));
            const std::size_t length = head.find("content-length:");
            const std::size_t body =
                length == std::string::npos ? 0 : std::stoul(head.substr(length + 15));
            if (received.size() >= end + 4 + body) {
                return received;
            }
        }
    }
    return received;
}

bool eventually(const std::function<bool()>& condition, std::chrono::milliseconds deadline) {
    const auto end = std::chrono::steady_clock::now() + deadline;
    while (true) {
        if (condition()) {
            return true;
        }
        if (std::chrono::steady_clock::now() > end) {
            return false;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

SyntheticEnvironment three_disc_environment(int width, int height) {
    SyntheticEnvironment environment;
    environment.light_directions = {glm::normalize(glm::dvec3(1.0, 1.2, 0.0)),
                                    glm::normalize(glm::dvec3(-0.6, 1.2, 0.8)),
                                    glm::normalize(glm::dvec3(-0.5, 1.0, -0.9))};
    environment.image =
        testing::disc_map(width, height, glm::vec3(0.05f),
                          {{environment.light_directions[0], 0.08, {400, 380, 350}},
                           {environment.light_directions[1], 0.08, {200, 260, 400}},
                           {environment.light_directions[2], 0.08, {300, 250, 200}}});
    return environment;
}

std::string exr_bytes(const HdrImage& image) {
    std::vector<float> rgba(image.pixel_count() * 4, 1.0f);
    for (std::size_t i = 0; i < image.pixel_count(); ++i) {
        for (int c = 0; c < 3; ++c) {
            rgba[i * 4 + c] = image.pixels[i * 3 + c];
        }
    }
    const std::vector<std::uint8_t> bytes = encode_exr(image.width, image.height, rgba);
    return std::string(bytes.begin(), bytes.end());
}

std::string hdr_bytes(const HdrImage& image) {
    const TempRoot folder;
    const std::string path = (folder.root() / "map.hdr").string();
    write_image_file(image, path);
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

namespace {

struct BoxGeometry {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> texcoords;  // each face the whole texture
    std::vector<std::uint32_t> indices;
};

BoxGeometry box_geometry(glm::dvec3 low_d, glm::dvec3 high_d) {
    const glm::vec3 low(low_d), high(high_d);
    BoxGeometry box;
    const glm::vec3 normals[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                  {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    const glm::vec3 centre = (low + high) * 0.5f, half = (high - low) * 0.5f;
    for (const glm::vec3& n : normals) {
        const glm::vec3 u = std::abs(n.y) > 0.5f ? glm::vec3(0, 0, n.y) : glm::vec3(0, 1, 0);
        const glm::vec3 v = glm::cross(n, u);
        const std::uint32_t base = std::uint32_t(box.positions.size());
        for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
            box.positions.push_back(centre + half * (n + float(a) * u + float(b) * v));
            box.normals.push_back(n);
            box.texcoords.emplace_back(float(a + 1) * 0.5f, float(b + 1) * 0.5f);
        }
        box.indices.insert(box.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return box;
}

}  // namespace

std::string box_obj(glm::dvec3 low, glm::dvec3 high) {
    const BoxGeometry box = box_geometry(low, high);
    std::ostringstream out;
    out.precision(9);
    out << "# a box\n";
    for (const glm::vec3& p : box.positions) {
        out << "v " << p.x << " " << p.y << " " << p.z << "\n";
    }
    for (const glm::vec3& n : box.normals) {
        out << "vn " << n.x << " " << n.y << " " << n.z << "\n";
    }
    for (std::size_t i = 0; i < box.indices.size(); i += 3) {
        out << "f";
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t index = box.indices[i + k] + 1;
            out << " " << index << "//" << index;
        }
        out << "\n";
    }
    return out.str();
}

std::string box_glb(glm::dvec3 low, glm::dvec3 high, const std::vector<std::uint8_t>& png,
                    int texture_maps) {
    const BoxGeometry box = box_geometry(low, high);
    std::string bin;
    const auto append = [&bin](const void* data, std::size_t size) {
        bin.append(static_cast<const char*>(data), size);
        while (bin.size() % 4 != 0) {
            bin += '\0';
        }
    };
    Json views = Json::array();
    const auto view = [&](const void* data, std::size_t size, std::optional<int> target) {
        Json entry = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}};
        if (target) {
            entry["target"] = *target;
        }
        append(data, size);
        views.push_back(entry);
        return int(views.size()) - 1;
    };
    const int positions =
        view(box.positions.data(), box.positions.size() * sizeof(glm::vec3), 34962);
    const int normals = view(box.normals.data(), box.normals.size() * sizeof(glm::vec3), 34962);
    const int indices = view(box.indices.data(), box.indices.size() * sizeof(std::uint32_t), 34963);
    Json attributes = {{"POSITION", 0}, {"NORMAL", 1}};
    Json accessors = {{{"bufferView", positions},
                       {"componentType", 5126},
                       {"count", box.positions.size()},
                       {"type", "VEC3"},
                       {"min", {low.x, low.y, low.z}},
                       {"max", {high.x, high.y, high.z}}},
                      {{"bufferView", normals},
                       {"componentType", 5126},
                       {"count", box.normals.size()},
                       {"type", "VEC3"}},
                      {{"bufferView", indices},
                       {"componentType", 5125},
                       {"count", box.indices.size()},
                       {"type", "SCALAR"}}};
    Json primitive = {{"attributes", attributes}, {"indices", 2}, {"mode", 4}};
    Json gltf = {{"asset", {{"version", "2.0"}}},
                 {"scene", 0},
                 {"scenes", {{{"nodes", {0}}}}},
                 {"nodes", {{{"mesh", 0}}}}};
    if (!png.empty()) {
        const int texcoords =
            view(box.texcoords.data(), box.texcoords.size() * sizeof(glm::vec2), 34962);
        accessors.push_back({{"bufferView", texcoords},
                             {"componentType", 5126},
                             {"count", box.texcoords.size()},
                             {"type", "VEC2"}});
        primitive["attributes"]["TEXCOORD_0"] = 3;
        primitive["material"] = 0;
        Json material = {{"pbrMetallicRoughness",
                          {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}}}};
        if (texture_maps > 1) {
            material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
        }
        if (texture_maps > 2) {
            material["normalTexture"] = {{"index", 2}};
        }
        if (texture_maps > 3) {
            material["occlusionTexture"] = {{"index", 3}};
        }
        gltf["materials"] = Json::array({material});
        gltf["textures"] = Json::array();
        gltf["images"] = Json::array();
        for (int map = 0; map < std::clamp(texture_maps, 1, 4); ++map) {
            gltf["textures"].push_back({{"source", map}});
            gltf["images"].push_back({{"bufferView", view(png.data(), png.size(), std::nullopt)},
                                      {"mimeType", "image/png"}});
        }
    }
    gltf["meshes"] = {{{"primitives", {primitive}}}};
    gltf["accessors"] = accessors;
    gltf["bufferViews"] = views;
    gltf["buffers"] = {{{"byteLength", bin.size()}}};
    std::string json = gltf.dump();
    while (json.size() % 4 != 0) {
        json += ' ';
    }
    std::string glb;
    const auto word = [&glb](std::uint32_t value) {
        glb.append(reinterpret_cast<const char*>(&value), 4);
    };
    word(0x46546C67);  // "glTF"
    word(2);
    word(std::uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    word(std::uint32_t(json.size()));
    word(0x4E4F534A);  // "JSON"
    glb += json;
    word(std::uint32_t(bin.size()));
    word(0x004E4942);  // "BIN\0"
    glb += bin;
    return glb;
}

Answer answer_of(const httplib::Result& result) {
    if (!result) {
        return {};
    }
    return {result->status, result->get_header_value("ETag"), result->body};
}

std::string noise_box_glb(unsigned seed, int side) {
    Rgba8Image noise;
    noise.width = noise.height = side;
    noise.pixels.resize(std::size_t(side) * std::size_t(side) * 4);
    std::mt19937 random(seed);
    for (std::size_t i = 0; i < noise.pixels.size(); i += 4) {
        const std::uint32_t bits = random();
        std::memcpy(&noise.pixels[i], &bits, 3);
        noise.pixels[i + 3] = 255;
    }
    return box_glb({-0.5, 0, -0.5}, {0.5, 1, 0.5}, encode_png(noise));
}

std::string grid_obj(int n) {
    std::string text;
    text.reserve(std::size_t(n + 1) * std::size_t(n + 1) * 24 +
                 std::size_t(n) * std::size_t(n) * 60);
    for (int z = 0; z <= n; ++z) {
        for (int x = 0; x <= n; ++x) {
            text += "v " + std::to_string(x) + " 0 " + std::to_string(z) + "\n";
        }
    }
    const auto vertex = [n](int x, int z) { return std::to_string(z * (n + 1) + x + 1); };
    for (int z = 0; z < n; ++z) {
        for (int x = 0; x < n; ++x) {
            text += "f " + vertex(x, z) + " " + vertex(x, z + 1) + " " + vertex(x + 1, z + 1) +
                    "\nf " + vertex(x, z) + " " + vertex(x + 1, z + 1) + " " + vertex(x + 1, z) +
                    "\n";
        }
    }
    return text;
}

Json upload_environment(httplib::Client& client, const std::string& bytes,
                        const std::string& content_type, const std::string& query) {
    const auto result =
        client.Post(("/v1/environments" + (query.empty() ? "" : "?" + query)).c_str(), bytes,
                    content_type.c_str());
    if (!result || (result->status != 200 && result->status != 201)) {
        ADD_FAILURE() << "POST /v1/environments?" << query << ": " << describe(result);
        return nullptr;
    }
    return expect_conforms("POST", "/v1/environments", result);
}

Json upload_mesh(httplib::Client& client, const std::string& bytes,
                 const std::string& content_type) {
    const auto result = client.Post("/v1/meshes", bytes, content_type.c_str());
    if (!result || (result->status != 200 && result->status != 201)) {
        ADD_FAILURE() << "POST /v1/meshes: " << describe(result);
        return nullptr;
    }
    return expect_conforms("POST", "/v1/meshes", result);
}

EventStream follow_events(httplib::Client& client, const std::string& path) {
    EventStream stream;
    std::string buffer;
    const auto followed = client.Get(
        path.c_str(),
        [&](const httplib::Response& response) {
            stream.status = response.status;
            stream.content_type = response.get_header_value("Content-Type");
            return response.status == 200;
        },
        [&](const char* data, std::size_t length) {
            buffer.append(data, length);
            for (std::size_t end; (end = buffer.find("\n\n")) != std::string::npos;) {
                const std::string event = buffer.substr(0, end);
                buffer.erase(0, end + 2);
                if (const auto data_at = event.find("data: "); data_at != std::string::npos) {
                    EXPECT_EQ(event.substr(0, 16), "event: progress\n") << event;
                    stream.events.push_back(Json::parse(event.substr(data_at + 6)));
                }
            }
            return true;
        });
    stream.ended = bool(followed);
    return stream;
}

std::string wait_for_preparation(httplib::Client& client, const std::string& mesh_id) {
    const std::string path = "/v1/meshes/" + mesh_id + "/preparation";
    const auto under_way = [](const std::string& state) {
        return state == "queued" || state == "baking";
    };
    std::string state;
    const bool ended = eventually(
        [&] {
            const auto answer = client.Get(path.c_str());
            if (!answer || answer->status != 200) {
                state.clear();
                return true;
            }
            const Json preparation = Json::parse(answer->body);
            state = preparation.value("state", "");
            const std::string without_floor =
                preparation.value("without_floor", Json::object()).value("state", "");
            return !under_way(state) && !under_way(without_floor);
        },
        std::chrono::seconds(120));
    EXPECT_TRUE(ended) << "the preparation of mesh " << mesh_id << " did not end";
    return state;
}

httplib::Result post_json(httplib::Client& client, const std::string& path, const Json& body,
                          const httplib::Headers& headers) {
    return client.Post(path.c_str(), headers, body.dump(), "application/json");
}

Rgba8Image get_frame(httplib::Client& client, const std::string& path_and_query) {
    const auto result = client.Get(path_and_query.c_str());
    if (!result || result->status != 200) {
        ADD_FAILURE() << "GET " << path_and_query << ": " << describe(result);
        return {};
    }
    expect_conforms("GET", "/v1/render", result);
    return decode_image(result);
}

double percentile(std::vector<double> values, double fraction) {
    if (values.empty()) {
        return 0.0;
    }
    std::sort(values.begin(), values.end());
    return values[std::min(values.size() - 1, std::size_t(fraction * double(values.size())))];
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

ShRgb sh_of(const Json& coefficients) {
    const int order = int(std::lround(std::sqrt(double(coefficients.size()))));
    ShRgb sh(order);
    for (std::size_t i = 0; i < coefficients.size(); ++i) {
        sh.coefficients[i] = {coefficients[i][0].get<double>(), coefficients[i][1].get<double>(),
                              coefficients[i][2].get<double>()};
    }
    return sh;
}

glm::dvec3 camera_vector(const std::string& header, const std::string& name) {
    const std::size_t at = header.find(name + "=");
    glm::dvec3 v(0.0);
    if (at == std::string::npos ||
        std::sscanf(header.c_str() + at + name.size() + 1, "%lf,%lf,%lf", &v.x, &v.y, &v.z) != 3) {
        ADD_FAILURE() << "no " << name << " in X-Oer-Camera '" << header << "'";
    }
    return v;
}

}  // namespace oer::itest
