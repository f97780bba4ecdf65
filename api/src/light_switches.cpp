#include "oer/api/light_switches.hpp"

#include "oer/api/invalid_parameter.hpp"

namespace oer::api {

std::vector<double> parse_light_switches(const std::optional<std::string>& text,
                                         std::size_t light_count) {
    if (!text) {
        return std::vector<double>(light_count, 1.0);
    }
    std::vector<double> visibility;
    std::size_t start = 0;
    while (start <= text->size()) {
        const std::size_t end = std::min(text->find(',', start), text->size());
        const std::string entry = text->substr(start, end - start);
        if (entry != "0" && entry != "1") {
            throw InvalidParameter("lights", "each entry must be 0 or 1, got '" + entry + "'");
        }
        visibility.push_back(entry == "1" ? 1.0 : 0.0);
        if (visibility.size() > light_count) {
            break;
        }
        start = end + 1;
    }
    if (visibility.size() != light_count) {
        throw InvalidParameter("lights", "the environment has " + std::to_string(light_count) +
                                             " light(s), got '" + *text + "'");
    }
    return visibility;
}

}  // namespace oer::api
