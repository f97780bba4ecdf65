#pragma once
// The service's log: one line per event on stderr, written with a single write() so that lines
// from several threads never interleave.
#include <string_view>

namespace oer::server {

void log_line(std::string_view message);

}  // namespace oer::server
