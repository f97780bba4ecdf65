#include "request_state.hpp"

#include <poll.h>

namespace oer::server {

RequestState& current_request() {
    thread_local RequestState state;
    return state;
}

bool client_has_gone() {
    const int sock = current_request().socket;
    if (sock < 0) {
        return false;
    }
    // POLLRDHUP (Linux): the peer closed or shut down its side, even with bytes still unread
    // before the end (a pipelined request, which such a client no longer waits for either).
    pollfd entry{sock, POLLRDHUP, 0};
    return ::poll(&entry, 1, 0) > 0 && (entry.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

}  // namespace oer::server
