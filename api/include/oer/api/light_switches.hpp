#pragma once
// The on/off state of a rig's lights as text ("1,0,1", the GET form and the CLI's --lights).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace oer::api {

// "1,0,1" -> {true, false, true}, before the environment (and so its light count) is known.
// Throws InvalidParameter ("lights") when an entry is not 0 or 1 or there are more than
// max_count entries (the text is read no further than that).
std::vector<bool> parse_light_list(const std::string& text, std::size_t max_count);

// Visibility per light (1 on, 0 off); no text means every light on. Throws InvalidParameter
// ("lights") when an entry is not 0 or 1 or the count differs from light_count.
std::vector<double> parse_light_switches(const std::optional<std::string>& text,
                                         std::size_t light_count);

}  // namespace oer::api
