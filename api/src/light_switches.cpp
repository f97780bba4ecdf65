#include "oer/api/light_switches.hpp"

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/scene/frame_request.hpp"

namespace oer::api {

namespace {

// The comma-separated entries of text, at most max_count of them.
std::vector<std::string> list_entries(const std::string& text, std::size_t max_count) {
    std::vector<std::string> entries;
    std::size_t start = 0;
    while (start <= text.size()) {
        if (entries.size() == max_count) {
            throw InvalidParameter("lights", "more than " + std::to_string(max_count) +
                                                 " entries in '" + excerpt(text) + "'");
        }
        const std::size_t end = std::min(text.find(',', start), text.size());
        entries.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return entries;
}

}  // namespace

std::vector<double> parse_light_list(const std::string& text, std::size_t max_count) {
    const std::vector<std::string> entries = list_entries(text, max_count);
    std::vector<double> weights;
    for (const std::string& entry : entries) {
        try {
            weights.push_back(parse_number("lights", entry, 0.0, kMaxLightWeight));
        } catch (const InvalidParameter&) {
            throw InvalidParameter(
                "lights", "entry " + std::to_string(weights.size()) + " must be a weight in [0, " +
                              number_text(kMaxLightWeight) + "], got '" + excerpt(entry) + "'");
        }
    }
    return weights;
}

std::vector<double> parse_light_switches(const std::optional<std::string>& text,
                                         std::size_t light_count) {
    if (!text) {
        return std::vector<double>(light_count, 1.0);
    }
    std::vector<double> visibility;
    for (const std::string& entry : list_entries(*text, light_count)) {
        if (entry != "0" && entry != "1") {
            throw InvalidParameter("lights",
                                   "each entry must be 0 or 1, got '" + excerpt(entry) + "'");
        }
        visibility.push_back(entry == "1" ? 1.0 : 0.0);
    }
    if (visibility.size() != light_count) {
        throw InvalidParameter("lights", "the environment has " + std::to_string(light_count) +
                                             " light(s), got '" + excerpt(*text) + "'");
    }
    return visibility;
}

}  // namespace oer::api
