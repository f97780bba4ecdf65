#pragma once
// The lights of a rig as text: weights for a render ("1,0.5,0", the GET form and the CLI's
// --lights; docs/design.md section 2, dimmable lights), and on/off switches ("1,0,1") for the
// environment's irradiance (GET /v1/environments/{id}/irradiance, `oer irradiance-map`).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace oer::api {

// "1,0.5,0" -> {1, 0.5, 0}, before the environment (and so its light count) is known. Throws
// InvalidParameter ("lights", the entry's index in the message) when an entry is not a number in
// [0, kMaxLightWeight] or there are more than max_count entries (the text is read no further).
std::vector<double> parse_light_list(const std::string& text, std::size_t max_count);

// Visibility per light (1 on, 0 off); no text means every light on. Throws InvalidParameter
// ("lights") when an entry is not 0 or 1 or the count differs from light_count.
std::vector<double> parse_light_switches(const std::optional<std::string>& text,
                                         std::size_t light_count);

}  // namespace oer::api
