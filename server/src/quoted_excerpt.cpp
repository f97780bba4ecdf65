#include "quoted_excerpt.hpp"

#include <nlohmann/json.hpp>

namespace oer::server {

std::string quoted_excerpt(std::string_view text) {
    constexpr std::size_t kShown = 80;
    const bool cut = text.size() > kShown;
    const std::string json = nlohmann::json(std::string(text.substr(0, kShown)))
                                 .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    return cut ? json + "... (" + std::to_string(text.size()) + " bytes)" : json;
}

}  // namespace oer::server
