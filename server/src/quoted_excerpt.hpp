#pragma once
// Untrusted text (a rejected flag value, an asset id from a URL) shown in a message: in double
// quotes, control and non-UTF-8 bytes escaped, and cut short, so a message stays one readable
// line whatever the text holds.
#include <string>
#include <string_view>

namespace oer::server {

std::string quoted_excerpt(std::string_view text);

}  // namespace oer::server
