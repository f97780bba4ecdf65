#pragma once
// cpp-httplib's server with a connection loop that bounds what one client can make it hold.
// cpp-httplib 0.11.4 reads a request line or header line of any length into memory, and a
// chunked body without bound (payload_max_length applies to Content-Length only), and it
// keeps reading after a route refused a body unread, taking the rest of that body for the next
// request. Here each request is read through a stream that fails (ending the connection) once
// the request is longer than its budget, a line is longer than kMaxLineBytes, or reading it
// takes longer than the read deadline; and a connection whose request body was refused unread
// is closed after the answer (RequestState::close_connection).
#include <chrono>
#include <cstddef>

#include <httplib.h>

namespace oer::server {

struct ConnectionLimits {
    // Request line, headers and body together (the largest body any route takes, plus headers).
    std::size_t request_bytes = 0;
    // From the first byte of a request to the last one read: a slow sender holds a thread at
    // most this long.
    std::chrono::seconds read_deadline{30};
};

// Longer than any request line cpp-httplib accepts (CPPHTTPLIB_REQUEST_URI_MAX_LENGTH, 8 KiB).
inline constexpr std::size_t kMaxLineBytes = 16 << 10;

class BoundedHttpServer : public httplib::Server {
  public:
    explicit BoundedHttpServer(const ConnectionLimits& limits) : limits_(limits) {}

  private:
    bool process_and_close_socket(socket_t sock) override;
    // Whether a request starts on sock within the keep-alive timeout (false when the server
    // stops meanwhile).
    bool wait_for_request(socket_t sock, bool buffered) const;

    const ConnectionLimits limits_;
};

}  // namespace oer::server
