#include "bench_support.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"

namespace oer::bench {

using std::numbers::pi;

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string content{std::istreambuf_iterator<char>(in), {}};
    if (!in.good() && !in.eof()) {
        throw Error(ErrorKind::Io, "cannot read " + path);
    }
    if (!in.is_open()) {
        throw Error(ErrorKind::Io, "cannot open " + path);
    }
    return content;
}

double percentile(std::vector<double> values, double p) {
    if (values.empty()) {
        return 0.0;
    }
    std::sort(values.begin(), values.end());
    const std::size_t index =
        std::min(values.size() - 1, std::size_t(p * double(values.size() - 1) + 0.5));
    return values[index];
}

std::vector<std::pair<std::string, double>> parse_server_timing(std::string_view header) {
    std::vector<std::pair<std::string, double>> entries;
    // Appended piece by piece: GCC 12's -Wrestrict misfires on "literal" + std::string chains.
    const auto fail = [header](std::string_view name, std::string_view problem) {
        std::string message = "Server-Timing \"";
        message.append(header).append("\": ");
        if (!name.empty()) {
            message.append("'").append(name).append("' ");
        }
        message.append(problem);
        throw Error(ErrorKind::InvalidInput, message);
    };
    const auto trimmed = [](std::string_view text) {
        const std::size_t first = text.find_first_not_of(' ');
        const std::size_t last = text.find_last_not_of(' ');
        return first == std::string_view::npos ? std::string_view()
                                               : text.substr(first, last - first + 1);
    };
    if (trimmed(header).empty()) {
        return entries;
    }
    std::size_t start = 0;
    while (start <= header.size()) {
        const std::size_t comma = std::min(header.find(',', start), header.size());
        const std::string_view entry = trimmed(header.substr(start, comma - start));
        const std::size_t semicolon = entry.find(';');
        const std::string_view name = trimmed(entry.substr(0, semicolon));
        if (name.empty()) {
            fail({}, "an entry without a name");
        }
        constexpr std::string_view kDuration = "dur=";
        const std::size_t duration = entry.find(kDuration, semicolon);
        if (semicolon == std::string_view::npos || duration == std::string_view::npos) {
            fail(name, "has no dur");
        }
        const std::string_view number = entry.substr(duration + kDuration.size());
        double ms = 0.0;
        const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), ms);
        if (error != std::errc() || end != number.data() + number.size()) {
            fail(name, std::string("has dur '").append(number).append("', not a number"));
        }
        entries.emplace_back(name, ms);
        start = comma + 1;
    }
    return entries;
}

glm::dvec3 disc_centre(const Disc& disc) {
    const double phi = disc.azimuth_degrees * pi / 180.0;
    const double elevation = disc.elevation_degrees * pi / 180.0;
    return {std::cos(elevation) * std::cos(phi), std::sin(elevation),
            std::cos(elevation) * std::sin(phi)};
}

HdrImage make_synthetic_map(int width, int height, int lights) {
    const equirect::Grid grid(width, height);
    std::vector<glm::dvec3> centres;
    std::vector<double> cos_radii;
    for (int k = 0; k < lights; ++k) {
        centres.push_back(disc_centre(kDiscs[k]));
        cos_radii.push_back(std::cos(kDiscs[k].radius_degrees * pi / 180.0));
    }
    HdrImage image(width, height);
    const glm::vec3 zenith(0.08f, 0.12f, 0.25f), horizon(0.30f, 0.32f, 0.35f),
        ground(0.06f, 0.05f, 0.04f);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 d = grid.direction(x, y);
            glm::vec3 value = d.y >= 0.0 ? horizon + (zenith - horizon) * float(std::sqrt(d.y))
                                         : ground * float(1.0 + 0.5 * d.y);
            value *= float(1.0 + 0.5 * d.x);
            for (int k = 0; k < lights; ++k) {
                if (glm::dot(d, centres[k]) >= cos_radii[k]) {
                    value = kDiscs[k].radiance;
                }
            }
            image.set(std::size_t(y) * std::size_t(width) + std::size_t(x), value);
        }
    }
    return image;
}

}  // namespace oer::bench
