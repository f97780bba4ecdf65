#include "sweep_support.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <fstream>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>

#include <glm/geometric.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/light_location.hpp"

namespace oer::bench {

std::vector<glm::dvec3> pixels_irradiance(const HdrImage& image,
                                          std::span<const std::uint32_t> pixels,
                                          std::span<const glm::dvec3> normals) {
    const equirect::Grid grid(image.width, image.height);
    std::vector<glm::dvec3> directions, weighted;
    directions.reserve(pixels.size());
    weighted.reserve(pixels.size());
    for (const std::uint32_t index : pixels) {
        if (index >= image.pixel_count()) {
            throw Error(ErrorKind::InvalidInput,
                        "pixel index " + std::to_string(index) + " outside a map of " +
                            std::to_string(image.pixel_count()) + " pixels");
        }
        directions.push_back(grid.direction(index));
        weighted.push_back(glm::dvec3(image.rgb(index)) *
                           grid.row_solid_angle[index / std::uint32_t(image.width)]);
    }
    std::vector<glm::dvec3> irradiance;
    irradiance.reserve(normals.size());
    for (const glm::dvec3& n : normals) {
        glm::dvec3 sum(0.0);
        for (std::size_t i = 0; i < directions.size(); ++i) {
            sum += weighted[i] * std::max(0.0, glm::dot(n, directions[i]));
        }
        irradiance.push_back(sum);
    }
    return irradiance;
}

namespace {

void check_factor(const HdrImage& image, int factor) {
    if (factor < 1 || image.width % factor != 0 || image.height % factor != 0) {
        throw Error(ErrorKind::InvalidInput,
                    "downsampling factor " + std::to_string(factor) + " does not divide a " +
                        std::to_string(image.width) + "x" + std::to_string(image.height) + " map");
    }
}

}  // namespace

HdrImage downsample_equirect(const HdrImage& image, int factor) {
    check_factor(image, factor);
    const int width = image.width / factor, height = image.height / factor;
    const equirect::Grid grid(image.width, image.height);
    HdrImage reduced(width, height);
    std::vector<glm::dvec3> row_sums(static_cast<std::size_t>(width));
    for (int y = 0; y < height; ++y) {
        std::fill(row_sums.begin(), row_sums.end(), glm::dvec3(0.0));
        double block_solid_angle = 0.0;
        for (int sy = y * factor; sy < (y + 1) * factor; ++sy) {
            const double solid_angle = grid.row_solid_angle[std::size_t(sy)];
            block_solid_angle += solid_angle * factor;
            for (int sx = 0; sx < image.width; ++sx) {
                const float* p = image.at(sx, sy);
                row_sums[std::size_t(sx / factor)] += glm::dvec3(p[0], p[1], p[2]) * solid_angle;
            }
        }
        for (int x = 0; x < width; ++x) {
            reduced.set(std::size_t(y) * std::size_t(width) + std::size_t(x),
                        glm::vec3(row_sums[std::size_t(x)] / block_solid_angle));
        }
    }
    return reduced;
}

std::vector<std::vector<std::uint32_t>> downsample_light_pixels(
    const HdrImage& image, std::span<const std::vector<std::uint32_t>> light_pixels, int factor) {
    check_factor(image, factor);
    const std::size_t width = std::size_t(image.width / factor);
    const std::size_t blocks = width * std::size_t(image.height / factor);
    const equirect::Grid grid(image.width, image.height);
    // Per block, each light's luminance energy in it: few lights, so a dense table per light.
    std::vector<std::vector<double>> energy(light_pixels.size());
    for (std::size_t k = 0; k < light_pixels.size(); ++k) {
        energy[k].assign(blocks, -1.0);  // -1: no pixel of light k in the block
        for (const std::uint32_t index : light_pixels[k]) {
            if (index >= image.pixel_count()) {
                throw Error(ErrorKind::InvalidInput,
                            "light " + std::to_string(k) + " has pixel index " +
                                std::to_string(index) + " outside the map");
            }
            const std::size_t x = index % std::size_t(image.width);
            const std::size_t y = index / std::size_t(image.width);
            const std::size_t block = (y / std::size_t(factor)) * width + x / std::size_t(factor);
            energy[k][block] = std::max(0.0, energy[k][block]) +
                               luminance(glm::dvec3(image.rgb(index))) * grid.row_solid_angle[y];
        }
    }
    std::vector<std::vector<std::uint32_t>> reduced(light_pixels.size());
    for (std::size_t block = 0; block < blocks; ++block) {
        std::size_t owner = light_pixels.size();
        double most = -1.0;
        for (std::size_t k = 0; k < light_pixels.size(); ++k) {
            if (energy[k][block] > most) {
                most = energy[k][block];
                owner = k;
            }
        }
        if (most >= 0.0) {
            reduced[owner].push_back(std::uint32_t(block));
        }
    }
    return reduced;
}

DiscMap make_disc_map(int width, int height, glm::vec3 sky, std::span<const Disc> discs) {
    DiscMap map{HdrImage(width, height), std::vector<std::vector<std::uint32_t>>(discs.size())};
    const equirect::Grid grid(width, height);
    std::vector<glm::dvec3> centres;
    std::vector<double> cos_radii;
    for (const Disc& disc : discs) {
        centres.push_back(disc_centre(disc));
        cos_radii.push_back(std::cos(disc.radius_degrees * std::numbers::pi / 180.0));
    }
    for (std::size_t i = 0; i < map.image.pixel_count(); ++i) {
        const glm::dvec3 d = grid.direction(i);
        std::size_t painter = discs.size();
        for (std::size_t k = 0; k < discs.size(); ++k) {
            if (glm::dot(d, centres[k]) >= cos_radii[k]) {
                painter = k;
            }
        }
        map.image.set(i, painter < discs.size() ? discs[painter].radiance : sky);
        if (painter < discs.size()) {
            map.disc_pixels[painter].push_back(std::uint32_t(i));
        }
    }
    return map;
}

IrradianceError irradiance_error(std::span<const glm::dvec3> approx,
                                 std::span<const glm::dvec3> truth) {
    if (approx.size() != truth.size() || truth.empty()) {
        throw Error(ErrorKind::InvalidInput, "irradiance error of " +
                                                 std::to_string(approx.size()) +
                                                 " values against " + std::to_string(truth.size()));
    }
    IrradianceError error;
    double squared_difference = 0.0, squared_truth = 0.0;
    glm::dvec3 smallest(std::numeric_limits<double>::infinity());
    glm::dvec3 largest_truth(0.0);
    for (std::size_t i = 0; i < truth.size(); ++i) {
        const glm::dvec3 difference = approx[i] - truth[i];
        squared_difference += glm::dot(difference, difference);
        squared_truth += glm::dot(truth[i], truth[i]);
        const double truth_norm = glm::length(truth[i]);
        const double difference_norm = glm::length(difference);
        const double relative = truth_norm > 0.0        ? difference_norm / truth_norm
                                : difference_norm > 0.0 ? std::numeric_limits<double>::infinity()
                                                        : 0.0;
        error.max_relative = std::max(error.max_relative, relative);
        smallest = glm::min(smallest, approx[i]);
        largest_truth = glm::max(largest_truth, truth[i]);
    }
    error.relative_rms = squared_truth > 0.0        ? std::sqrt(squared_difference / squared_truth)
                         : squared_difference > 0.0 ? std::numeric_limits<double>::infinity()
                                                    : 0.0;
    for (int c = 0; c < 3; ++c) {
        if (largest_truth[c] > 0.0) {
            error.most_negative = std::min(error.most_negative, smallest[c] / largest_truth[c]);
        }
    }
    return error;
}

std::vector<std::size_t> pareto_front(std::span<const double> time, std::span<const double> error) {
    if (time.size() != error.size()) {
        throw Error(ErrorKind::InvalidInput, "Pareto front of " + std::to_string(time.size()) +
                                                 " times and " + std::to_string(error.size()) +
                                                 " errors");
    }
    std::vector<std::size_t> order(time.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return time[a] != time[b] ? time[a] < time[b] : error[a] < error[b];
    });
    // Sorted by time (then error), a point is on the front when it is strictly more accurate
    // than every faster one.
    std::vector<std::size_t> front;
    double best_error = std::numeric_limits<double>::infinity();
    for (const std::size_t i : order) {
        if (error[i] < best_error) {
            front.push_back(i);
            best_error = error[i];
        }
    }
    return front;
}

SweepArguments parse_sweep_arguments(int argc, const char* const* argv) {
    SweepArguments arguments;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (flag == "--quick") {
            arguments.quick = true;
        } else if (flag == "--json" || flag == "--csv") {
            if (i + 1 >= argc) {
                throw Error(ErrorKind::InvalidInput, flag + " needs a file name");
            }
            (flag == "--json" ? arguments.json_path : arguments.csv_path) = argv[++i];
        } else {
            throw Error(ErrorKind::InvalidInput,
                        "unknown argument '" + flag + "' (takes --quick, --json FILE, --csv FILE)");
        }
    }
    return arguments;
}

void write_text_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out) {
        throw Error(ErrorKind::Io, "cannot write " + path);
    }
}

std::vector<std::filesystem::path> blender_worlds() {
    std::vector<std::filesystem::path> paths;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(kBlenderWorldDirectory, error)) {
        if (entry.path().extension() == ".exr") {
            paths.push_back(entry.path());
        }
    }
    if (paths.empty()) {
        throw Error(ErrorKind::Io, std::string("no worlds in ") + kBlenderWorldDirectory +
                                       " (install blender-data)");
    }
    std::sort(paths.begin(), paths.end());
    return paths;
}

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) {
        return text;
    }
    std::string quoted = "\"";
    for (const char c : text) {
        quoted += c;
        if (c == '"') {
            quoted += '"';
        }
    }
    return quoted + "\"";
}

std::vector<std::string> split_names(const std::string& text) {
    std::vector<std::string> names;
    for (std::size_t start = 0; start <= text.size();) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        names.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    return names;
}

std::string flag_value(int argc, const char* const* argv, int& i) {
    if (i + 1 >= argc) {
        throw Error(ErrorKind::InvalidInput, std::string(argv[i]) + " needs a value");
    }
    return argv[++i];
}

int reference_samples(const std::string& flag, const std::string& text) {
    std::size_t used = 0;
    int number = 0;
    try {
        number = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || number < 2 || number % 2 != 0) {
        throw Error(ErrorKind::InvalidInput,
                    flag + " takes an even number of at least 2, not '" + text + "'");
    }
    return number;
}

}  // namespace oer::bench
