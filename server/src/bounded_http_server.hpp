#pragma once
// cpp-httplib's server with a connection loop that bounds what one client can make it hold.
// cpp-httplib 0.11.4 reads a request line or header line of any length into memory, and a
// chunked body without bound (payload_max_length applies to Content-Length only), and it
// keeps reading after a route refused a body unread, taking the rest of that body for the next
// request. Here each request is read through a stream that fails (ending the connection) once
// the request is longer than its budget, a line is longer than kMaxLineBytes, or reading it
// takes longer than the read deadline; and a connection whose request body was refused unread
// is closed after the answer (RequestState::close_connection).
//
// Slow clients (slowloris: headers a byte at a time; slow bodies) hold a thread each, as every
// connection does here. Two bounds keep them from starving everyone else: the request line and
// headers must arrive within a short deadline, and one client address holds at most a few of
// the many threads (its further connections are answered 429 and closed before anything is
// read), so that other clients always find free threads. The deployment's proxy adds what one
// process cannot: buffering whole requests before they reach the service (docker/README.md).
#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>
#include <string>

#include <httplib.h>

namespace oer::server {

struct ConnectionLimits {
    // Request line, headers and body together (the largest body any route takes, plus headers).
    std::size_t request_bytes = 0;
    // From the first byte of a request to the last one read: a slow sender holds a thread at
    // most this long.
    std::chrono::seconds read_deadline{30};
    // From the first byte of a request to the end of its headers.
    std::chrono::seconds header_deadline{5};
    // Connections one client address may hold at once; 0: no limit.
    std::size_t max_connections_per_client = 0;
};

// Longer than any request line cpp-httplib accepts (CPPHTTPLIB_REQUEST_URI_MAX_LENGTH, 8 KiB).
inline constexpr std::size_t kMaxLineBytes = 16 << 10;

// The details of the 414 and 431 answers, with the limits they are over: the request line's is
// cpp-httplib's (CPPHTTPLIB_REQUEST_URI_MAX_LENGTH), a header line's kMaxLineBytes.
std::string request_line_too_long();
std::string header_line_too_long();

// The open connections of each client address.
class ConnectionsPerClient {
  public:
    explicit ConnectionsPerClient(std::size_t limit) : limit_(limit) {}
    // Counts a connection of address in; false (counting nothing) when it already holds the
    // limit.
    bool enter(const std::string& address);
    void leave(const std::string& address);

  private:
    const std::size_t limit_;
    std::mutex mutex_;
    std::map<std::string, std::size_t> open_;
};

class BoundedHttpServer : public httplib::Server {
  public:
    // on_refused: called with the address of each connection refused over the per-client
    // limit (for a metric).
    explicit BoundedHttpServer(const ConnectionLimits& limits,
                               std::function<void(const std::string&)> on_refused = {})
        : limits_(limits),
          connections_(limits.max_connections_per_client),
          on_refused_(std::move(on_refused)) {}

  private:
    bool process_and_close_socket(socket_t sock) override;
    bool serve_connection(socket_t sock);
    // Whether a request starts on sock within the keep-alive timeout (false when the server
    // stops meanwhile).
    bool wait_for_request(socket_t sock, bool buffered) const;

    const ConnectionLimits limits_;
    ConnectionsPerClient connections_;
    const std::function<void(const std::string&)> on_refused_;
};

}  // namespace oer::server
