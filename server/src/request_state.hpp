#pragma once
// What the HTTP layer knows about the request being answered on this thread: cpp-httplib
// answers each connection on one thread, request after request, so thread-local state is the
// request's own: BoundedHttpServer resets it before each request.
#include <chrono>
#include <string>

namespace oer::server {

struct RequestState {
    std::chrono::steady_clock::time_point start{};  // the epoch: no pre-routing (unparsable)
    std::string route = "unmatched";                // the matched route's pattern
    // The body was refused unread (or read only in part): what is left of it on the
    // connection must not be taken for the next request, so the connection closes.
    bool close_connection = false;
};

RequestState& current_request();

}  // namespace oer::server
