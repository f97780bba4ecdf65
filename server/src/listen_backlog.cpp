#include "listen_backlog.hpp"

#include <netinet/in.h>
#include <sys/socket.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace oer::server {

bool widen_listen_backlog(int port) {
    std::error_code ignored;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", ignored)) {
        int fd = -1;
        try {
            fd = std::stoi(entry.path().filename().string());
        } catch (const std::exception&) {
            continue;
        }
        int listening = 0;
        socklen_t length = sizeof listening;
        if (getsockopt(fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &length) != 0 || !listening) {
            continue;
        }
        sockaddr_storage address{};
        socklen_t address_length = sizeof address;
        if (getsockname(fd, reinterpret_cast<sockaddr*>(&address), &address_length) != 0) {
            continue;
        }
        int bound = -1;
        if (address.ss_family == AF_INET) {
            bound = ntohs(reinterpret_cast<const sockaddr_in&>(address).sin_port);
        } else if (address.ss_family == AF_INET6) {
            bound = ntohs(reinterpret_cast<const sockaddr_in6&>(address).sin6_port);
        }
        if (bound == port) {
            return listen(fd, SOMAXCONN) == 0;
        }
    }
    return false;
}

}  // namespace oer::server
