#include "oer/server/log_line.hpp"

#include <unistd.h>

#include <string>

namespace oer::server {

void log_line(std::string_view message) {
    std::string line = "oer-server: ";
    line += message;
    line += '\n';
    // A log line that cannot be written has nowhere else to go: the result is deliberately
    // ignored rather than turned into an error of the operation being logged.
    [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, line.data(), line.size());
}

}  // namespace oer::server
