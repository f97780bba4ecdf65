#pragma once
// What the HTTP layer knows about the request being answered on this thread: cpp-httplib
// answers each connection on one thread, request after request, so thread-local state is the
// request's own: BoundedHttpServer resets it before each request.
#include <sys/types.h>

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace oer::server {

// A line of the request longer than the server reads (kMaxLineBytes), by where it was.
enum class OversizedLine { None, RequestLine, HeaderLine };

struct RequestState {
    std::chrono::steady_clock::time_point start{};  // the epoch: no pre-routing (unparsable)
    std::string route = "unmatched";                // the matched route's pattern
    // The body was refused unread (or read only in part): what is left of it on the
    // connection must not be taken for the next request, so the connection closes.
    bool close_connection = false;
    // Set by the connection's stream when it stopped reading a line: answered 414 or 431.
    OversizedLine oversized_line = OversizedLine::None;
    // The request's byte ranges, taken out of cpp-httplib's hands before routing
    // (byte_ranges.hpp): cpp-httplib's parse of its Range header, a pair of positions each.
    std::vector<std::pair<ssize_t, ssize_t>> ranges;
    // The connection's socket, for client_has_gone(); -1 outside BoundedHttpServer.
    int socket = -1;
};

RequestState& current_request();

// Whether the client of the request answered on this thread has closed its connection (or shut
// down its sending side: it sends nothing more, and HTTP clients do that only on leaving), so
// that work done only for it can stop, as nginx's proxy does for a client that goes
// (proxy_ignore_client_abort off). Looks at the socket without waiting or reading; false
// outside BoundedHttpServer.
bool client_has_gone();

}  // namespace oer::server
