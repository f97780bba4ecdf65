#include "oer/lighting/light_location.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <sstream>

#include <glm/geometric.hpp>

#include "equirect_blur.hpp"
#include "kmeans.hpp"
#include "large_buffer.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "percentile.hpp"

namespace oer {

double luminance(const glm::dvec3& rgb) {
    return 179.0 * (0.265 * rgb.r + 0.670 * rgb.g + 0.065 * rgb.b);
}

LightProfile light_profile(const ShRgb& light_sh, const glm::dvec3& direction) {
    const double band0 = luminance(light_sh.truncated(1).evaluate(direction));
    if (!(band0 > 0.0) || light_sh.order < 2) {
        return {1.0, 0.0};
    }
    // Legendre moment l: band l at the direction over (2l + 1) times band 0.
    const auto moment = [&](int l) {
        const double band = luminance(light_sh.truncated(l + 1).evaluate(direction)) -
                            luminance(light_sh.truncated(l).evaluate(direction));
        return std::clamp(band / ((2.0 * l + 1.0) * band0), -1.0, 1.0);
    };
    const double mean_cosine = std::max(moment(1), 0.0);
    const LightProfile one_disc{0.0, std::acos(2.0 * mean_cosine - 1.0)};
    const double spread1 = 1.0 - mean_cosine;
    if (light_sh.order < 3 || spread1 <= 1e-12) {
        return spread1 <= 1e-12 ? LightProfile{1.0, 0.0} : one_disc;
    }
    const double ratio = (1.0 - moment(2)) / spread1;
    if (!(ratio >= 1.0 && ratio < 3.0)) {
        return one_disc;
    }
    const double glow_cosine = ratio - 2.0;
    const double core_share = 1.0 - 2.0 * spread1 / (1.0 - glow_cosine);
    if (!(core_share >= 0.0)) {
        return one_disc;
    }
    return {core_share, std::acos(glow_cosine)};
}

namespace {

using std::numbers::pi;

// Bright pixels beyond this many are subsampled by a fixed stride for the k-means itself (every
// second one of the ~21000 of a 2048x1024 map: k-means was a third of the time, and the
// clusters of a regular subsample are the same lights); each bright pixel then joins its
// nearest centre, so the light's membership is decided over all of them.
constexpr std::size_t max_cluster_points = 16384;
// Above this, k-means over tens of thousands of points and one run per light would take
// minutes: a request for it is refused rather than served slowly.
constexpr int max_cluster_count = 256;

// Per-pixel membership while lights are taken: in the halo set, also in the bright set, taken
// by the light being built, or 0 once a light has it.
constexpr std::uint8_t in_halo = 1;
constexpr std::uint8_t in_bright = 2;
constexpr std::uint8_t taken_now = 4;

// Radiance as image_io's repair_radiance leaves it: NaN and negative values read as 0, +Inf as
// the largest finite float.
double sanitised(float value) {
    return value > 0.0f ? double(std::min(value, FLT_MAX)) : 0.0;
}

glm::dvec3 radiance(const HdrImage& image, std::size_t index) {
    const float* p = &image.pixels[index * 3];
    return {sanitised(p[0]), sanitised(p[1]), sanitised(p[2])};
}

void validate(const HdrImage& image, int max_lights, const LightLocationOptions& options) {
    auto fail = [](const std::string& message) {
        throw Error(ErrorKind::InvalidInput, "locate_lights: " + message);
    };
    std::ostringstream message;
    if (image.width <= 0 || image.height <= 0) {
        message << "image is empty (" << image.width << "x" << image.height << ")";
        fail(message.str());
    }
    if (image.pixels.size() != image.pixel_count() * 3) {
        message << "pixel buffer holds " << image.pixels.size() << " floats, a " << image.width
                << "x" << image.height << " RGB image needs " << image.pixel_count() * 3;
        fail(message.str());
    }
    if (image.pixel_count() > std::size_t(std::numeric_limits<std::uint32_t>::max()) + 1) {
        message << "locate_lights: " << image.width << "x" << image.height
                << " image has more pixels than the 32-bit indices of Light::pixels can address";
        throw Error(ErrorKind::LimitExceeded, message.str());
    }
    if (max_lights < 0) {
        message << "max_lights is " << max_lights << ", must be >= 0";
        fail(message.str());
    }
    if (!(options.light_percentile > 0.0 && options.light_percentile < 1.0)) {
        message << "light_percentile is " << options.light_percentile
                << ", must be in (0, 1) exclusive";
        fail(message.str());
    }
    if (!(options.halo_percentile > 0.0 && options.halo_percentile < 1.0)) {
        message << "halo_percentile is " << options.halo_percentile
                << ", must be in (0, 1) exclusive";
        fail(message.str());
    }
    if (options.halo_percentile > options.light_percentile) {
        message << "halo_percentile (" << options.halo_percentile << ") is above light_percentile ("
                << options.light_percentile << "): the halo must include the bright pixels";
        fail(message.str());
    }
    if (options.cluster_count < 1 || options.cluster_count > max_cluster_count) {
        message << "cluster_count is " << options.cluster_count << ", must be in [1, "
                << max_cluster_count << "]";
        fail(message.str());
    }
    if (!std::isfinite(options.blur_radius) || options.blur_radius < 0.0 ||
        options.blur_radius > detail::max_blur_radius) {
        message << "blur_radius is " << options.blur_radius << ", must be in [0, "
                << detail::max_blur_radius << "] pixels";
        fail(message.str());
    }
}

// The space k-means runs in: unit directions (chord distance, angular radius) or the thesis's
// pixel coordinates (Euclidean distance in pixels, no wrap).
class PointSpace {
  public:
    PointSpace(const equirect::Grid& grid, Clustering clustering)
        : grid_(grid), directions_(clustering == Clustering::Directions) {}

    int dimension() const { return directions_ ? 3 : 2; }
    detail::CentreKind centre_kind() const {
        return directions_ ? detail::CentreKind::UnitMean : detail::CentreKind::Mean;
    }

    void append(std::uint32_t pixel, std::vector<double>& out) const {
        const int x = int(pixel % std::uint32_t(grid_.width));
        const int y = int(pixel / std::uint32_t(grid_.width));
        if (directions_) {
            const glm::dvec3 d = grid_.direction(x, y);
            out.insert(out.end(), {d.x, d.y, d.z});
        } else {
            out.insert(out.end(), {x + 0.5, y + 0.5});
        }
    }

    // The centre of a set of pixels and its spread sigma: for directions, the renormalised
    // mean direction and sqrt(mean(angle^2)) about it; for pixels, the mean position and the
    // larger of the standard deviations in x and y. fallback is used when the mean direction
    // vanishes.
    struct Spread {
        glm::dvec3 centre{0.0};  // direction, or (x, y, 0) in pixel units
        double sigma = 0.0;
    };
    Spread spread(const std::vector<std::uint32_t>& pixels, const double* fallback) const {
        Spread s;
        const double n = double(pixels.size());
        const std::uint32_t width = std::uint32_t(grid_.width);
        if (directions_) {
            glm::dvec3 sum{0.0};
            for (std::uint32_t pixel : pixels) {
                sum += grid_.direction(int(pixel % width), int(pixel / width));
            }
            const double length = glm::length(sum);
            s.centre =
                length > 0.0 ? sum / length : glm::dvec3{fallback[0], fallback[1], fallback[2]};
            double accumulated = 0.0;
            for (std::uint32_t pixel : pixels) {
                const glm::dvec3 p = grid_.direction(int(pixel % width), int(pixel / width));
                const double angle =
                    2.0 * std::asin(std::min(1.0, glm::length(p - s.centre) / 2.0));
                accumulated += angle * angle;
            }
            s.sigma = std::sqrt(accumulated / n);
        } else {
            double sx = 0.0, sy = 0.0;
            for (std::uint32_t pixel : pixels) {
                sx += double(pixel % width) + 0.5;
                sy += double(pixel / width) + 0.5;
            }
            s.centre = {sx / n, sy / n, 0.0};
            double vx = 0.0, vy = 0.0;
            for (std::uint32_t pixel : pixels) {
                const double dx = double(pixel % width) + 0.5 - s.centre.x;
                const double dy = double(pixel / width) + 0.5 - s.centre.y;
                vx += dx * dx;
                vy += dy * dy;
            }
            s.sigma = std::sqrt(std::max(vx, vy) / n);
        }
        return s;
    }

    // 3 sigma, but at least one pixel (pi / H for directions), so that a one-pixel light keeps
    // its pixel and its immediate neighbours.
    double radius(double sigma) const {
        return directions_ ? std::min(pi, std::max(3.0 * sigma, pi / grid_.height))
                           : std::max(3.0 * sigma, 1.0);
    }

    // Marks taken_now every candidate still in the halo within radius of centre.
    void mark_within(const std::vector<std::uint32_t>& candidates, std::uint8_t* state,
                     const glm::dvec3& centre, double radius) const {
        const std::uint32_t width = std::uint32_t(grid_.width);
        if (directions_) {
            const double min_cos = std::cos(radius);
            for (std::uint32_t pixel : candidates) {
                if ((state[pixel] & in_halo) != 0 &&
                    glm::dot(grid_.direction(int(pixel % width), int(pixel / width)), centre) >=
                        min_cos) {
                    state[pixel] = taken_now;
                }
            }
        } else {
            const double r2 = radius * radius;
            for (std::uint32_t pixel : candidates) {
                const double dx = double(pixel % width) + 0.5 - centre.x;
                const double dy = double(pixel / width) + 0.5 - centre.y;
                if ((state[pixel] & in_halo) != 0 && dx * dx + dy * dy <= r2) {
                    state[pixel] = taken_now;
                }
            }
        }
    }

    glm::dvec3 centre_direction(const glm::dvec3& centre) const {
        return directions_ ? centre
                           : equirect::direction_at(centre.x, centre.y, grid_.width, grid_.height);
    }

  private:
    const equirect::Grid& grid_;
    bool directions_;
};

// Flood fill (LightLocationOptions::grow_connected): appends to pixels every bright pixel not
// yet taken that is connected to them through bright pixels, and marks it taken_now.
// Neighbours: the 8 around a pixel, x wrapping across the seam; above the first row (below the
// last) lie the three pixels of that row on the far side of the pole.
void grow_connected(std::vector<std::uint32_t>& pixels, std::uint8_t* state, int width, int height,
                    std::vector<std::uint32_t>& stack) {
    const std::uint32_t w = std::uint32_t(width);
    stack.assign(pixels.begin(), pixels.end());
    auto visit = [&](int x, int y) {
        const std::uint32_t pixel = std::uint32_t(y) * w + std::uint32_t(x);
        if (state[pixel] & in_bright) {
            state[pixel] = taken_now;
            pixels.push_back(pixel);
            stack.push_back(pixel);
        }
    };
    while (!stack.empty()) {
        const std::uint32_t pixel = stack.back();
        stack.pop_back();
        const int x = int(pixel % w), y = int(pixel / w);
        for (int dy = -1; dy <= 1; ++dy) {
            int ny = y + dy;
            int shift = 0;
            if (ny < 0 || ny >= height) {
                ny = y;  // across the pole: same row, half a turn away
                shift = width / 2;
            }
            for (int dx = -1; dx <= 1; ++dx) {
                int nx = x + shift + dx;
                nx = nx < 0 ? nx + width : (nx >= width ? nx - width : nx);
                if (nx >= 0 && nx < width && (nx != x || ny != y)) {
                    visit(nx, ny);
                }
            }
        }
    }
}

Light measure_light(const HdrImage& image, const equirect::Grid& grid,
                    std::vector<std::uint32_t> pixels, double total_energy,
                    const glm::dvec3& fallback_direction) {
    Light light;
    glm::dvec3 weighted{0.0}, plain{0.0};
    const std::uint32_t width = std::uint32_t(grid.width);
    for (std::uint32_t pixel : pixels) {
        const int x = int(pixel % width), y = int(pixel / width);
        const double d_omega = grid.row_solid_angle[std::size_t(y)];
        const glm::dvec3 l = radiance(image, pixel);
        const glm::dvec3 dir = grid.direction(x, y);
        const double e = luminance(l) * d_omega;
        light.intensity += l * d_omega;
        light.solid_angle += d_omega;
        weighted += e * dir;
        plain += dir;
    }
    const double weighted_length = glm::length(weighted);
    const double plain_length = glm::length(plain);
    if (weighted_length > 0.0 && std::isfinite(weighted_length)) {
        light.direction = weighted / weighted_length;
    } else if (plain_length > 1e-9 * double(pixels.size())) {
        light.direction = plain / plain_length;
    } else {
        light.direction = fallback_direction;
    }
    light.angular_radius = std::acos(std::clamp(1.0 - light.solid_angle / (2.0 * pi), -1.0, 1.0));
    // luminance(intensity) rather than the sum of the weights, exactly as the map's total. At
    // most 1 by construction: the two sums round differently, and a light holding the whole
    // map's energy (a map with Inf pixels, or of denormals) came out just above 1, which the
    // rig's own reader (api/rig_from_json, the spec's range [0, 1]) then refused.
    light.luminance_share =
        total_energy > 0.0 ? std::min(luminance(light.intensity) / total_energy, 1.0) : 0.0;
    light.pixels = std::move(pixels);
    return light;
}

std::string plural(std::size_t n, const char* word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// Each pixel's luminance, capped to a float range that the blur cannot overflow, then blurred;
// and the map's total luminance energy sum(lum dOmega), the denominator of every luminance
// share.
struct BlurredLuminance {
    detail::LargeBuffer<float> values;
    double total_energy = 0.0;
};

BlurredLuminance blurred_luminance(const HdrImage& image, const equirect::Grid& grid,
                                   double blur_radius) {
    const int width = image.width, height = image.height;
    const std::size_t n = image.pixel_count();
    BlurredLuminance result{detail::LargeBuffer<float>(n), 0.0};
    for (int y = 0; y < height; ++y) {
        const std::size_t begin = std::size_t(y) * std::size_t(width);
        // Four partial sums: one serial chain of double additions would bound this loop.
        double row[4] = {0.0, 0.0, 0.0, 0.0};
        for (std::size_t x = 0; x < std::size_t(width); ++x) {
            const std::size_t i = begin + x;
            const float* p = &image.pixels[i * 3];
            double l = luminance({p[0], p[1], p[2]});
            if (!(p[0] >= 0.0f && p[1] >= 0.0f && p[2] >= 0.0f && l <= 1e300)) [[unlikely]] {
                l = luminance(radiance(image, i));  // not repaired: NaN, negative, Inf
            }
            result.values[i] = float(std::min(l, 1e30));
            row[x & 3] += l;
        }
        result.total_energy +=
            ((row[0] + row[1]) + (row[2] + row[3])) * grid.row_solid_angle[std::size_t(y)];
    }
    detail::LargeBuffer<float> scratch(n);
    detail::blur_equirect_in_place(result.values.data(), width, height, blur_radius,
                                   scratch.data());
    return result;
}

// The bright set and the halo set (bright is a subset of halo), in pixel order, and each
// pixel's membership while lights are taken. A pixel at the map's minimum is never bright, so
// that a uniform map has no light.
struct PixelSets {
    std::vector<std::uint32_t> bright, halo;
    detail::LargeBuffer<std::uint8_t> state;
};

PixelSets classify_pixels(const detail::LargeBuffer<float>& blurred,
                          const detail::PercentilePair& thresholds) {
    const std::size_t n = blurred.size();
    PixelSets sets{{}, {}, detail::LargeBuffer<std::uint8_t>(n)};
    for (std::size_t i = 0; i < n; ++i) {
        const float v = blurred[i];
        std::uint8_t s = 0;
        if (v > thresholds.minimum && v >= thresholds.low) {
            s = in_halo;
            sets.halo.push_back(std::uint32_t(i));
            if (v >= thresholds.high) {
                s |= in_bright;
                sets.bright.push_back(std::uint32_t(i));
            }
        }
        sets.state[i] = s;
    }
    return sets;
}

// Takes the lights one at a time out of the pixel sets: k-means over the bright pixels, the
// brightest cluster's core, the halo around it (docs/design.md section 2). Every light taken
// leaves the sets smaller for the next.
class LightTaker {
  public:
    LightTaker(const HdrImage& image, const equirect::Grid& grid,
               const LightLocationOptions& options, const BlurredLuminance& luminance,
               PixelSets& sets)
        : image_(image),
          grid_(grid),
          options_(options),
          luminance_(luminance),
          sets_(sets),
          space_(grid, options.clustering),
          grow_(options.grow_connected && options.clustering == Clustering::Directions) {}

    bool has_bright_pixels() const { return !sets_.bright.empty(); }

    // The next light, from k clusters; run numbers the lights for k-means' seed.
    Light take_light(int k, std::uint64_t run) {
        const detail::KMeansResult clusters = cluster_bright_pixels(k, run);
        const std::size_t chosen = brightest_cluster(std::size_t(clusters.k));
        take_core(chosen);
        const PointSpace::Spread spread =
            space_.spread(core_, &clusters.centres[chosen * std::size_t(space_.dimension())]);
        take_halo_within(spread.centre, space_.radius(spread.sigma));
        return measure_light(image_, grid_, light_pixels_, luminance_.total_energy,
                             space_.centre_direction(spread.centre));
    }

  private:
    // k-means over the bright pixels (a fixed-stride subsample when there are many), then every
    // bright pixel joins its nearest centre (cluster_of_).
    detail::KMeansResult cluster_bright_pixels(int k, std::uint64_t run) {
        const std::vector<std::uint32_t>& bright = sets_.bright;
        const int dim = space_.dimension();
        const std::size_t stride = (bright.size() + max_cluster_points - 1) / max_cluster_points;
        points_.clear();
        for (std::size_t j = 0; j < bright.size(); j += stride) {
            space_.append(bright[j], points_);
        }
        const std::size_t point_count = points_.size() / std::size_t(dim);
        detail::KMeansResult clusters =
            detail::kmeans(points_, dim, int(std::min<std::size_t>(std::size_t(k), point_count)),
                           space_.centre_kind(), options_.seed ^ (run * 0x9E3779B97F4A7C15ull));
        if (stride == 1) {
            cluster_of_ = clusters.assignment;
        } else {
            cluster_of_.resize(bright.size());
            for (std::size_t j = 0; j < bright.size(); ++j) {
                points_.clear();
                space_.append(bright[j], points_);
                cluster_of_[j] = detail::nearest_centre(points_.data(), clusters.centres, dim);
            }
        }
        return clusters;
    }

    // The cluster of greatest mean blurred luminance: the light.
    std::size_t brightest_cluster(std::size_t cluster_count) const {
        const std::vector<std::uint32_t>& bright = sets_.bright;
        std::vector<double> luminance_sum(cluster_count, 0.0);
        std::vector<std::size_t> count(cluster_count, 0);
        for (std::size_t j = 0; j < bright.size(); ++j) {
            luminance_sum[cluster_of_[j]] += luminance_.values[bright[j]];
            ++count[cluster_of_[j]];
        }
        std::size_t chosen = 0;
        double best = -std::numeric_limits<double>::infinity();
        for (std::size_t c = 0; c < count.size(); ++c) {
            if (count[c] > 0 && luminance_sum[c] / double(count[c]) > best) {
                best = luminance_sum[c] / double(count[c]);
                chosen = c;
            }
        }
        return chosen;
    }

    // The light's core (core_), marked taken_now. With grow_connected: the connected bright
    // region around the cluster's brightest member, so that a cluster k-means drew across
    // several separate lamps yields one compact light (the other lamps stay bright for the next
    // lights). Without it: the cluster's members, as the thesis has it.
    void take_core(std::size_t chosen) {
        const std::vector<std::uint32_t>& bright = sets_.bright;
        std::uint8_t* state = sets_.state.data();
        core_.clear();
        if (grow_) {
            std::uint32_t brightest = 0;
            double brightest_luminance = -std::numeric_limits<double>::infinity();
            for (std::size_t j = 0; j < bright.size(); ++j) {
                if (cluster_of_[j] == chosen &&
                    luminance_.values[bright[j]] > brightest_luminance) {
                    brightest_luminance = luminance_.values[bright[j]];
                    brightest = bright[j];
                }
            }
            core_.push_back(brightest);
            state[brightest] = taken_now;
            grow_connected(core_, state, grid_.width, grid_.height, stack_);
        } else {
            for (std::size_t j = 0; j < bright.size(); ++j) {
                if (cluster_of_[j] == chosen) {
                    core_.push_back(bright[j]);
                    state[bright[j]] = taken_now;
                }
            }
        }
    }

    // The core and the remaining halo pixels within radius of centre into light_pixels_, out of
    // the halo and bright sets. Every pixel taken is a halo pixel: collecting them in halo order
    // gives them sorted.
    void take_halo_within(const glm::dvec3& centre, double radius) {
        std::vector<std::uint32_t>& halo = sets_.halo;
        std::uint8_t* state = sets_.state.data();
        space_.mark_within(halo, state, centre, radius);
        light_pixels_.clear();
        std::size_t kept = 0;
        for (std::uint32_t pixel : halo) {
            if (state[pixel] == taken_now) {
                light_pixels_.push_back(pixel);
                state[pixel] = 0;
            } else {
                halo[kept++] = pixel;
            }
        }
        halo.resize(kept);
        sets_.bright.erase(
            std::remove_if(sets_.bright.begin(), sets_.bright.end(),
                           [state](std::uint32_t pixel) { return state[pixel] == 0; }),
            sets_.bright.end());
    }

    const HdrImage& image_;
    const equirect::Grid& grid_;
    const LightLocationOptions& options_;
    const BlurredLuminance& luminance_;
    PixelSets& sets_;
    const PointSpace space_;
    const bool grow_;
    // Work buffers, kept across lights.
    std::vector<double> points_;
    std::vector<std::uint32_t> cluster_of_, core_, light_pixels_, stack_;
};

// Why fewer lights than asked were found. Each light costs one cluster: k_left is the cluster
// count left when the taking stopped.
std::string shortfall_note(const LightLocationOptions& options, int max_lights, std::size_t found,
                           int k_left) {
    std::ostringstream note;
    if (k_left == 0) {
        note << "cluster_count " << options.cluster_count << " allows at most "
             << plural(std::size_t(options.cluster_count), "light") << " (asked for " << max_lights
             << ")";
    } else {
        note << "no bright pixels left after " << plural(found, "light") << " (asked for "
             << max_lights << ")";
    }
    return note.str();
}

}  // namespace

LightLocation locate_lights(const HdrImage& image, int max_lights,
                            const LightLocationOptions& options) {
    validate(image, max_lights, options);
    const equirect::Grid grid(image.width, image.height);
    LightLocation result;
    const BlurredLuminance blurred = blurred_luminance(image, grid, options.blur_radius);
    const detail::PercentilePair thresholds =
        detail::select_percentiles(blurred.values.data(), blurred.values.size(),
                                   options.light_percentile, options.halo_percentile);
    result.light_threshold = thresholds.high;
    result.halo_threshold = thresholds.low;

    PixelSets sets = classify_pixels(blurred.values, thresholds);
    result.bright_pixel_count = sets.bright.size();
    result.halo_pixel_count = sets.halo.size();
    if (sets.bright.empty()) {
        if (max_lights > 0) {
            result.note = thresholds.minimum == 0.0f
                              ? "map is black: no pixel carries any luminance"
                              : "map is uniform: no pixel is brighter than the rest";
        }
        return result;
    }

    LightTaker taker(image, grid, options, blurred, sets);
    int k = options.cluster_count;
    for (std::uint64_t run = 0;
         int(result.lights.size()) < max_lights && k >= 1 && taker.has_bright_pixels();
         ++run, --k) {
        result.lights.push_back(taker.take_light(k, run));
    }
    if (int(result.lights.size()) < max_lights) {
        result.note = shortfall_note(options, max_lights, result.lights.size(), k);
    }
    return result;
}

}  // namespace oer
