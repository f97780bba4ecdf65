#include "byte_ranges.hpp"

#include <algorithm>
#include <optional>
#include <string>
#include <utility>

#include "http_errors.hpp"
#include "http_exchange.hpp"

namespace oer::server {

namespace {

// A range as [begin, end) over a body of `length` bytes; nullopt when it is unsatisfiable (RFC
// 9110 section 14.1.1: a first position at or past the end, or a suffix of zero bytes).
std::optional<std::pair<std::size_t, std::size_t>> resolve(const httplib::Range& range,
                                                           std::size_t length) {
    const auto [first, last] = range;
    if (first < 0) {  // "-N": the last N bytes
        if (last <= 0 || length == 0) {
            return std::nullopt;
        }
        return std::pair{length - std::min(std::size_t(last), length), length};
    }
    if (std::size_t(first) >= length) {
        return std::nullopt;
    }
    const std::size_t end =
        last < 0 ? length : std::min(std::size_t(last) + 1, length);  // "N-" or "N-M"
    return std::pair{std::size_t(first), end};
}

// If-Range (RFC 9110 section 13.1.5): the range applies only when the validator is the
// answer's strong ETag; a date, a weak tag or another tag asks for the whole representation.
bool if_range_holds(const httplib::Request& request, const httplib::Response& response) {
    if (!request.has_header("If-Range")) {
        return true;
    }
    const std::string validator = request.get_header_value("If-Range");
    const std::string etag = response.get_header_value("ETag");
    return !etag.empty() && etag.front() == '"' && validator == etag;
}

}  // namespace

httplib::Ranges take_byte_ranges(const httplib::Request& request) {
    // cpp-httplib hands handlers a const Request, yet reads its ranges after they return: the
    // object is the library's own, not const, and clearing this member is the only way to keep
    // the library from applying them.
    httplib::Ranges& ranges = const_cast<httplib::Request&>(request).ranges;
    httplib::Ranges taken = std::move(ranges);
    ranges.clear();
    return taken;
}

void answer_byte_ranges(const httplib::Ranges& ranges, const httplib::Request& request,
                        httplib::Response& response) {
    if (response.status != 200 && response.status != -1) {
        return;
    }
    response.status = 200;
    response.set_header("Accept-Ranges", "bytes");
    if (ranges.size() != 1 || !if_range_holds(request, response)) {
        return;
    }
    const std::size_t length = response.body.size();
    const auto range = resolve(ranges.front(), length);
    if (!range) {
        // The answer is no longer the representation: none of its validators or caching.
        for (const char* name : {"ETag", "Cache-Control", "Last-Modified"}) {
            response.headers.erase(name);
        }
        send_problem(response, {problem(ProblemKind::RangeNotSatisfiable,
                                        "the range asked for starts past the end of the " +
                                            std::to_string(length) + " bytes of this answer"),
                                {{"Content-Range", "bytes */" + std::to_string(length)}},
                                false,
                                ""});
        return;
    }
    const auto [begin, end] = *range;
    response.status = 206;
    response.set_header("Content-Range", "bytes " + std::to_string(begin) + "-" +
                                             std::to_string(end - 1) + "/" +
                                             std::to_string(length));
    response.body = response.body.substr(begin, end - begin);
}

}  // namespace oer::server
