#include "oer/api/light_switches.hpp"

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/parameter_text.hpp"

namespace oer::api {

std::vector<bool> parse_light_list(const std::string& text, std::size_t max_count) {
    std::vector<bool> switches;
    std::size_t start = 0;
    while (start <= text.size()) {
        if (switches.size() == max_count) {
            throw InvalidParameter("lights", "more than " + std::to_string(max_count) +
                                                 " entries in '" + excerpt(text) + "'");
        }
        const std::size_t end = std::min(text.find(',', start), text.size());
        const std::string entry = text.substr(start, end - start);
        if (entry != "0" && entry != "1") {
            throw InvalidParameter("lights",
                                   "each entry must be 0 or 1, got '" + excerpt(entry) + "'");
        }
        switches.push_back(entry == "1");
        start = end + 1;
    }
    return switches;
}

std::vector<double> parse_light_switches(const std::optional<std::string>& text,
                                         std::size_t light_count) {
    if (!text) {
        return std::vector<double>(light_count, 1.0);
    }
    const std::vector<bool> switches = parse_light_list(*text, light_count);
    if (switches.size() != light_count) {
        throw InvalidParameter("lights", "the environment has " + std::to_string(light_count) +
                                             " light(s), got '" + excerpt(*text) + "'");
    }
    return {switches.begin(), switches.end()};
}

}  // namespace oer::api
