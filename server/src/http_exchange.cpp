#include "http_exchange.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <ctime>
#include <string_view>

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/core/one_line.hpp"

namespace oer::server {

void send_json(httplib::Response& response, int status, const nlohmann::json& body) {
    response.status = status;
    response.set_content(body.dump(), "application/json");
}

std::string upload_file_name(const std::map<std::string, std::string>& query,
                             const std::string& extension) {
    const auto given = query.find("filename");
    if (given == query.end()) {
        return "the uploaded ." + extension + " file";
    }
    const std::string& name = given->second;
    const bool control = std::any_of(name.begin(), name.end(), [](char c) {
        return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
    });
    if (name.empty() || name.size() > 255 || control || detail::valid_utf8(name) != name) {
        throw api::InvalidParameter("filename",
                                    "the file's name as the user knows it: 1 to 255 bytes of "
                                    "UTF-8 without control characters");
    }
    return name;
}

void send_upload(httplib::Response& response, nlohmann::json asset, bool cached,
                 const std::string& location) {
    asset["cached"] = cached;
    if (!cached) {
        response.set_header("Location", location);
    }
    send_json(response, cached ? 200 : 201, asset);
}

void send_problem(httplib::Response& response, const ErrorAnswer& answer) {
    response.status = answer.problem.status();
    for (const auto& [name, value] : answer.headers) {
        response.set_header(name, value);
    }
    response.set_content(problem_to_json(answer.problem).dump(), std::string(kProblemContentType));
}

std::string media_type(const httplib::Request& request) {
    std::string type = request.get_header_value("Content-Type");
    type = type.substr(0, type.find(';'));
    while (!type.empty() && std::isspace(static_cast<unsigned char>(type.back()))) {
        type.pop_back();
    }
    std::transform(type.begin(), type.end(), type.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return type;
}

std::map<std::string, std::string> single_query(const httplib::Request& request,
                                                const std::vector<std::string>& allowed) {
    std::map<std::string, std::string> values;
    for (const auto& [name, value] : request.params) {
        if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
            throw api::InvalidParameter(name, "unknown query parameter");
        }
        if (!values.emplace(name, value).second) {
            throw api::InvalidParameter(name, "given more than once");
        }
    }
    return values;
}

ListingQuery listing_query(const httplib::Request& request, const ListingForm& form) {
    const auto query = single_query(request, {"limit", "after"});
    ListingQuery listing;
    if (const auto limit = query.find("limit"); limit != query.end()) {
        listing.limit = std::size_t(
            api::parse_integer("limit", limit->second, 1, static_cast<long long>(form.max_limit)));
    }
    if (const auto after = query.find("after"); after != query.end()) {
        if (!form.is_id(after->second)) {
            throw api::InvalidParameter("after", "must be an id of the listing (" +
                                                     std::string(form.id_form) + "), got '" +
                                                     api::excerpt(after->second) + "'");
        }
        listing.after = after->second;
    }
    return listing;
}

void send_listing(httplib::Response& response, const std::string& path, const std::string& member,
                  nlohmann::json entries, const std::optional<std::string>& next_after,
                  std::size_t limit) {
    nlohmann::json body = {{member, std::move(entries)}};
    if (next_after) {
        body["next"] = path + "?limit=" + std::to_string(limit) + "&after=" + *next_after;
    }
    send_json(response, 200, body);
}

std::string rfc3339(std::chrono::system_clock::time_point time) {
    const std::time_t seconds = std::chrono::system_clock::to_time_t(time);
    std::tm utc{};
    gmtime_r(&seconds, &utc);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
    return text;
}

void require_api_key(const httplib::Request& request, const std::string& key) {
    const std::string given = request.get_header_value("Authorization");
    // RFC 9110 section 11.4: credentials = auth-scheme [ 1*SP token68 ], the scheme
    // case-insensitive (section 11.1), so "bearer KEY" is "Bearer KEY".
    const std::size_t space = std::min(given.find(' '), given.size());
    std::string scheme = given.substr(0, space);
    std::transform(scheme.begin(), scheme.end(), scheme.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    const std::size_t token = std::min(given.find_first_not_of(' ', space), given.size());
    const std::string_view credentials = std::string_view(given).substr(token);
    // Constant time over the key's length: the time does not tell how much of a guess was right.
    unsigned char difference = scheme == "bearer" && credentials.size() == key.size() ? 0 : 1;
    for (std::size_t i = 0; i < key.size(); ++i) {
        difference |= static_cast<unsigned char>(
            key[i] ^ (i < credentials.size() ? credentials[i] : static_cast<char>(~key[i])));
    }
    if (difference != 0) {
        throw HttpError(problem(ProblemKind::Unauthorized,
                                given.empty() ? "this route needs Authorization: Bearer <api key>"
                                              : "the API key is wrong"),
                        {{"WWW-Authenticate", "Bearer"}});
    }
}

bool etag_matches(const httplib::Request& request, const std::string& etag) {
    const std::string header = request.get_header_value("If-None-Match");
    std::size_t start = 0;
    while (start < header.size()) {
        std::size_t end = header.find(',', start);
        if (end == std::string::npos) {
            end = header.size();
        }
        std::string tag = header.substr(start, end - start);
        tag.erase(0, tag.find_first_not_of(" \t"));
        tag.erase(tag.find_last_not_of(" \t") + 1);
        if (tag.starts_with("W/")) {
            tag.erase(0, 2);  // weak comparison, as RFC 9110 asks of If-None-Match
        }
        if (tag == etag || tag == "*") {
            return true;
        }
        start = end + 1;
    }
    return false;
}

void require_json_body(const httplib::Request& request, const std::string& what) {
    if (const std::string type = media_type(request); type != "application/json") {
        throw HttpError(problem(ProblemKind::UnsupportedMediaType,
                                what + " is application/json, not '" + api::excerpt(type) + "'"));
    }
}

std::string camera_header(const Camera& camera) {
    const auto vector = [](const glm::vec3& v) {
        char text[96];
        std::snprintf(text, sizeof text, "%.9g,%.9g,%.9g", double(v.x), double(v.y), double(v.z));
        return std::string(text);
    };
    char fov_y[32];
    std::snprintf(fov_y, sizeof fov_y, "%.9g", double(camera.fov_y));
    return "eye=" + vector(camera.eye) + "; target=" + vector(camera.target) +
           "; up=" + vector(camera.up) + "; fov_y=" + fov_y;
}

}  // namespace oer::server
