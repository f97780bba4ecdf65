// The prefiltered residual cube map of the split-sum specular IBL (see
// oer/lighting/specular_environment.hpp):
//  1. the map resampled to an unfiltered cube of face_size: 4 x 4 regular subsamples per
//     texel, each read bilinearly from the equirect (docs/design.md section 3 mapping, wrapping in
//     phi, clamped at the poles) and weighted by its solid angle, the cube's Jacobian
//     dOmega = ds dt / (1 + sc^2 + tc^2)^(3/2) (up to a constant);
//  2. its box-filtered mip pyramid, in float, down to 1 x 1, each 2 x 2 box weighted by its
//     texels' solid angles, every face bordered by one texel of its neighbours so that reads
//     filter across the cube's edges (as GL's seamless cube maps do);
//  3. level 0 of the output is the unfiltered cube; level i >= 1 is, per texel direction r
//     (n = v = r), the GGX-importance-sampled estimate
//       P(r) = sum_k L(l_k, lod_k) (n.l_k) / sum_k (n.l_k)
//     over Hammersley points (J. M. Hammersley and D. C. Handscomb, "Monte Carlo Methods",
//     1964; as in Karis 2013; drawn by oer/lighting/sampling.hpp) with h of pdf D(h) (n.h), so
//     l = 2 (v.h) h - v has pdf D(h) / 4 (n = v);
//     D is GGX (B. Walter, S. Marschner, H. Li and K. Torrance, "Microfacet Models for
//     Refraction through Rough Surfaces", EGSR 2007) of alpha = roughness^2. Each sample reads
//     the pyramid at the lod of filtered importance sampling (J. Krivanek and M. Colbert,
//     "Real-time Shading with Filtered Importance Sampling", EGSR 2008):
//       lod = 0.5 log2(omega_s / omega_p) + 1,  omega_s = 1 / (samples pdf),
//       omega_p = 4 pi / (6 face_size^2),
//     as Filament's cmgen does, then corrected by the solid angle of the texel the sample falls
//     in (omega_p is the mean texel's; see prefilter_faces). The sample set is the same for
//     every texel of a level (only its frame turns with r), so it is built once per level;
//  4. stored as IEEE half floats (glm::packHalf1x16), clamped to the largest finite half
//     (65504): GL_RGB16F cannot hold more, and a stored cube must decode (no infinities).
// Two threads with a fixed split (faces 0-2 and 3-5, rows of a table at half): every texel is
// computed by one thread from the same inputs, so the bytes do not depend on the timing.
#include "oer/lighting/specular_environment.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

#include "cube_faces.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/sampling.hpp"
#include "two_thread_split.hpp"

namespace oer {
namespace {

using std::numbers::pi;

constexpr int kMinFaceSize = 4;
constexpr int kMaxFaceSize = 2048;
constexpr int kMaxSamples = 4096;
constexpr int kSubsamplesPerAxis = 4;  // per texel of the unfiltered cube
constexpr float kMaxHalf = 65504.0f;
// The most lights a stored environment may claim: the renderer's most lights per frame
// (kMaxFrameLights, renderer/gl/src/frame_programs.hpp); a rig has at most 16. Its lights' cube
// has at most twice as many layers (a floor layer each).
constexpr int kMaxStoredLights = 64;

constexpr char kMagic[] = "OERSPEC";  // 7 bytes, then the version character
constexpr char kVersion = '3';
// Magic and version, then face_size, levels and layers (uint32 LE) of each of the two cubes,
// then the count of floor layers (uint32 LE), each of them (int32 LE) after the header.
constexpr std::size_t kHeaderBytes = 36;

[[noreturn]] void invalid(const std::string& what) {
    throw Error(ErrorKind::InvalidInput, what);
}

int log2_of(int power_of_two) {
    return std::countr_zero(unsigned(power_of_two));
}

bool is_power_of_two(int n) {
    return n > 0 && std::has_single_bit(unsigned(n));
}

void validate_options(const SpecularOptions& options) {
    if (!is_power_of_two(options.face_size) || options.face_size < kMinFaceSize ||
        options.face_size > kMaxFaceSize) {
        invalid("specular cube: face_size " + std::to_string(options.face_size) +
                " is not a power of two in [" + std::to_string(kMinFaceSize) + ", " +
                std::to_string(kMaxFaceSize) + "]");
    }
    const int max_levels = log2_of(options.face_size) + 1;
    if (options.levels < 2 || options.levels > max_levels) {
        invalid("specular cube: levels " + std::to_string(options.levels) + " is not in [2, " +
                std::to_string(max_levels) + "] for face_size " +
                std::to_string(options.face_size));
    }
    if (options.samples < 1 || options.samples > kMaxSamples) {
        invalid("specular cube: samples " + std::to_string(options.samples) + " is not in [1, " +
                std::to_string(kMaxSamples) + "]");
    }
}

void validate_map(const HdrImage& map) {
    if (map.width <= 0 || map.height <= 0 || map.pixels.size() != map.pixel_count() * 3) {
        invalid("specular cube: map of " + std::to_string(map.width) + "x" +
                std::to_string(map.height) + " with " + std::to_string(map.pixels.size()) +
                " floats is not a valid RGB map");
    }
    for (std::size_t i = 0; i < map.pixels.size(); ++i) {
        const float value = map.pixels[i];
        if (!(value >= 0.0f && std::isfinite(value))) {
            const std::size_t pixel = i / 3;
            invalid("specular cube: map pixel (" + std::to_string(pixel % std::size_t(map.width)) +
                    ", " + std::to_string(pixel / std::size_t(map.width)) + ") channel " +
                    std::to_string(i % 3) + " is " + std::to_string(value) +
                    ": radiance must be finite and non-negative");
        }
    }
}

// One level of a cube in float: 6 faces of size x size RGB texels, rows from t = 0.
// With a border of one texel (the pyramid), i and j run from -1 to size: the border holds the
// neighbouring faces' edge texels, so that bilinear reads filter across the cube's edges as
// GL's seamless cube maps do.
struct FloatLevel {
    int size = 0;
    int border = 0;
    int stride = 0;
    std::vector<float> rgb;

    FloatLevel(int n, int border_texels)
        : size(n),
          border(border_texels),
          stride(n + 2 * border_texels),
          rgb(std::size_t(6) * stride * stride * 3, 0.0f) {}
    std::size_t index(int face, int i, int j) const {
        return ((std::size_t(face) * stride + std::size_t(j + border)) * stride +
                std::size_t(i + border)) *
               3;
    }
    float* texel(int face, int i, int j) { return &rgb[index(face, i, j)]; }
    const float* texel(int face, int i, int j) const { return &rgb[index(face, i, j)]; }
};

// Fills the border of every face of a level with a border of one texel: the texel of the
// neighbouring face nearest to the border texel's direction (on a face's plane extended, the
// border texel's centre falls within a hundredth of a texel of the neighbour's edge texel;
// a corner's, where three faces meet, takes one of them).
void fill_border(FloatLevel& level) {
    const int n = level.size;
    for (int face = 0; face < 6; ++face) {
        for (int j = -1; j <= n; ++j) {
            for (int i = -1; i <= n; ++i) {
                if (i >= 0 && i < n && j >= 0 && j < n) {
                    continue;
                }
                const auto c =
                    detail::cube_lookup(detail::cube_direction(face, (i + 0.5) / n, (j + 0.5) / n));
                const int si = std::clamp(int(c.s * n), 0, n - 1);
                const int sj = std::clamp(int(c.t * n), 0, n - 1);
                const float* source = level.texel(c.face, si, sj);
                std::copy(source, source + 3, level.texel(face, i, j));
            }
        }
    }
}

// Bilinear read of one face at (s, t) in [0, 1], clamped to the face's edge texels (GL's
// CLAMP_TO_EDGE within a face: nearest across its edge). fetch(i, j) returns a texel's RGB.
template <typename Fetch>
inline glm::vec3 bilinear_face(int size, float s, float t, const Fetch& fetch) {
    const float x = std::clamp(s * float(size) - 0.5f, 0.0f, float(size - 1));
    const float y = std::clamp(t * float(size) - 0.5f, 0.0f, float(size - 1));
    const int x0 = int(x), y0 = int(y);
    const int x1 = std::min(x0 + 1, size - 1), y1 = std::min(y0 + 1, size - 1);
    const float fx = x - float(x0), fy = y - float(y0);
    const glm::vec3 top = glm::mix(fetch(x0, y0), fetch(x1, y0), fx);
    const glm::vec3 bottom = glm::mix(fetch(x0, y1), fetch(x1, y1), fx);
    return glm::mix(top, bottom, fy);
}

// Bilinear read of the equirect at its continuous position (u, v), u in [0, 2 W), wrapping in
// u (phi) and clamped in v (theta) at the poles' rows.
inline glm::vec3 sample_equirect(const HdrImage& map, float u, float v) {
    // u - 0.5 is at least -0.5: truncating u + 0.5 floors it, plus 1 (cheaper than std::floor).
    const float x = u + 0.5f;
    int x0 = int(x) - 1;
    const float fx = x - float(x0 + 1);
    x0 = x0 < 0 ? x0 + map.width : (x0 >= map.width ? x0 - map.width : x0);
    const int x1 = x0 + 1 == map.width ? 0 : x0 + 1;
    const float y = std::clamp(v - 0.5f, 0.0f, float(map.height - 1));
    const int y0 = int(y), y1 = std::min(y0 + 1, map.height - 1);
    const float fy = y - float(y0);
    const auto at = [&](int px, int py) {
        const float* p = map.at(px, py);
        return glm::vec3(p[0], p[1], p[2]);
    };
    const glm::vec3 top = glm::mix(at(x0, y0), at(x1, y0), fx);
    const glm::vec3 bottom = glm::mix(at(x0, y1), at(x1, y1), fx);
    return glm::mix(top, bottom, fy);
}

// Where step 1's subsamples fall in the equirect: side x side subsamples per face (k x k per
// texel), subsample (a, b) at s = (a + 0.5) / side, t = (b + 0.5) / side. The faces are turns
// and mirrors of two (cube_faces.hpp): -X, +Z and -Z are +X turned about +Y by pi, pi / 2 and
// 3 pi / 2 (u + W / 2, W / 4, 3 W / 4), on which phi depends on a alone; -Y is +Y with t and
// y mirrored (row side - 1 - b, v -> H - v). Mirroring a (sc -> -sc) keeps theta on both and
// turns +Y's phi into pi - phi (u -> 3 W / 2 - u). So the trigonometry runs on a quarter of
// two faces only.
struct SubsamplePositions {
    int side = 0;
    std::vector<float> weight;  // solid angle, up to a constant: (1 + sc^2 + tc^2)^(-3/2)
    std::vector<float> side_u;  // +X, per column a
    std::vector<float> side_v;  // +X, per (a, b)
    std::vector<float> top_u;   // +Y, per (a, b), in [0, 2 W)
    std::vector<float> top_v;

    SubsamplePositions(int face_size, const HdrImage& map)
        : side(face_size * kSubsamplesPerAxis),
          weight(std::size_t(side) * side),
          side_u(std::size_t(side)),
          side_v(weight.size()),
          top_u(weight.size()),
          top_v(weight.size()) {
        for (int a = 0; a < side; ++a) {
            side_u[std::size_t(a)] =
                float(equirect::position_of(detail::cube_direction(0, (a + 0.5) / side, 0.5),
                                            map.width, map.height)
                          .x);
        }
        const float width = float(map.width), height = float(map.height);
        const int half = side / 2;
        detail::split_on_two_threads(half, half / 2, [&](int b_begin, int b_end) {
            for (int b = b_begin; b < b_end; ++b) {
                const double t = (b + 0.5) / side, tc = 2.0 * t - 1.0;
                const std::size_t row = std::size_t(b) * side;
                const std::size_t mirrored_row = std::size_t(side - 1 - b) * side;
                for (int a = 0; a < half; ++a) {
                    const double s = (a + 0.5) / side, sc = 2.0 * s - 1.0;
                    const std::size_t quadrant[4] = {row + a, row + (side - 1 - a),
                                                     mirrored_row + a,
                                                     mirrored_row + (side - 1 - a)};
                    const double q = 1.0 + sc * sc + tc * tc;
                    const float w = float(1.0 / (q * std::sqrt(q)));
                    const float v_side =
                        float(equirect::position_of(detail::cube_direction(0, s, t), map.width,
                                                    map.height)
                                  .y);
                    const glm::dvec2 top = equirect::position_of(detail::cube_direction(2, s, t),
                                                                 map.width, map.height);
                    const float u_top = float(top.x), v_top = float(top.y);
                    // Mirroring b (tc -> -tc) turns +X's theta into pi - theta and +Y's phi
                    // into -phi (u -> W - u); mirroring a as above.
                    const float side_vs[4] = {v_side, v_side, height - v_side, height - v_side};
                    const float top_us[4] = {u_top, 1.5f * width - u_top, width - u_top,
                                             0.5f * width + u_top};
                    for (int k = 0; k < 4; ++k) {
                        weight[quadrant[k]] = w;
                        side_v[quadrant[k]] = side_vs[k];
                        top_u[quadrant[k]] = top_us[k];
                        top_v[quadrant[k]] = v_top;
                    }
                }
            }
        });
    }

    // Equirect position of subsample (a, b) of `face`, u in [0, 2 W).
    glm::vec2 at(int face, int a, int b, const HdrImage& map) const {
        const std::size_t index = std::size_t(b) * side + a;
        const std::size_t mirrored = std::size_t(side - 1 - b) * side + a;
        switch (face) {
            case 0:
                return {side_u[std::size_t(a)], side_v[index]};
            case 1:
                return {side_u[std::size_t(a)] + 0.5f * float(map.width), side_v[index]};
            case 2:
                return {top_u[index], top_v[index]};
            case 3:
                return {top_u[mirrored], float(map.height) - top_v[mirrored]};
            case 4:
                return {side_u[std::size_t(a)] + 0.25f * float(map.width), side_v[index]};
            default:
                return {side_u[std::size_t(a)] + 0.75f * float(map.width), side_v[index]};
        }
    }
};

// Where a map can be non-zero: texel directions whose dot with axis is below cos_limit see
// black only (the whole sphere: cos_limit -2).
struct SupportCone {
    glm::vec3 axis{0.0f, 1.0f, 0.0f};
    float cos_limit = -2.0f;
    double angle = pi;  // acos(cos_limit), or pi for the whole sphere

    // Whether the centre of texel (i, j) of an n x n face lies outside the cone.
    bool excludes(int face, int i, int j, int n) const {
        return cos_limit > -1.0f &&
               glm::dot(glm::vec3(detail::cube_direction(face, (i + 0.5) / n, (j + 0.5) / n)),
                        axis) < cos_limit;
    }
};

// The cone about `cone`'s axis of the given half angle (the whole sphere from pi on).
SupportCone widened(const SupportCone& cone, double angle) {
    return angle >= pi ? SupportCone{} : SupportCone{cone.axis, float(std::cos(angle)), angle};
}

// Step 1, faces [face_begin, face_end): the map area-averaged over each texel; 0 outside the
// map's support.
void resample_faces(const HdrImage& map, const SubsamplePositions& positions,
                    const SupportCone& support, FloatLevel& cube, int face_begin, int face_end) {
    const int n = cube.size;
    constexpr int k = kSubsamplesPerAxis;
    for (int face = face_begin; face < face_end; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                if (support.excludes(face, i, j, n)) {
                    continue;  // the level starts black
                }
                glm::vec3 sum(0.0f);
                float weight_sum = 0.0f;
                for (int b = j * k; b < (j + 1) * k; ++b) {
                    for (int a = i * k; a < (i + 1) * k; ++a) {
                        const glm::vec2 position = positions.at(face, a, b, map);
                        const float w = positions.weight[std::size_t(b) * positions.side + a];
                        sum += w * sample_equirect(map, position.x, position.y);
                        weight_sum += w;
                    }
                }
                const glm::vec3 mean = sum / weight_sum;
                float* out = cube.texel(face, i, j);
                out[0] = float(mean.r), out[1] = float(mean.g), out[2] = float(mean.b);
            }
        }
    }
}

// The pyramid of step 2: the levels, and per level the solid angles of a face's texels
// (cube_faces.hpp) and step 3's lod offsets, -0.5 log2 of each texel's solid angle over the
// level's mean texel solid angle 4 pi / (6 n^2).
struct Pyramid {
    std::vector<FloatLevel> levels;
    std::vector<std::vector<double>> solid_angles;
    std::vector<std::vector<float>> lod_offsets;

    explicit Pyramid(int face_size) {
        for (int n = face_size; n >= 1; n /= 2) {
            levels.emplace_back(n, 1);
            solid_angles.push_back(detail::cube_face_solid_angles(n));
            const double mean = 4.0 * pi / (6.0 * double(n) * n);
            std::vector<float> offsets(solid_angles.back().size());
            for (std::size_t i = 0; i < offsets.size(); ++i) {
                offsets[i] = float(-0.5 * std::log2(solid_angles.back()[i] / mean));
            }
            lod_offsets.push_back(std::move(offsets));
        }
    }
};

// Step 2, faces [face_begin, face_end) of every level below the first: 2 x 2 box averages
// weighted by the fine texels' solid angles, so that every level holds the same energy (a
// plain mean would count a face's corner texels, a fifth of a centre texel's solid angle, as
// much as its centre's: on Blender's studio, level 4 lost 8 % of the map's energy that way).
void downsample_faces(Pyramid& pyramid, int face_begin, int face_end) {
    for (std::size_t level = 1; level < pyramid.levels.size(); ++level) {
        const FloatLevel& fine = pyramid.levels[level - 1];
        const std::vector<double>& solid_angle = pyramid.solid_angles[level - 1];
        FloatLevel& coarse = pyramid.levels[level];
        for (int face = face_begin; face < face_end; ++face) {
            for (int j = 0; j < coarse.size; ++j) {
                for (int i = 0; i < coarse.size; ++i) {
                    glm::dvec3 sum(0.0);
                    double weight_sum = 0.0;
                    for (int y = 2 * j; y < 2 * j + 2; ++y) {
                        for (int x = 2 * i; x < 2 * i + 2; ++x) {
                            const double w = solid_angle[std::size_t(y) * fine.size + x];
                            const float* p = fine.texel(face, x, y);
                            sum += w * glm::dvec3(p[0], p[1], p[2]);
                            weight_sum += w;
                        }
                    }
                    const glm::dvec3 mean = sum / weight_sum;
                    float* out = coarse.texel(face, i, j);
                    out[0] = float(mean.r), out[1] = float(mean.g), out[2] = float(mean.b);
                }
            }
        }
    }
}

// Bilinear read of a level with its border at (s, t) of a face: across the face's edges.
inline glm::vec3 sample_level(const FloatLevel& level,
                              const detail::CubeFaceCoordinates<float>& c) {
    // s n - 0.5 is at least -0.5: truncating s n + 0.5 floors it, plus 1 (cheaper than
    // std::floor without SSE4.1); likewise t.
    const float x = std::clamp(c.s, 0.0f, 1.0f) * float(level.size) + 0.5f;
    const float y = std::clamp(c.t, 0.0f, 1.0f) * float(level.size) + 0.5f;
    const int x0 = int(x) - 1, y0 = int(y) - 1;
    const float fx = x - float(x0 + 1), fy = y - float(y0 + 1);
    const float* p00 = level.texel(c.face, x0, y0);
    const float* p01 = p00 + std::size_t(level.stride) * 3;
    const auto at = [](const float* p) { return glm::vec3(p[0], p[1], p[2]); };
    const glm::vec3 top = glm::mix(at(p00), at(p00 + 3), fx);
    const glm::vec3 bottom = glm::mix(at(p01), at(p01 + 3), fx);
    return glm::mix(top, bottom, fy);
}

// One GGX sample in the frame of r (r = +z): its direction, weight n.l over the sum of the
// level's, and the pyramid's levels and blend it reads.
struct LobeSample {
    glm::vec3 direction;
    float weight;
    float lod;          // Krivanek and Colbert's, for a texel of the mean solid angle, unclamped
    int nearest_level;  // lod rounded and clamped to the pyramid: whose texel sizes correct it
};

std::vector<LobeSample> lobe_samples(double roughness, int samples, int face_size,
                                     int pyramid_levels) {
    const double alpha = roughness * roughness;
    const double alpha2 = alpha * alpha;
    const double omega_p = 4.0 * pi / (6.0 * double(face_size) * face_size);
    std::vector<LobeSample> result;
    result.reserve(std::size_t(samples));
    double weight_sum = 0.0;
    for (int k = 0; k < samples; ++k) {
        // Hammersley point k: the polar angle from k / samples, the azimuth 2 pi times the
        // radical inverse.
        const glm::dvec2 point = sampling::hammersley(std::uint32_t(k), std::uint32_t(samples));
        const sampling::GgxHalfVector h =
            sampling::ggx_half_vector(alpha2, point.x, 2.0 * pi * point.y);
        const double cos_h = h.direction.z;
        const glm::dvec3 l = 2.0 * cos_h * h.direction - glm::dvec3(0.0, 0.0, 1.0);
        const double n_dot_l = l.z;
        if (n_dot_l <= 0.0) {
            continue;
        }
        const double pdf = sampling::ggx_distribution(alpha2, h.cos2_theta) / 4.0;
        const double omega_s = 1.0 / (samples * pdf);
        const double lod = 0.5 * std::log2(omega_s / omega_p) + 1.0;
        const int nearest = std::clamp(int(std::lround(lod)), 0, pyramid_levels - 1);
        result.push_back({glm::vec3(l), float(n_dot_l), float(lod), nearest});
        weight_sum += n_dot_l;
    }
    for (LobeSample& sample : result) {
        sample.weight = float(sample.weight / weight_sum);
    }
    return result;
}

// Step 3 for one output level, faces [face_begin, face_end). A sample's lod is corrected by
// the solid angle of the texel it falls in at its nearest level: a cube's texels shrink 5.2
// times from a face's centre to its corners, and the lod of the mean texel blurs a light at a
// face centre too much and one at a corner too little (measured on 24 discs of 3 degrees at
// random directions against their exact convolution, relative RMS at levels 1 to 4: 5.9, 11.1,
// 11.8, 17.7 % with the mean texel's lod; 2.7, 6.7, 13.6, 17.7 % corrected).
void prefilter_faces(const Pyramid& pyramid, const std::vector<LobeSample>& samples,
                     FloatLevel& out, int face_begin, int face_end) {
    const int n = out.size;
    const float max_lod = float(pyramid.levels.size() - 1);
    for (int face = face_begin; face < face_end; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const glm::dvec3 r = detail::cube_direction(face, (i + 0.5) / n, (j + 0.5) / n);
                const glm::dvec3 up =
                    std::abs(r.z) < 0.999 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(1.0, 0.0, 0.0);
                const glm::vec3 tangent(glm::normalize(glm::cross(up, r)));
                const glm::vec3 bitangent(glm::cross(r, glm::dvec3(tangent)));
                const glm::vec3 normal(r);
                glm::vec3 sum(0.0f);
                for (const LobeSample& sample : samples) {
                    const glm::vec3 l = sample.direction.x * tangent +
                                        sample.direction.y * bitangent +
                                        sample.direction.z * normal;
                    const detail::CubeFaceCoordinates<float> c = detail::cube_lookup(l);
                    const std::size_t nearest = std::size_t(sample.nearest_level);
                    const int nearest_size = pyramid.levels[nearest].size;
                    const int ti = std::min(int(c.s * float(nearest_size)), nearest_size - 1);
                    const int tj = std::min(int(c.t * float(nearest_size)), nearest_size - 1);
                    const float offset =
                        pyramid.lod_offsets[nearest][std::size_t(tj) * nearest_size + ti];
                    const float lod = std::clamp(sample.lod + offset, 0.0f, max_lod);
                    const int lower = int(lod);
                    const float blend = lod - float(lower);
                    glm::vec3 radiance = sample_level(pyramid.levels[std::size_t(lower)], c);
                    if (blend > 0.0f) {
                        radiance = glm::mix(radiance,
                                            sample_level(pyramid.levels[std::size_t(lower) + 1], c),
                                            blend);
                    }
                    sum += sample.weight * radiance;
                }
                float* texel = out.texel(face, i, j);
                texel[0] = sum.r, texel[1] = sum.g, texel[2] = sum.b;
            }
        }
    }
}

std::size_t level_values(int face_size, int level) {
    const std::size_t n = std::size_t(face_size >> level);
    return 6 * n * n * 3;
}

// Step 4, faces [face_begin, face_end) of one level, its border left out.
void to_half(const FloatLevel& level, std::uint16_t* out, int face_begin, int face_end) {
    const int n = level.size;
    for (int face = face_begin; face < face_end; ++face) {
        for (int j = 0; j < n; ++j) {
            const float* row = level.texel(face, 0, j);
            std::uint16_t* out_row = &out[((std::size_t(face) * n + j) * n) * 3];
            for (int k = 0; k < 3 * n; ++k) {
                out_row[k] = glm::packHalf1x16(std::min(row[k], kMaxHalf));
            }
        }
    }
}

// Steps 1 and 2: the map resampled to a cube of face_size, and its pyramid.
Pyramid resampled_pyramid(const HdrImage& map, int face_size, const SupportCone& support = {}) {
    Pyramid pyramid(face_size);
    const SubsamplePositions positions(face_size, map);
    detail::split_on_two_threads(6, 3, [&](int begin, int end) {
        resample_faces(map, positions, support, pyramid.levels[0], begin, end);
        downsample_faces(pyramid, begin, end);
    });
    for (FloatLevel& level : pyramid.levels) {
        fill_border(level);
    }
    return pyramid;
}

// The first texel of layer `layer` of level `level` of a cube whose levels are allocated for
// all its layers.
std::uint16_t* layer_texels(PrefilteredCube& cube, int level, int layer) {
    return cube.rgb_half[std::size_t(level)].data() +
           std::size_t(layer) * level_values(cube.face_size, level);
}

// Steps 1 to 4 of the map at face_size, written as layer `layer` of `cube`.
void prefilter_into(const HdrImage& map, int face_size, int samples, PrefilteredCube& cube,
                    int layer) {
    const Pyramid pyramid = resampled_pyramid(map, face_size);
    std::vector<std::vector<LobeSample>> level_samples;
    std::vector<FloatLevel> filtered;
    for (int level = 1; level < cube.levels; ++level) {
        level_samples.push_back(lobe_samples(roughness_of_level(level, cube.levels), samples,
                                             face_size, int(pyramid.levels.size())));
        filtered.emplace_back(face_size >> level, 0);
    }
    detail::split_on_two_threads(6, 3, [&](int begin, int end) {
        to_half(pyramid.levels[0], layer_texels(cube, 0, layer), begin, end);
        for (std::size_t k = 0; k < filtered.size(); ++k) {
            prefilter_faces(pyramid, level_samples[k], filtered[k], begin, end);
            to_half(filtered[k], layer_texels(cube, int(k) + 1, layer), begin, end);
        }
    });
}

// A light's cube (prefilter_lights): a light is a small bright region on black, which GGX
// importance sampling with filtered importance sampling estimates badly at high roughness (its
// 64 samples read pyramid levels of 2 x 2 texels, and a soft box's reflection came out 25 %
// off its peak and lopsided). So levels 1 and above are instead the exact sum over the light's
// texels at a level of the pyramid fine enough for the lobe,
//   P(r) = sum_t K(r, l_t) L_t dOmega_t / Z,   K(r, l) = D(h) (r.l),   Z = integral of K,
// K being the kernel the sampled prefiltering estimates (n = v = r, D of alpha = roughness^2,
// (n.h)^2 = (1 + r.l) / 2), so that the lights' cubes and the residual's are the same filter.
// The source level has texels of at most alpha / 2 radians across (n >= pi / alpha), and at
// least 32 a face (2.8 degrees), which keeps each texel's energy near its place for the
// widest lobes.
struct LightTexel {
    glm::vec3 direction;
    glm::vec3 energy;  // radiance times solid angle
};

std::vector<LightTexel> light_texels(const Pyramid& pyramid, std::size_t level) {
    const FloatLevel& texels = pyramid.levels[level];
    const std::vector<double>& solid_angles = pyramid.solid_angles[level];
    const int n = texels.size;
    std::vector<LightTexel> result;
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const float* p = texels.texel(face, i, j);
                if (p[0] > 0.0f || p[1] > 0.0f || p[2] > 0.0f) {
                    const float solid_angle = float(solid_angles[std::size_t(j) * n + i]);
                    result.push_back(
                        {glm::vec3(detail::cube_direction(face, (i + 0.5) / n, (j + 0.5) / n)),
                         solid_angle * glm::vec3(p[0], p[1], p[2])});
                }
            }
        }
    }
    return result;
}

// Each output texel is the mean of P over it, from k x k directions across it: k = 2 where the
// lobe (about 2 alpha wide) is narrower than two texels, which a texel's centre alone would
// miss or overweigh (a level's energy was then 1.4 % off at roughness 0.087 on 64 texels).
// Texels whose direction lies outside `reach` get 0: no texel of the light is within the angle
// where the kernel falls under a millionth of its peak (kernel_reach).
void prefilter_light_faces(const std::vector<LightTexel>& texels, double alpha,
                           double normalisation, const SupportCone& reach, FloatLevel& out,
                           int face_begin, int face_end) {
    const float a2 = float(alpha * alpha);
    const float scale = float(1.0 / (pi * normalisation));
    const int n = out.size;
    const int k = (pi / 2.0) / n > alpha ? 2 : 1;
    for (int face = face_begin; face < face_end; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                if (reach.excludes(face, i, j, n)) {
                    continue;  // the level starts black
                }
                glm::vec3 sum(0.0f);
                for (int b = 0; b < k; ++b) {
                    for (int a = 0; a < k; ++a) {
                        const glm::vec3 r(detail::cube_direction(face, (i + (a + 0.5) / k) / n,
                                                                 (j + (b + 0.5) / k) / n));
                        for (const LightTexel& texel : texels) {
                            const float c = glm::dot(r, texel.direction);
                            if (c > 0.0f) {
                                const float q = 0.5f * (1.0f + c) * (a2 - 1.0f) + 1.0f;
                                sum += (c / (q * q)) * texel.energy;
                            }
                        }
                    }
                }
                float* value = out.texel(face, i, j);
                const glm::vec3 radiance = a2 * scale / float(k * k) * sum;
                value[0] = radiance.r, value[1] = radiance.g, value[2] = radiance.b;
            }
        }
    }
}

// The angle from a direction beyond which the kernel of alpha is under 1e-6 of its peak:
// D(h) / D(0) ~ (alpha / tan theta_h)^4, so tan theta_h = 31.6 alpha, theta = 2 theta_h, plus
// one output texel's diagonal (`texel`). What lies beyond carries under 0.1 % of the lobe's
// energy (alpha^2 / (alpha^2 + tan^2 theta_h)).
double kernel_reach(double alpha, double texel) {
    return 2.0 * std::atan(std::sqrt(1e3) * alpha) + texel;
}

// The cone about a light's direction that holds its pixels, widened by what reaches a texel's
// subsamples from outside it: two map pixels (bilinear reads) and one texel's diagonal.
SupportCone light_support(const Light& light, const HdrImage& map, int face_size) {
    const equirect::Grid grid(map.width, map.height);
    const glm::dvec3 axis = light.direction;
    double widest = 0.0;
    for (const std::uint32_t index : light.pixels) {
        widest = std::max(widest,
                          std::acos(std::clamp(glm::dot(grid.direction(index), axis), -1.0, 1.0)));
    }
    const double margin = 2.0 * 2.0 * pi / map.width + std::sqrt(2.0) * (pi / 2.0) / face_size;
    return widened(SupportCone{glm::vec3(axis), 0.0f}, widest + margin);
}

// Light k's pixels alone (black elsewhere) into layer `layer` of `cube`: level 0 resampled as
// every cube's, the levels above by prefilter_light_faces.
void prefilter_light_into(const HdrImage& alone, const SupportCone& support, PrefilteredCube& cube,
                          int layer) {
    const Pyramid pyramid = resampled_pyramid(alone, cube.face_size, support);
    std::vector<std::vector<LightTexel>> sources;
    std::vector<FloatLevel> filtered;
    std::vector<double> alphas, normalisations;
    for (int level = 1; level < cube.levels; ++level) {
        const double alpha = std::pow(roughness_of_level(level, cube.levels), 2.0);
        alphas.push_back(alpha);
        normalisations.push_back(prefilter_kernel_integral(alpha));
        // Sources no finer than half the face: a quarter of the texels of the finest at the
        // first level, whose lobe (0.64 degrees at roughness 0.11) the output's 2 x 2 directions
        // per texel of 1.4 degrees resolve no better.
        const int wanted =
            std::clamp(int(std::bit_ceil(unsigned(std::ceil(pi / alpha)))), 32, cube.face_size / 2);
        sources.push_back(light_texels(pyramid, std::size_t(log2_of(cube.face_size / wanted))));
        filtered.emplace_back(cube.face_size >> level, 0);
    }
    detail::split_on_two_threads(6, 3, [&](int begin, int end) {
        to_half(pyramid.levels[0], layer_texels(cube, 0, layer), begin, end);
        for (std::size_t k = 0; k < filtered.size(); ++k) {
            const double alpha = alphas[k];
            const SupportCone reach = widened(
                support, support.angle +
                             kernel_reach(alpha, std::sqrt(2.0) * (pi / 2.0) / filtered[k].size));
            prefilter_light_faces(sources[k], alpha, normalisations[k], reach, filtered[k], begin,
                                  end);
            to_half(filtered[k], layer_texels(cube, int(k) + 1, layer), begin, end);
        }
    });
}

// A cube of `layers` layers with every level allocated (zero).
PrefilteredCube allocate_cube(int face_size, int levels, int layers) {
    PrefilteredCube cube;
    cube.face_size = face_size;
    cube.levels = levels;
    cube.layers = layers;
    for (int level = 0; level < levels; ++level) {
        cube.rgb_half.emplace_back(std::size_t(layers) * level_values(face_size, level));
    }
    return cube;
}

PrefilteredCube prefilter(const HdrImage& map, const SpecularOptions& options) {
    PrefilteredCube cube = allocate_cube(options.face_size, options.levels, 1);
    prefilter_into(map, options.face_size, options.samples, cube, 0);
    return cube;
}

// The checks prefilter_residual and prefilter_lights share: options, model, map.
void validate_rig_map(const HdrImage& map, const Rig& rig, const SpecularOptions& options) {
    validate_options(options);
    if (rig.model != LightingModel::Hdr) {
        invalid("specular cube: the rig's lighting model is " + to_string(rig.model) +
                ", which has no specular term (only hdr has)");
    }
    if (map.width != rig.source_width || map.height != rig.source_height) {
        invalid("specular cube: the map is " + std::to_string(map.width) + "x" +
                std::to_string(map.height) + ", the rig was built from a " +
                std::to_string(rig.source_width) + "x" + std::to_string(rig.source_height) +
                " map");
    }
    validate_map(map);
    for (std::size_t k = 0; k < rig.lights.size(); ++k) {
        for (const std::uint32_t index : rig.lights[k].pixels) {
            if (index >= map.pixel_count()) {
                invalid("specular cube: light " + std::to_string(k) + " has pixel index " +
                        std::to_string(index) + ", the map has " +
                        std::to_string(map.pixel_count()) + " pixels");
            }
        }
    }
}

void put_u32(std::string& out, std::uint32_t value) {
    for (int byte = 0; byte < 4; ++byte) {
        out.push_back(char((value >> (8 * byte)) & 0xffu));
    }
}

std::uint32_t get_u32(std::string_view bytes, std::size_t offset) {
    std::uint32_t value = 0;
    for (int byte = 0; byte < 4; ++byte) {
        value |= std::uint32_t(std::uint8_t(bytes[offset + std::size_t(byte)])) << (8 * byte);
    }
    return value;
}

}  // namespace

std::size_t PrefilteredCube::byte_size() const {
    std::size_t values = 0;
    for (const std::vector<std::uint16_t>& level : rgb_half) {
        values += level.size();
    }
    return values * sizeof(std::uint16_t);
}

std::size_t SpecularEnvironment::byte_size() const {
    return residual.byte_size() + lights.byte_size();
}

double roughness_of_level(int level, int levels) {
    if (levels < 2 || level < 0 || level >= levels) {
        invalid("roughness_of_level: level " + std::to_string(level) + " of a cube of " +
                std::to_string(levels) + " levels (levels >= 2, level in [0, levels - 1])");
    }
    return 1.0 - std::sqrt(1.0 - double(level) / double(levels - 1));
}

double lod_of_roughness(double roughness, int levels) {
    const double r = std::clamp(roughness, 0.0, 1.0);
    return double(levels - 1) * r * (2.0 - r);
}

double prefilter_kernel_integral(double alpha) {
    const double a2 = alpha * alpha;
    // At alpha = 1, D = 1 / pi and Z = 2 int_0^1 c dc = 1; the closed form's terms cancel
    // towards it, and within 1e-3 of it a linear step off 1 is closer than their difference.
    if (a2 > 0.999) {
        return 1.0 + 2.0 / 3.0 * (1.0 - a2);
    }
    const double d = a2 - 1.0;
    return 8.0 * a2 / (d * d) * (std::log(2.0 * a2 / (1.0 + a2)) + (1.0 - a2) / (2.0 * a2));
}

double prefilter_kernel(double alpha, double r_dot_l) {
    return r_dot_l > 0.0 ? sampling::ggx_distribution(alpha * alpha, 0.5 * (1.0 + r_dot_l)) *
                               r_dot_l / prefilter_kernel_integral(alpha)
                         : 0.0;
}

double light_core_correction(double roughness, int levels, const LightSpread& spread,
                             double r_dot_l) {
    const double lod = light_lod(roughness, levels, spread);
    const int below = int(std::floor(lod));
    if (below < 2 || below >= levels - 1) {
        return 0.0;
    }
    const double w = lod - below;
    const double r = std::clamp(roughness, 0.0, 1.0);
    const auto level_kernel = [&](int level) {
        return prefilter_kernel(std::pow(roughness_of_level(level, levels), 2.0), r_dot_l);
    };
    return prefilter_kernel(r * r, r_dot_l) -
           ((1.0 - w) * level_kernel(below) + w * level_kernel(below + 1));
}

glm::dvec3 light_core_energy(const Light& light, const LightSpread& spread, int levels) {
    // Under four levels light_core_correction is 0 everywhere (it starts at the second level
    // and stops below the last).
    if (levels < 4) {
        return glm::dvec3(0.0);
    }
    const glm::dvec3 energy = spread.core_share * light.intensity;
    const double peak = std::max({energy.r, energy.g, energy.b}) *
                        prefilter_kernel(std::pow(roughness_of_level(2, levels), 2.0), 1.0);
    return std::isfinite(peak) && peak <= double(kMaxHalf) ? energy : glm::dvec3(0.0);
}

double light_cap_tan2(double angular_radius) {
    // At least a microradian: a light has pixels, and T > 0 keeps light_lod's shares defined.
    return std::pow(std::tan(0.5 * std::clamp(angular_radius, 1e-6, 3.0)), 2.0);
}

LightSpread light_spread(double angular_radius, const LightProfile& profile) {
    return {profile.core_share, light_cap_tan2(std::min(angular_radius, kLightCoreAngularRadius)),
            light_cap_tan2(std::min(angular_radius, profile.glow_angular_radius))};
}

LightSpread disc_spread(double angular_radius) {
    const double cap_tan2 = light_cap_tan2(angular_radius);
    return {0.0, cap_tan2, cap_tan2};
}

double light_lod(double roughness, int levels, const LightSpread& spread) {
    const double lod = lod_of_roughness(roughness, levels);
    const int below = int(std::floor(lod));
    if (below >= levels - 1) {
        return double(levels - 1);
    }
    // The peak over the light's energy, up to 1 / (4 pi): M = (1 + T) / (alpha^2 + T) per disc.
    const auto peak = [&spread](double r) {
        const double a2 = std::pow(r, 4.0);
        return spread.core_share * (1.0 + spread.core_cap_tan2) / (a2 + spread.core_cap_tan2) +
               (1.0 - spread.core_share) * (1.0 + spread.glow_cap_tan2) /
                   (a2 + spread.glow_cap_tan2);
    };
    const double sharp = peak(roughness_of_level(below, levels));
    const double span = peak(roughness_of_level(below + 1, levels)) - sharp;
    // Peaks within 1e-4 of each other (a light far larger than both lobes): the levels agree,
    // any weight will do, and the lod's fraction is better conditioned.
    if (std::abs(span) < 1e-4 * sharp) {
        return lod;
    }
    return below + std::clamp((peak(std::clamp(roughness, 0.0, 1.0)) - sharp) / span, 0.0, 1.0);
}

PrefilteredCube prefilter_map(const HdrImage& map, const SpecularOptions& options) {
    validate_options(options);
    validate_map(map);
    return prefilter(map, options);
}

PrefilteredCube prefilter_residual(const HdrImage& map, const Rig& rig,
                                   const SpecularOptions& options) {
    validate_rig_map(map, rig, options);
    HdrImage residual = map;
    for (const Light& light : rig.lights) {
        for (const std::uint32_t index : light.pixels) {
            residual.set(index, glm::vec3(0.0f));
        }
    }
    return prefilter(residual, options);
}

PrefilteredLights prefilter_lights(const HdrImage& map, const Rig& rig,
                                   const SpecularOptions& options) {
    validate_rig_map(map, rig, options);
    // The lights' cube has the residual's levels, so that one lod reads both.
    const int min_light_face = 1 << (options.levels - 1);
    if (!is_power_of_two(options.light_face_size) || options.light_face_size < min_light_face ||
        options.light_face_size > options.face_size) {
        invalid("specular cube: light_face_size " + std::to_string(options.light_face_size) +
                " is not a power of two in [" + std::to_string(min_light_face) + ", " +
                std::to_string(options.face_size) + "] (levels " + std::to_string(options.levels) +
                ", face_size " + std::to_string(options.face_size) + ")");
    }
    // Which pixels of each light lie above the horizon, and so which lights need a floor layer.
    const equirect::Grid grid(map.width, map.height);
    const auto above_horizon = [&](std::uint32_t index) { return grid.direction(index).y > 0.0; };
    PrefilteredLights result;
    int layers = int(rig.lights.size());
    for (std::size_t k = 0; k < rig.lights.size(); ++k) {
        const std::vector<std::uint32_t>& pixels = rig.lights[k].pixels;
        const auto above = std::count_if(pixels.begin(), pixels.end(), above_horizon);
        result.floor_layers.push_back(above == std::ptrdiff_t(pixels.size()) ? int(k)
                                      : above == 0                           ? -1
                                                                             : layers++);
    }
    result.cube = allocate_cube(options.light_face_size, options.levels, layers);
    // One map holds each light's pixels (or those above the horizon) in turn, black elsewhere.
    HdrImage alone(map.width, map.height);
    const auto prefilter_pixels = [&](std::size_t k, int layer, bool only_above) {
        for (const std::uint32_t index : rig.lights[k].pixels) {
            if (!only_above || above_horizon(index)) {
                alone.set(index, map.rgb(index));
            }
        }
        prefilter_light_into(alone, light_support(rig.lights[k], map, result.cube.face_size),
                             result.cube, layer);
        for (const std::uint32_t index : rig.lights[k].pixels) {
            alone.set(index, glm::vec3(0.0f));
        }
    };
    for (std::size_t k = 0; k < rig.lights.size(); ++k) {
        prefilter_pixels(k, int(k), false);
        if (result.floor_layers[k] >= int(rig.lights.size())) {
            prefilter_pixels(k, result.floor_layers[k], true);
        }
    }
    return result;
}

SpecularEnvironment prefilter_specular(const HdrImage& map, const Rig& rig,
                                       const SpecularOptions& options) {
    PrefilteredLights lights = prefilter_lights(map, rig, options);
    return {prefilter_residual(map, rig, options), std::move(lights.cube),
            std::move(lights.floor_layers)};
}

glm::dvec3 sample_cube(const PrefilteredCube& cube, const glm::dvec3& d, double lod, int layer) {
    if (cube.levels < 1 || int(cube.rgb_half.size()) != cube.levels ||
        cube.face_size >> (cube.levels - 1) < 1) {
        invalid("sample_cube: a cube of face_size " + std::to_string(cube.face_size) + ", " +
                std::to_string(cube.levels) + " levels has " +
                std::to_string(cube.rgb_half.size()) + " levels of texels");
    }
    if (layer < 0 || layer >= cube.layers) {
        invalid("sample_cube: layer " + std::to_string(layer) + " of a cube of " +
                std::to_string(cube.layers) + " layers");
    }
    for (int level = 0; level < cube.levels; ++level) {
        const std::size_t expected = std::size_t(cube.layers) * level_values(cube.face_size, level);
        if (cube.rgb_half[std::size_t(level)].size() != expected) {
            invalid("sample_cube: level " + std::to_string(level) + " has " +
                    std::to_string(cube.rgb_half[std::size_t(level)].size()) + " values, not " +
                    std::to_string(expected));
        }
    }
    const detail::CubeFaceCoordinates c = detail::cube_lookup(d);
    const auto read_level = [&](int level) {
        const int n = cube.face_size >> level;
        const std::uint16_t* texels = cube.rgb_half[std::size_t(level)].data() +
                                      std::size_t(layer) * level_values(cube.face_size, level);
        return glm::dvec3(bilinear_face(n, float(c.s), float(c.t), [&](int i, int j) {
            const std::size_t at = ((std::size_t(c.face) * n + j) * n + i) * 3;
            return glm::vec3(glm::unpackHalf1x16(texels[at]), glm::unpackHalf1x16(texels[at + 1]),
                             glm::unpackHalf1x16(texels[at + 2]));
        }));
    };
    const double clamped = std::clamp(lod, 0.0, double(cube.levels - 1));
    const int lower = std::min(int(clamped), cube.levels - 1);
    const double blend = clamped - lower;
    glm::dvec3 result = read_level(lower);
    if (blend > 0.0) {
        result = glm::mix(result, read_level(lower + 1), blend);
    }
    return result;
}

std::string encode_specular_environment(const SpecularEnvironment& environment) {
    std::string out;
    out.reserve(kHeaderBytes + 4 * environment.floor_layers.size() + environment.byte_size());
    out.append(kMagic, 7);
    out.push_back(kVersion);
    for (const PrefilteredCube* cube : {&environment.residual, &environment.lights}) {
        put_u32(out, std::uint32_t(cube->face_size));
        put_u32(out, std::uint32_t(cube->levels));
        put_u32(out, std::uint32_t(cube->layers));
    }
    put_u32(out, std::uint32_t(environment.floor_layers.size()));
    for (const int layer : environment.floor_layers) {
        put_u32(out, std::uint32_t(layer));
    }
    for (const PrefilteredCube* cube : {&environment.residual, &environment.lights}) {
        for (const std::vector<std::uint16_t>& level : cube->rgb_half) {
            for (const std::uint16_t value : level) {
                out.push_back(char(value & 0xffu));
                out.push_back(char(value >> 8));
            }
        }
    }
    return out;
}

SpecularEnvironment decode_specular_environment(std::string_view bytes) {
    const std::string what = "stored specular environment: ";
    if (bytes.size() < kHeaderBytes) {
        invalid(what + "truncated: " + std::to_string(bytes.size()) +
                " bytes, the header alone is " + std::to_string(kHeaderBytes));
    }
    if (bytes.substr(0, 7) != std::string_view(kMagic, 7)) {
        invalid(what + "wrong magic: the bytes do not start with \"OERSPEC\"");
    }
    if (bytes[7] != kVersion) {
        invalid(what + "version '" + std::string(1, bytes[7]) + "' is not the supported '" +
                std::string(1, kVersion) + "'");
    }
    SpecularEnvironment environment;
    std::size_t expected = kHeaderBytes;
    const char* names[2] = {"the residual's cube", "the lights' cube"};
    PrefilteredCube* cubes[2] = {&environment.residual, &environment.lights};
    for (int c = 0; c < 2; ++c) {
        const std::size_t at = 8 + 12 * std::size_t(c);
        const std::uint32_t face_size = get_u32(bytes, at), levels = get_u32(bytes, at + 4),
                            layers = get_u32(bytes, at + 8);
        const std::string cube_what = what + names[c] + ": ";
        if (face_size < 1 || face_size > std::uint32_t(kMaxFaceSize) ||
            !std::has_single_bit(face_size)) {
            invalid(cube_what + "face_size " + std::to_string(face_size) +
                    " is not a power of two in [1, " + std::to_string(kMaxFaceSize) + "]");
        }
        const int max_levels = log2_of(int(face_size)) + 1;
        if (levels < 2 || levels > std::uint32_t(max_levels)) {
            invalid(cube_what + "levels " + std::to_string(levels) + " is not in [2, " +
                    std::to_string(max_levels) + "] for face_size " + std::to_string(face_size));
        }
        // The residual is one cube; the lights' are at most a rig's lights and a floor layer each.
        const std::uint32_t max_layers = c == 0 ? 1 : std::uint32_t(2 * kMaxStoredLights);
        if ((c == 0 && layers != 1) || layers > max_layers) {
            invalid(cube_what + std::to_string(layers) + " layers, at most " +
                    std::to_string(max_layers) + (c == 0 ? " (exactly 1)" : ""));
        }
        cubes[c]->face_size = int(face_size);
        cubes[c]->levels = int(levels);
        cubes[c]->layers = int(layers);
        for (int level = 0; level < int(levels); ++level) {
            expected +=
                std::size_t(layers) * level_values(int(face_size), level) * sizeof(std::uint16_t);
        }
    }
    if (environment.lights.levels != environment.residual.levels) {
        invalid(what + "the lights' cube has " + std::to_string(environment.lights.levels) +
                " levels, the residual's " + std::to_string(environment.residual.levels) +
                ": one lod reads both");
    }
    const std::uint32_t lights = get_u32(bytes, 32);
    if (lights > std::uint32_t(kMaxStoredLights) ||
        lights > std::uint32_t(environment.lights.layers)) {
        invalid(what + std::to_string(lights) + " lights, at most " +
                std::to_string(kMaxStoredLights) + " and at most the lights' cube's " +
                std::to_string(environment.lights.layers) + " layers");
    }
    expected += 4 * std::size_t(lights);
    const std::size_t floor_layers_end = kHeaderBytes + 4 * std::size_t(lights);
    if (bytes.size() < floor_layers_end) {
        invalid(what + "truncated: " + std::to_string(bytes.size()) + " bytes, the header and " +
                std::to_string(lights) + " floor layers take " + std::to_string(floor_layers_end));
    }
    for (std::uint32_t k = 0; k < lights; ++k) {
        const std::int32_t layer = std::int32_t(get_u32(bytes, kHeaderBytes + 4 * std::size_t(k)));
        if (layer < -1 || layer >= environment.lights.layers) {
            invalid(what + "light " + std::to_string(k) + "'s floor layer " +
                    std::to_string(layer) + " is neither -1 nor a layer of the lights' cube (" +
                    std::to_string(environment.lights.layers) + ")");
        }
        environment.floor_layers.push_back(int(layer));
    }
    if (bytes.size() != expected) {
        invalid(what + std::to_string(bytes.size()) + " bytes, but its cubes' sizes take " +
                std::to_string(expected) + (bytes.size() < expected ? " (truncated)" : ""));
    }
    std::size_t offset = floor_layers_end;
    for (int c = 0; c < 2; ++c) {
        PrefilteredCube& cube = *cubes[c];
        for (int level = 0; level < cube.levels; ++level) {
            std::vector<std::uint16_t> texels(std::size_t(cube.layers) *
                                              level_values(cube.face_size, level));
            for (std::size_t i = 0; i < texels.size(); ++i, offset += 2) {
                const std::uint16_t value = std::uint16_t(std::uint8_t(bytes[offset]) |
                                                          (std::uint8_t(bytes[offset + 1]) << 8));
                const bool not_finite = (value & 0x7c00u) == 0x7c00u;
                const bool negative = (value & 0x8000u) != 0 && (value & 0x7fffu) != 0;
                if (not_finite || negative) {
                    invalid(what + names[c] + " level " + std::to_string(level) + " value " +
                            std::to_string(i) + " is " +
                            std::to_string(glm::unpackHalf1x16(value)) +
                            ": texels must be finite and non-negative");
                }
                texels[i] = value;
            }
            cube.rgb_half.push_back(std::move(texels));
        }
    }
    return environment;
}

}  // namespace oer
