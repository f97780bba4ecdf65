// Shadow sweep (the "Soft shadows" section of docs/accuracy.md): one light's shadow as the
// renderer filters it against the path-traced reference (renderer/reference), on the ground and
// on the dress form's base, with nothing else in the comparison.
//
// A light's share of a frame is separated by linearity. Ours: the frame with the light on less
// the frame with it off (its SH and lobes removed, docs/design.md section 2), divided per pixel
// by the same difference with shadows off, is the visibility v the filter gave that pixel. The
// reference: the map with every pixel but the light's own black (so that the path tracer's map
// sampling spends its samples on the light, and its noise is that of the visibility alone), on
// a flat surface divided by the same radiance where that surface sees the whole light (the
// median over the surface's pixels that ours sees fully lit, v >= 0.99: a flat surface's
// unshadowed radiance from a distant light is one constant). Both are direct light only
// (Bounce::None), without the residual map's occlusion, Lambertian.
//
// Per scene (mesh, environment), for the rig's brightest light (largest luminance share):
// - the penumbra: ground pixels (not on a silhouette) whose reference visibility, averaged over
//   3 x 3 pixels against its noise, lies in (0.05, 0.95);
// - error: relative RMS of visibility there, sqrt(sum (v - v_ref)^2 / sum v_ref^2), beside the
//   reference's own noise in the same form (from its per-pixel half-sample estimate);
// - smoothness: the RMS of the high-pass visibility v - G * v (G a Gaussian of sigma 1 pixel,
//   5 x 5 taps) over the penumbra pixels whose taps are all ground: what blotches, steps and
//   grain add. The reference's is corrected for its Monte Carlo noise: the expected energy of
//   its noise through the high-pass filter, sum_j h_j^2 sigma_j^2 per pixel, is subtracted (an
//   unbiased estimate, since the pixels' noises are independent). The ratio ours / reference
//   is 1 for a filter as smooth as the truth.
// - on the dress form, the leak: from a camera close to the stand's base, for every light, the
//   base's top pixels whose ray to the light's centre passes within half the pole's radius of its
//   axis (the middle of the pole's shadow); the mean visibility there, ours and the reference's
//   (a leak: ours above the reference's).
// Shadow maps at 2048 (the default) and 512 texels, the PCF filter.
//
//   shadow_sweep --out DIR [--quick] [--samples N] [--size N] [--worlds NAME,NAME]
// writes DIR/shadow_sweep.json. --quick: 64 x 64 against 64 samples, the default environment
// only (the pipeline check); the full run takes a few minutes on 2 cores, most in the
// references.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "bench_renderer.hpp"
#include "bench_support.hpp"
#include "frame_metrics.hpp"
#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/mesh/default_product.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/reference/reference_renderer.hpp"
#include "sweep_support.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kBunny = "/usr/share/glmark2/models/bunny.obj";
// The dress form's stand (renderer/mesh default_product.cpp): the base's top and radius, the
// pole's radius and height.
constexpr double kBaseTop = 0.03, kBaseRadius = 0.3, kPoleRadius = 0.012, kPoleTop = 0.92;
constexpr double kPenumbraLow = 0.05, kPenumbraHigh = 0.95;
constexpr double kLit = 0.99;  // ours at or above this: the point sees the whole light
constexpr std::size_t kLeastLitPixels = 50;  // of them, to scale the reference by
// Below this the reference's high-pass, less its noise's, is not known well enough to divide by.
constexpr double kLeastReferenceHighPass = 0.005;

struct Arguments {
    fs::path out;
    bool quick = false;
    int samples = 512;
    int size = 256;
    std::vector<std::string> worlds{"default", "studio"};
};

Arguments parse_arguments(int argc, char** argv) {
    Arguments arguments;
    const auto value = [&](int& i) { return oer::bench::flag_value(argc, argv, i); };
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (flag == "--out") {
            arguments.out = value(i);
        } else if (flag == "--quick") {
            arguments.quick = true;
        } else if (flag == "--samples") {
            arguments.samples = oer::bench::reference_samples(flag, value(i));
        } else if (flag == "--size") {
            arguments.size = std::stoi(value(i));
        } else if (flag == "--worlds") {
            arguments.worlds = oer::bench::split_names(value(i));
        } else {
            throw oer::Error(oer::ErrorKind::InvalidInput,
                             "unknown argument '" + flag +
                                 "' (takes --out DIR, --quick, --samples N, --size N, "
                                 "--worlds NAME,NAME)");
        }
    }
    if (arguments.out.empty()) {
        throw oer::Error(oer::ErrorKind::InvalidInput, "--out DIR is required");
    }
    if (arguments.quick) {
        arguments.samples = 64;
        arguments.size = 64;
        arguments.worlds = {"default"};
    }
    return arguments;
}

std::shared_ptr<const oer::Mesh> lambertian(oer::Mesh mesh) {
    for (oer::Material& material : mesh.materials) {
        material.model = oer::ShadingModel::Lambertian;
    }
    return std::make_shared<const oer::Mesh>(std::move(mesh));
}

struct Scene {
    std::string mesh_name, world;
    std::shared_ptr<const oer::HdrImage> map;
    std::shared_ptr<const oer::Rig> rig;
    std::shared_ptr<const oer::Mesh> mesh;
};

oer::FrameRequest base_request(const Scene& scene, int size, std::optional<oer::Camera> camera) {
    oer::FrameRequest request;
    request.rig = scene.rig;
    request.environment_map = scene.map;
    request.objects.push_back({scene.mesh, glm::mat4(1.0f), std::nullopt});
    request.width = request.height = size;
    request.camera = camera;
    request.occlusion = false;
    request.bounce = oer::Bounce::None;
    request.linear = true;
    return request;
}

// Light k's share of our frame, and the visibility our filter gives each pixel (-1 where the
// light does not reach the surface at all).
struct OurLight {
    std::vector<double> share, visibility;
};
OurLight our_light(oer::bench::BenchRenderer& renderer, oer::FrameRequest request,
                   std::size_t light, int shadow_resolution) {
    const auto luminance = [&](float weight, bool shadows) {
        request.lights.assign(request.rig->lights.size(), 1.0f);
        request.lights[light] = weight;
        request.shadows.enabled = shadows;
        request.shadows.resolution = shadow_resolution;
        return oer::bench::frame_luminance(renderer.render(request).linear);
    };
    const std::vector<double> on = luminance(1.0f, true), off = luminance(0.0f, true);
    const std::vector<double> open = luminance(1.0f, false), open_off = luminance(0.0f, false);
    OurLight out;
    for (std::size_t i = 0; i < on.size(); ++i) {
        const double unshadowed = open[i] - open_off[i];
        out.share.push_back(on[i] - off[i]);
        out.visibility.push_back(unshadowed > 1e-6 ? out.share.back() / unshadowed : -1.0);
    }
    return out;
}

// The reference of light k alone: the map black but for its pixels.
oer::ReferenceFrame reference_light(const Scene& scene, oer::FrameRequest request,
                                    std::size_t light, int samples) {
    const oer::Rig& rig = *scene.rig;
    if (rig.source_width != scene.map->width || rig.source_height != scene.map->height) {
        throw oer::Error(oer::ErrorKind::Internal, "the rig's pixels are not the map's");
    }
    auto only = std::make_shared<oer::HdrImage>(scene.map->width, scene.map->height);
    for (const std::uint32_t pixel : rig.lights[light].pixels) {
        for (int c = 0; c < 3; ++c) {
            only->pixels[std::size_t(pixel) * 3 + std::size_t(c)] =
                scene.map->pixels[std::size_t(pixel) * 3 + std::size_t(c)];
        }
    }
    request.environment_map = only;
    oer::ReferenceOptions options;
    options.samples = samples;
    return oer::render_reference(request, options);
}

double median(std::vector<double> values) {
    if (values.empty()) {
        throw oer::Error(oer::ErrorKind::Internal, "no fully lit pixel to scale the reference by");
    }
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2),
                     values.end());
    return values[values.size() / 2];
}

// The reference's visibility over `surface` (a flat surface's pixels): its light share over
// the median share of the pixels ours sees fully lit; and its noise in the same unit.
struct ReferenceVisibility {
    std::vector<double> visibility, noise;
};
ReferenceVisibility reference_visibility(const oer::ReferenceFrame& frame,
                                         const std::vector<std::uint8_t>& surface,
                                         const OurLight& ours) {
    const std::vector<double> share = oer::bench::frame_luminance(frame.linear);
    std::vector<double> lit;
    for (std::size_t i = 0; i < share.size(); ++i) {
        if (surface[i] != 0 && ours.visibility[i] >= kLit) {
            lit.push_back(share[i]);
        }
    }
    if (lit.size() < kLeastLitPixels) {
        return {};  // too little of the surface sees the whole light to scale the reference by
    }
    const double open = median(lit);
    ReferenceVisibility out;
    for (std::size_t i = 0; i < share.size(); ++i) {
        out.visibility.push_back(share[i] / open);
        out.noise.push_back(frame.luminance_noise[i] / open);
    }
    return out;
}

// Pixels of `surface` whose neighbours within `radius` are all of it too.
std::vector<std::uint8_t> eroded(const std::vector<std::uint8_t>& surface, int size, int radius) {
    std::vector<std::uint8_t> out(surface.size(), 0);
    for (int y = radius; y < size - radius; ++y) {
        for (int x = radius; x < size - radius; ++x) {
            bool all = true;
            for (int dy = -radius; dy <= radius && all; ++dy) {
                for (int dx = -radius; dx <= radius && all; ++dx) {
                    all = surface[std::size_t((y + dy) * size + x + dx)] != 0;
                }
            }
            out[std::size_t(y * size + x)] = all ? 1 : 0;
        }
    }
    return out;
}

// The 5 x 5 Gaussian of sigma 1 pixel, normalised.
std::array<double, 25> gaussian_taps() {
    std::array<double, 25> taps{};
    double sum = 0.0;
    for (int dy = -2; dy <= 2; ++dy) {
        for (int dx = -2; dx <= 2; ++dx) {
            sum += taps[std::size_t((dy + 2) * 5 + dx + 2)] = std::exp(-0.5 * (dx * dx + dy * dy));
        }
    }
    for (double& tap : taps) {
        tap /= sum;
    }
    return taps;
}

struct Penumbra {
    std::size_t pixels = 0;
    double error = 0.0, noise = 0.0;  // relative RMS of visibility
    double high_pass = 0.0, reference_high_pass = 0.0, reference_high_pass_raw = 0.0;
};

Penumbra measure_penumbra(const OurLight& ours, const ReferenceVisibility& reference,
                          const std::vector<std::uint8_t>& ground, int size) {
    const std::vector<std::uint8_t> inner = eroded(ground, size, 2);
    const std::array<double, 25> taps = gaussian_taps();
    Penumbra out;
    double error = 0.0, noise = 0.0, truth = 0.0, ours_hp = 0.0, reference_hp = 0.0, noise_hp = 0.0;
    for (int y = 2; y < size - 2; ++y) {
        for (int x = 2; x < size - 2; ++x) {
            const auto i = std::size_t(y * size + x);
            if (inner[i] == 0) {
                continue;
            }
            double mean = 0.0;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    mean += reference.visibility[std::size_t((y + dy) * size + x + dx)] / 9.0;
                }
            }
            if (mean <= kPenumbraLow || mean >= kPenumbraHigh) {
                continue;
            }
            ++out.pixels;
            error += std::pow(ours.visibility[i] - reference.visibility[i], 2);
            noise += std::pow(reference.noise[i], 2);
            truth += std::pow(reference.visibility[i], 2);
            double ours_low = 0.0, reference_low = 0.0;
            for (int dy = -2; dy <= 2; ++dy) {
                for (int dx = -2; dx <= 2; ++dx) {
                    const auto j = std::size_t((y + dy) * size + x + dx);
                    const double tap = taps[std::size_t((dy + 2) * 5 + dx + 2)];
                    ours_low += tap * ours.visibility[j];
                    reference_low += tap * reference.visibility[j];
                    const double h = (j == i ? 1.0 : 0.0) - tap;
                    noise_hp += h * h * std::pow(reference.noise[j], 2);
                }
            }
            ours_hp += std::pow(ours.visibility[i] - ours_low, 2);
            reference_hp += std::pow(reference.visibility[i] - reference_low, 2);
        }
    }
    if (out.pixels == 0) {
        return out;
    }
    const double n = double(out.pixels);
    out.error = std::sqrt(error / truth);
    out.noise = std::sqrt(noise / truth);
    out.high_pass = std::sqrt(ours_hp / n);
    out.reference_high_pass_raw = std::sqrt(reference_hp / n);
    out.reference_high_pass = std::sqrt(std::max(0.0, reference_hp - noise_hp) / n);
    return out;
}

std::vector<std::uint8_t> surface_mask(const oer::ReferenceFrame& frame,
                                       oer::ReferenceSurface surface) {
    std::vector<std::uint8_t> mask;
    for (const oer::ReferenceSurface s : frame.surfaces) {
        mask.push_back(s == surface ? 1 : 0);
    }
    return mask;
}

// The camera close to the dress form's base, and per pixel the point where its ray meets the
// base's top (nothing where it misses the top or sees the pole).
const oer::Camera kBaseCamera{
    {0.25f, 0.55f, 0.45f}, {0.0f, float(kBaseTop), 0.0f}, {0, 1, 0}, 45.0f};
std::vector<std::optional<glm::dvec3>> base_top_points(int size) {
    const oer::Camera& camera = kBaseCamera;
    const glm::dvec3 eye(camera.eye);
    const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target) - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double tan_half_fov = std::tan(glm::radians(double(camera.fov_y)) / 2.0);
    std::vector<std::optional<glm::dvec3>> points;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const double nx = (2.0 * (x + 0.5) / size - 1.0) * tan_half_fov;
            const double ny = (1.0 - 2.0 * (y + 0.5) / size) * tan_half_fov;
            const glm::dvec3 direction = forward + nx * right + ny * up;
            const glm::dvec3 p = eye + (kBaseTop - eye.y) / direction.y * direction;
            const double r = std::hypot(p.x, p.z);
            points.push_back(r < kBaseRadius - 0.01 && r > 2.0 * kPoleRadius
                                 ? std::optional<glm::dvec3>(p)
                                 : std::nullopt);
        }
    }
    return points;
}

// Whether the ray from p towards the light passes within `reach` of the pole's axis below its top.
bool behind_pole(const glm::dvec3& p, const glm::dvec3& light, double reach) {
    const glm::dvec2 d(light.x, light.z);
    const double along = glm::dot(d, d);
    if (along < 1e-9) {
        return false;
    }
    const double t = -glm::dot(glm::dvec2(p.x, p.z), d) / along;
    const glm::dvec2 closest = glm::dvec2(p.x, p.z) + t * d;
    return t > 0.0 && glm::length(closest) < reach && p.y + t * light.y < kPoleTop;
}

class Sweep {
  public:
    explicit Sweep(const Arguments& arguments) : arguments_(arguments) {}
    const oer::GlInfo& info() const { return renderer_.info(); }

    void penumbra(const Scene& scene) {
        const std::size_t light = brightest(*scene.rig);
        const oer::FrameRequest request = base_request(scene, arguments_.size, std::nullopt);
        const oer::ReferenceFrame frame =
            reference_light(scene, request, light, arguments_.samples);
        std::vector<std::uint8_t> ground = surface_mask(frame, oer::ReferenceSurface::Ground);
        // Only the floor drawn whole: farther out it fades into the background
        // (SceneBounds::ground_weight), which the reference composes by the same weight but
        // our visibility, a ratio of our own frames, does not see. Its coverage is the alpha of
        // a frame over transparency.
        oer::FrameRequest coverage = request;
        coverage.background.kind = oer::BackgroundKind::Transparent;
        coverage.shadows.enabled = false;
        const std::vector<float> covered = renderer_.render(coverage).linear;
        for (std::size_t i = 0; i < ground.size(); ++i) {
            if (covered[i * 4 + 3] < 1.0f) {
                ground[i] = 0;
            }
        }
        for (const int resolution : {2048, 512}) {
            const OurLight ours = our_light(renderer_, request, light, resolution);
            const ReferenceVisibility reference = reference_visibility(frame, ground, ours);
            if (reference.visibility.empty()) {
                continue;
            }
            const Penumbra p = measure_penumbra(ours, reference, ground, arguments_.size);
            const double ratio = p.reference_high_pass >= kLeastReferenceHighPass
                                     ? p.high_pass / p.reference_high_pass
                                     : NAN;
            std::printf(
                "  %-6s %-8s light %zu, %4d: penumbra %5zu px, error %.4f (reference noise "
                "%.4f), high-pass %.4f against %.4f (raw %.4f): ratio %.2f\n",
                scene.mesh_name.c_str(), scene.world.c_str(), light + 1, resolution, p.pixels,
                p.error, p.noise, p.high_pass, p.reference_high_pass, p.reference_high_pass_raw,
                ratio);
            rows_.push_back({{"kind", "penumbra"},
                             {"mesh", scene.mesh_name},
                             {"world", scene.world},
                             {"light", light + 1},
                             {"shadow_resolution", resolution},
                             {"pixels", p.pixels},
                             {"relative_rms", p.error},
                             {"reference_noise", p.noise},
                             {"high_pass", p.high_pass},
                             {"reference_high_pass", p.reference_high_pass},
                             {"reference_high_pass_raw", p.reference_high_pass_raw},
                             {"smoothness_ratio", std::isnan(ratio) ? json() : json(ratio)},
                             {"samples", arguments_.samples},
                             {"size", arguments_.size}});
        }
    }

    void leak(const Scene& scene) {
        const oer::FrameRequest request = base_request(scene, arguments_.size, kBaseCamera);
        const std::vector<std::optional<glm::dvec3>> points = base_top_points(arguments_.size);
        for (std::size_t light = 0; light < scene.rig->lights.size(); ++light) {
            const glm::dvec3 direction = scene.rig->lights[light].direction;
            if (direction.y <= 0.0) {
                continue;
            }
            const oer::ReferenceFrame frame =
                reference_light(scene, request, light, arguments_.samples);
            std::vector<std::uint8_t> top(points.size(), 0), shadow(points.size(), 0);
            for (std::size_t i = 0; i < points.size(); ++i) {
                if (points[i] && frame.surfaces[i] == oer::ReferenceSurface::Object) {
                    top[i] = 1;
                    shadow[i] = behind_pole(*points[i], direction, 0.5 * kPoleRadius) ? 1 : 0;
                }
            }
            const auto pixels = std::size_t(std::count(shadow.begin(), shadow.end(), 1));
            if (pixels == 0) {
                continue;
            }
            for (const int resolution : {2048, 512}) {
                const OurLight ours = our_light(renderer_, request, light, resolution);
                const ReferenceVisibility reference = reference_visibility(frame, top, ours);
                if (reference.visibility.empty()) {
                    continue;
                }
                const double mean = oer::bench::masked_mean(ours.visibility, shadow);
                const double reference_mean = oer::bench::masked_mean(reference.visibility, shadow);
                // A visibility over 1 is no visibility: the base's fully lit pixels (by ours)
                // that scale the reference do not see this light whole in the reference.
                if (reference_mean > 1.05) {
                    std::printf(
                        "  %-6s %-8s light %zu, %4d: the pole's shadow on the base: the "
                        "reference's scale failed (visibility %.3f), left out\n",
                        scene.mesh_name.c_str(), scene.world.c_str(), light + 1, resolution,
                        reference_mean);
                    continue;
                }
                std::printf(
                    "  %-6s %-8s light %zu, %4d: the pole's shadow on the base, %zu px: "
                    "visibility %.3f against %.3f\n",
                    scene.mesh_name.c_str(), scene.world.c_str(), light + 1, resolution, pixels,
                    mean, reference_mean);
                rows_.push_back({{"kind", "leak"},
                                 {"mesh", scene.mesh_name},
                                 {"world", scene.world},
                                 {"light", light + 1},
                                 {"shadow_resolution", resolution},
                                 {"pixels", pixels},
                                 {"visibility", mean},
                                 {"reference_visibility", reference_mean},
                                 {"samples", arguments_.samples},
                                 {"size", arguments_.size}});
            }
        }
    }

    json to_json() const {
        return {{"renderer", info().renderer}, {"quick", arguments_.quick}, {"rows", rows_}};
    }

  private:
    static std::size_t brightest(const oer::Rig& rig) {
        if (rig.lights.empty()) {
            throw oer::Error(oer::ErrorKind::InvalidInput, "the rig finds no light");
        }
        std::size_t best = 0;
        for (std::size_t k = 1; k < rig.lights.size(); ++k) {
            if (rig.lights[k].luminance_share > rig.lights[best].luminance_share) {
                best = k;
            }
        }
        return best;
    }

    const Arguments& arguments_;
    oer::bench::BenchRenderer renderer_;
    json rows_ = json::array();
};

}  // namespace

int main(int argc, char** argv) {
    try {
        const Arguments arguments = parse_arguments(argc, argv);
        std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress as it comes, into a log too
        fs::create_directories(arguments.out);
        Sweep sweep(arguments);
        std::printf("oer shadow sweep%s: %dx%d against %d samples on %s\n",
                    arguments.quick ? " (quick)" : "", arguments.size, arguments.size,
                    arguments.samples, sweep.info().renderer.c_str());
        const auto started = oer::bench::Clock::now();
        const auto bunny = lambertian(oer::load_mesh_file(kBunny));
        const auto dress_form = lambertian(oer::make_default_product());
        for (const std::string& world : arguments.worlds) {
            std::shared_ptr<const oer::HdrImage> map;
            std::shared_ptr<const oer::Rig> rig;
            if (world == "default") {
                map = std::make_shared<const oer::HdrImage>(oer::make_default_environment());
                rig = std::make_shared<const oer::Rig>(oer::build_rig(*map, {}, {}));
            } else {
                const oer::LoadedImage loaded = oer::load_image_file(
                    (fs::path(oer::bench::kBlenderWorldDirectory) / (world + ".exr")).string());
                map = std::make_shared<const oer::HdrImage>(loaded.image);
                rig = std::make_shared<const oer::Rig>(
                    oer::build_rig(loaded.image, loaded.repaired, {}));
            }
            sweep.penumbra({"bunny", world, map, rig, bunny});
            sweep.penumbra({"dress form", world, map, rig, dress_form});
            sweep.leak({"dress form", world, map, rig, dress_form});
        }
        oer::bench::write_text_file((arguments.out / "shadow_sweep.json").string(),
                                    sweep.to_json().dump(1) + "\n");
        std::printf("shadow sweep: %.0f s; %s\n", oer::bench::ms_since(started) / 1000.0,
                    arguments.out.string().c_str());
        return 0;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "shadow_sweep: %s\n", error.what());
        return 1;
    }
}
