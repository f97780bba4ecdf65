#include "bounded_http_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "http_errors.hpp"
#include "request_state.hpp"

namespace oer::server {

namespace {

using Clock = std::chrono::steady_clock;

// Waits until sock is ready for events, at most timeout; false on timeout or error.
bool wait_ready(socket_t sock, short events, std::chrono::milliseconds timeout) {
    pollfd entry{sock, events, 0};
    int ready = 0;
    do {
        ready = ::poll(&entry, 1, int(timeout.count()));
    } while (ready < 0 && errno == EINTR);
    return ready > 0;
}

void address_of(socket_t sock, bool peer, std::string& ip, int& port) {
    sockaddr_storage address{};
    socklen_t length = sizeof address;
    const int result = peer ? ::getpeername(sock, reinterpret_cast<sockaddr*>(&address), &length)
                            : ::getsockname(sock, reinterpret_cast<sockaddr*>(&address), &length);
    if (result != 0) {
        return;
    }
    std::array<char, INET6_ADDRSTRLEN> text{};
    if (address.ss_family == AF_INET) {
        const auto* v4 = reinterpret_cast<const sockaddr_in*>(&address);
        ::inet_ntop(AF_INET, &v4->sin_addr, text.data(), text.size());
        port = ntohs(v4->sin_port);
    } else if (address.ss_family == AF_INET6) {
        const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&address);
        ::inet_ntop(AF_INET6, &v6->sin6_addr, text.data(), text.size());
        port = ntohs(v6->sin6_port);
    }
    ip = text.data();
}

// The bytes of one connection, read ahead in blocks; outlives the streams of its requests so
// that a pipelined request's bytes read ahead are not lost.
class Connection {
  public:
    explicit Connection(socket_t sock) : sock_(sock) {}
    socket_t socket() const { return sock_; }
    bool buffered() const { return begin_ < end_; }

    // As recv: bytes (> 0), 0 at the end of the stream, -1 on error or timeout.
    ssize_t read(char* out, std::size_t size, std::chrono::milliseconds timeout) {
        if (!buffered()) {
            if (!wait_ready(sock_, POLLIN, timeout)) {
                return -1;
            }
            ssize_t got = 0;
            do {
                got = ::recv(sock_, buffer_.data(), buffer_.size(), 0);
            } while (got < 0 && errno == EINTR);
            if (got <= 0) {
                return got;
            }
            begin_ = 0;
            end_ = std::size_t(got);
        }
        const std::size_t n = std::min(size, end_ - begin_);
        std::memcpy(out, buffer_.data() + begin_, n);
        begin_ += n;
        return ssize_t(n);
    }

  private:
    socket_t sock_;
    std::array<char, 16 << 10> buffer_{};
    std::size_t begin_ = 0;
    std::size_t end_ = 0;
};

// One request's view of its connection, failing reads past the request's limits.
class BoundedStream : public httplib::Stream {
  public:
    BoundedStream(Connection& connection, const ConnectionLimits& limits,
                  std::chrono::milliseconds read_timeout, std::chrono::milliseconds write_timeout)
        : connection_(connection),
          limits_(limits),
          read_timeout_(read_timeout),
          write_timeout_(write_timeout) {}

    bool is_readable() const override {
        return connection_.buffered() || wait_ready(connection_.socket(), POLLIN, read_timeout_);
    }
    bool is_writable() const override {
        return wait_ready(connection_.socket(), POLLOUT, write_timeout_);
    }

    ssize_t read(char* out, std::size_t size) override {
        const auto now = Clock::now();
        if (read_bytes_ == 0) {
            deadline_ = now + limits_.read_deadline;
            header_deadline_ = std::min(deadline_, now + limits_.header_deadline);
        }
        const Clock::time_point deadline = headers_read_ ? deadline_ : header_deadline_;
        if (now > deadline || read_bytes_ >= limits_.request_bytes) {
            return -1;
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
        const ssize_t got =
            connection_.read(out, std::min(size, limits_.request_bytes - read_bytes_),
                             std::min(read_timeout_, left + std::chrono::milliseconds(1)));
        if (got <= 0) {
            return got;
        }
        read_bytes_ += std::size_t(got);
        // cpp-httplib reads request, header and chunk-size lines a byte at a time: a line is
        // a run of one-byte reads, bounded here as cpp-httplib does not bound it.
        if (size == 1) {
            if (*out == '\n') {
                // An empty line ("\r\n", or "\n" as RFC 9112 section 2.2 lets a server
                // accept) ends the headers.
                headers_read_ = headers_read_ || line_bytes_ <= 1;
                line_bytes_ = 0;
                ++lines_read_;
            } else if (++line_bytes_ > kMaxLineBytes) {
                // Answered 414 or 431 (a chunk-size line of the body just ends the connection).
                if (!headers_read_) {
                    current_request().oversized_line =
                        lines_read_ == 0 ? OversizedLine::RequestLine : OversizedLine::HeaderLine;
                }
                return -1;
            }
        } else {
            line_bytes_ = 0;
        }
        return got;
    }

    ssize_t write(const char* data, std::size_t size) override {
        if (!is_writable()) {
            return -1;
        }
        ssize_t sent = 0;
        do {
            sent = ::send(connection_.socket(), data, size, MSG_NOSIGNAL);
        } while (sent < 0 && errno == EINTR);
        return sent;
    }

    void get_remote_ip_and_port(std::string& ip, int& port) const override {
        address_of(connection_.socket(), true, ip, port);
    }
    void get_local_ip_and_port(std::string& ip, int& port) const override {
        address_of(connection_.socket(), false, ip, port);
    }
    socket_t socket() const override { return connection_.socket(); }

  private:
    Connection& connection_;
    const ConnectionLimits& limits_;
    const std::chrono::milliseconds read_timeout_;
    const std::chrono::milliseconds write_timeout_;
    std::size_t read_bytes_ = 0;
    std::size_t line_bytes_ = 0;
    std::size_t lines_read_ = 0;
    bool headers_read_ = false;
    Clock::time_point deadline_{};
    Clock::time_point header_deadline_{};
};

// A problem written straight to the socket, outside cpp-httplib (which has no request to answer
// at this point); the connection closes after it.
void send_closing_problem(socket_t sock, const Problem& answer, const std::string& headers = "") {
    const std::string body = problem_to_json(answer).dump();
    const std::string response =
        "HTTP/1.1 " + std::to_string(answer.status()) + " " +
        std::string(problem_type(answer.kind).title) +
        "\r\nContent-Type: " + std::string(kProblemContentType) + "\r\n" + headers +
        "Connection: close\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
    // One non-blocking attempt: a client that does not read its answer gets none.
    (void)::send(sock, response.data(), response.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

// The answer to a connection over its address's limit, written before reading anything (RFC
// 6585 section 4's 429, with when to come back).
void refuse_connection(socket_t sock, const std::string& address, std::size_t limit) {
    send_closing_problem(sock,
                         problem(ProblemKind::TooManyConnections,
                                 "too many connections from " + address + " (at most " +
                                     std::to_string(limit) + " at once); close one or retry later"),
                         "Retry-After: " + std::to_string(kRetryAfterSeconds) + "\r\n");
}

std::chrono::milliseconds milliseconds(time_t seconds, time_t microseconds) {
    return std::chrono::milliseconds(seconds * 1000 + microseconds / 1000);
}

}  // namespace

std::string request_line_too_long() {
    return "the request line (method, path and query) is longer than the " +
           std::to_string(CPPHTTPLIB_REQUEST_URI_MAX_LENGTH) + " bytes the server reads";
}

std::string header_line_too_long() {
    return "a header line is longer than the " + std::to_string(kMaxLineBytes) +
           " bytes the server reads";
}

bool BoundedHttpServer::wait_for_request(socket_t sock, bool buffered) const {
    if (buffered) {
        return true;
    }
    // In slices, so that stop() does not wait for idle connections to time out.
    constexpr std::chrono::milliseconds kSlice(100);
    const auto end = Clock::now() + std::chrono::seconds(keep_alive_timeout_sec_);
    while (svr_sock_ != INVALID_SOCKET && Clock::now() < end) {
        if (wait_ready(sock, POLLIN, kSlice)) {
            return true;
        }
    }
    return false;
}

bool ConnectionsPerClient::enter(const std::string& address) {
    if (limit_ == 0) {
        return true;
    }
    const std::lock_guard lock(mutex_);
    std::size_t& open = open_[address];
    if (open >= limit_) {
        return false;
    }
    ++open;
    return true;
}

void ConnectionsPerClient::leave(const std::string& address) {
    if (limit_ == 0) {
        return;
    }
    const std::lock_guard lock(mutex_);
    const auto found = open_.find(address);
    if (found != open_.end() && --found->second == 0) {
        open_.erase(found);
    }
}

bool BoundedHttpServer::process_and_close_socket(socket_t sock) {
    std::string address;
    int port = 0;
    address_of(sock, true, address, port);
    bool served = false;
    if (connections_.enter(address)) {
        served = serve_connection(sock);
        connections_.leave(address);
    } else {
        refuse_connection(sock, address, limits_.max_connections_per_client);
        if (on_refused_) {
            on_refused_(address);
        }
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return served;
}

bool BoundedHttpServer::serve_connection(socket_t sock) {
    Connection connection(sock);
    bool served = false;
    for (std::size_t left = keep_alive_max_count_; left > 0; --left) {
        if (!wait_for_request(sock, connection.buffered())) {
            break;
        }
        current_request() = RequestState{};
        current_request().socket = sock;
        BoundedStream stream(connection, limits_,
                             milliseconds(read_timeout_sec_, read_timeout_usec_),
                             milliseconds(write_timeout_sec_, write_timeout_usec_));
        bool closed = false;
        served = process_request(stream, left == 1, closed, [](httplib::Request&) {});
        // cpp-httplib gives up on a request line it could not read without answering.
        if (!served && current_request().oversized_line == OversizedLine::RequestLine) {
            send_closing_problem(sock, problem(ProblemKind::UriTooLong, request_line_too_long()));
        }
        if (!served || closed || current_request().close_connection) {
            break;
        }
    }
    return served;
}

}  // namespace oer::server
