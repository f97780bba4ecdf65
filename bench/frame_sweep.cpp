// Frame sweep (sweep 2 of the accuracy report, docs/accuracy.md): rendered frames against the
// reference renderer. Real meshes on the ground under the Blender worlds, rendered as plain SH
// irradiance without shadows (what product viewers ship), as the thesis's pipeline (tone-mapped
// projection, hard shadows), as OER without occlusion (the thesis's lighting, `occlusion` off) and
// as our default, which adds the occlusion of the residual map through the scene's baked transfer,
// and with the light count, SH order and shadow maps varied one at a time; with every light on and,
// on the bunny, the brightest switched off and dimmed to half. Per configuration, the frame time at
// the time size (the renderer's own pass timings, shadow maps cached, and the shadow pass when they
// are new) and, at the compare size, the error against the path-traced reference
// (renderer/reference: no bounce, and one diffuse bounce), over the product's pixels, the ground's,
// and the ground's near the product (where contact shadows and reflected light live) separately,
// each without its silhouette (interior_mask: a pixel there measures anti-aliasing, not light):
// relative RMS of luminance over the means of kErrorBlock x kErrorBlock blocks of pixels
// (frame_metrics.hpp's BlockGrid: edges inside a product measure anti-aliasing too, and a block's
// mean has a kErrorBlock-th of a pixel's reference noise), and model-viewer's render-fidelity
// metric in dB per pixel (frame_metrics.hpp).
//
// A configuration with occlusion is rendered once per bounce mode, its transfer baked in that
// mode, and compared only with the reference of the same mode (bounce none with the direct
// reference, one with the one-bounce reference). A transfer depends on the scene's objects and
// ground alone, so it is baked once per mesh, bounce and ray count, and its bake time recorded.
// On the bunny under three worlds, the transfer's ray count and evaluation order are varied
// around the rule's choice (transfer_ray_count, transfer_order), to check the rule.
//
// The reference's Monte Carlo noise must stay below a fifth of every error it measures: each
// reference starts at --min-samples (1024) and is rendered again, with the samples its measured
// noise predicts, while that noise is above a fifth of the smallest error measured against it,
// up to --max-samples (32768); every row records its noise ratio, so that a comparison that
// stays noisy is marked, never hidden.
//
//   frame_sweep --out DIR [--quick] [--mesh-dir DIR] [--min-samples N] [--max-samples N]
//               [--worlds NAME,NAME] [--meshes NAME,NAME] (only those: to look again at one)
// writes DIR/frame_sweep.json, DIR/frame_sweep.csv and DIR/images/*.png (the report's
// side-by-side images). --mesh-dir holds horse.glb and cat.glb, converted from glmark2's .3ds
// files and stood upright by scripts/accuracy-report.sh (assimp export, then
// docs/accuracy/upright_glb.py); without it those two are skipped.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "bench_renderer.hpp"
#include "bench_support.hpp"
#include "frame_metrics.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/reference/reference_renderer.hpp"
#include "oer/scene/scene_bounds.hpp"
#include "oer/transfer/transfer_bake.hpp"
#include "oer/transfer/transfer_lighting.hpp"
#include "sweep_support.hpp"
#include "targets.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kNoiseFraction = 0.2;      // the reference's noise at most this share of an error
constexpr double kErrorMapFullScale = 0.5;  // error maps saturate at +-50 % of the mean
constexpr int kTimedFrames = 3;             // median of these, shadow maps cached
constexpr int kErrorBlock = 4;              // the error's blocks, in pixels at the compare size

struct MeshSource {
    std::string name;
    std::string path;
};

struct Arguments {
    fs::path out;
    bool quick = false;
    std::optional<fs::path> mesh_dir;
    int min_samples = 1024;
    int max_samples = 32768;
    int compare_size = 128;
    int time_size = 512;
    std::vector<std::string> worlds;  // empty: every world
    std::vector<std::string> meshes;  // empty: every mesh
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
        } else if (flag == "--mesh-dir") {
            arguments.mesh_dir = value(i);
        } else if (flag == "--min-samples") {
            arguments.min_samples = oer::bench::reference_samples(flag, value(i));
        } else if (flag == "--max-samples") {
            arguments.max_samples = oer::bench::reference_samples(flag, value(i));
        } else if (flag == "--worlds") {
            arguments.worlds = oer::bench::split_names(value(i));
        } else if (flag == "--meshes") {
            arguments.meshes = oer::bench::split_names(value(i));
        } else {
            throw oer::Error(oer::ErrorKind::InvalidInput,
                             "unknown argument '" + flag +
                                 "' (takes --out DIR, --quick, --mesh-dir DIR, --min-samples N, "
                                 "--max-samples N, --worlds NAME,NAME, --meshes NAME,NAME)");
        }
    }
    if (arguments.out.empty()) {
        throw oer::Error(oer::ErrorKind::InvalidInput, "--out DIR is required");
    }
    if (arguments.max_samples < arguments.min_samples) {
        throw oer::Error(oer::ErrorKind::InvalidInput, "--max-samples is below --min-samples");
    }
    if (arguments.quick) {
        arguments.min_samples = std::min(arguments.min_samples, 64);
        arguments.max_samples = std::min(arguments.max_samples, 256);
        arguments.compare_size = 64;
        // Timed at the compare size: the quick run's timings are only checked to exist (its
        // ctest), and four frames of 256x256 per configuration were most of its GL time.
        arguments.time_size = 64;
    }
    return arguments;
}

// One way of rendering a frame: the rig's options, the shadow options and whether the residual
// map is occluded, everything else the service's defaults (FrameRequest's).
struct Configuration {
    std::string name;
    std::string family;  // "pipeline", "lights", "order", "shadows" or "transfer"
    oer::RigOptions rig;
    oer::ShadowOptions shadows;
    // The thesis model's lighting is display-referred (tone mapped and normalised before
    // projection): it has no absolute scale, so it is compared after the least-squares scale.
    bool scale_fitted = false;
    bool occlusion = false;
    int transfer_rays = 0;  // with occlusion: rays per point of the bake, 0 for the rule's
};

// The ray counts of the rule's check: around the bunny's 144 (transfer_ray_count),
// each a square (the bake's strata). --quick keeps one, so that the report's table is exercised.
std::vector<int> checked_ray_counts(bool quick) {
    return quick ? std::vector<int>{64} : std::vector<int>{64, 256, 576};
}

std::vector<Configuration> configurations(bool quick) {
    std::vector<Configuration> list;
    list.push_back({"default", "pipeline", {}, {}, false, true});
    list.push_back({"OER, no occlusion", "pipeline", {}, {}, false});
    Configuration plain{"plain SH", "pipeline", {}, {}, false};
    // Order 3 (9 coefficients) without shadows, as product viewers light diffuse surfaces
    // (R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment
    // Maps", SIGGRAPH 2001). The rig still finds the lights, so that switching one off removes
    // its pixels from the map (by linearity, the lights' SH add up to the whole map's).
    plain.rig.sh_order = 3;
    plain.shadows.enabled = false;
    list.push_back(plain);
    Configuration thesis{"thesis", "pipeline", {}, {}, true};
    thesis.rig.model = oer::LightingModel::Thesis;
    thesis.rig.sh_order = 3;
    thesis.shadows.filter = oer::ShadowFilter::Hard;
    list.push_back(thesis);
    for (const int rays : checked_ray_counts(quick)) {
        Configuration c{
            "occlusion, " + std::to_string(rays) + " rays", "transfer", {}, {}, false, true};
        c.transfer_rays = rays;
        list.push_back(c);
    }
    // The transfer is evaluated at the rig's order (transfer_order): varied through the rig.
    for (const int order : {3, 5}) {
        Configuration c{
            "occlusion, order " + std::to_string(order), "transfer", {}, {}, false, true};
        c.rig.sh_order = order;
        list.push_back(c);
    }
    if (quick) {
        return list;
    }
    for (int lights = 0; lights <= 4; ++lights) {
        Configuration c{"lights " + std::to_string(lights), "lights", {}, {}, false};
        c.rig.light_count = lights;
        list.push_back(c);
    }
    Configuration order3{"order 3", "order", {}, {}, false};
    order3.rig.sh_order = 3;
    list.push_back(order3);
    for (const int resolution : {256, 512, 1024, 2048, 4096}) {
        for (const auto filter : {oer::ShadowFilter::Hard, oer::ShadowFilter::Pcf}) {
            const oer::ShadowOptions defaults;
            if (resolution == defaults.resolution && filter == defaults.filter) {
                continue;  // the default
            }
            Configuration c{"shadows " + std::to_string(resolution) +
                                (filter == oer::ShadowFilter::Hard ? " hard" : " pcf"),
                            "shadows",
                            {},
                            {},
                            false};
            c.shadows.resolution = resolution;
            c.shadows.filter = filter;
            list.push_back(c);
        }
    }
    return list;
}

// The light states compared: every light on, and (when the default rig finds a light) its
// brightest light switched off and dimmed to half. Only the pipeline family is rendered in the
// states other than all on.
struct LightState {
    std::string name;
    float first_light_weight = 1.0f;
};
const LightState kAllOn{"all on", 1.0f};
const LightState kFirstOff{"light 1 off", 0.0f};
const LightState kFirstHalf{"light 1 at 0.5", 0.5f};

std::string to_string(oer::Bounce bounce) {
    return bounce == oer::Bounce::None ? "none" : "one";
}

std::string file_stem(const std::string& text) {
    std::string out;
    for (const char c : text) {
        out += std::isalnum(static_cast<unsigned char>(c)) ? char(std::tolower(c)) : '-';
    }
    return out;
}

void write_png(const oer::Rgba8Image& image, const fs::path& path) {
    const std::vector<std::uint8_t> bytes = oer::encode_png(image);
    std::ofstream file(path, std::ios::binary);
    file.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!file) {
        throw oer::Error(oer::ErrorKind::Io, "cannot write " + path.string());
    }
}

// Our frame of one configuration in one state, at the compare size, and its timings.
struct OurFrame {
    const Configuration* configuration = nullptr;
    std::shared_ptr<const oer::Rig> rig;
    // With occlusion, its transfer: compared only with the reference of the transfer's bounce.
    std::shared_ptr<const oer::SceneTransfer> transfer;
    std::vector<float> linear;
    std::vector<double> luminance;
    double frame_ms = 0.0;   // time size, shadow maps cached: median of kTimedFrames
    double shadow_ms = 0.0;  // time size, the shadow pass when the maps are new
};

struct Scene {
    std::string mesh_name;
    std::string world;
    std::shared_ptr<const oer::HdrImage> map;
    std::vector<oer::SceneObject> objects;
};

// With a transfer, the frame occludes the residual map through it, in the transfer's bounce mode.
oer::FrameRequest frame_request(const Scene& scene, std::shared_ptr<const oer::Rig> rig,
                                const Configuration& configuration, const LightState& state,
                                int size,
                                std::shared_ptr<const oer::SceneTransfer> transfer = nullptr) {
    oer::FrameRequest request;
    request.rig = std::move(rig);
    request.environment_map = scene.map;
    request.objects = scene.objects;
    request.width = request.height = size;
    request.shadows = configuration.shadows;
    if (transfer) {
        request.occlusion = true;
        request.bounce = transfer->bounce;
        request.transfer = std::move(transfer);
    }
    if (!request.rig->lights.empty() && state.first_light_weight != 1.0f) {
        request.lights.assign(request.rig->lights.size(), 1.0f);
        request.lights[0] = state.first_light_weight;
    }
    return request;
}

// Per pixel, whether the camera ray through its centre meets the ground plane (y = the scene
// bounds' lowest y, where both renderers put it) within one bounding-sphere radius of the
// objects' footprint (their bounds in x and z): the ground near the product, where its contact
// shadows and the light it reflects land. The camera is the frames' own: the
// request's, or the automatic framing of the scene's bounds as both renderers choose it.
std::vector<std::uint8_t> near_ground_footprint(const oer::FrameRequest& request) {
    const oer::SceneBounds bounds = oer::scene_bounds(request.objects);
    const float aspect = float(request.width) / float(request.height);
    const oer::Camera camera =
        request.camera.value_or(oer::frame_bounds(bounds.box, oer::Camera{}.fov_y, aspect));
    const glm::dvec3 eye(camera.eye);
    const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target) - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double tan_half_fov = std::tan(glm::radians(double(camera.fov_y)) / 2.0);
    const double ground_y = bounds.box.min.y;
    std::vector<std::uint8_t> near(std::size_t(request.width) * std::size_t(request.height), 0);
    for (int y = 0; y < request.height; ++y) {
        for (int x = 0; x < request.width; ++x) {
            const double nx = (2.0 * (x + 0.5) / request.width - 1.0) * tan_half_fov * aspect;
            const double ny = (1.0 - 2.0 * (y + 0.5) / request.height) * tan_half_fov;
            const glm::dvec3 direction = forward + nx * right + ny * up;
            const double t = (ground_y - eye.y) / direction.y;
            if (!(t > 0.0)) {
                continue;  // the ray never comes down to the plane
            }
            const glm::dvec3 point = eye + t * direction;
            // Distance in the plane to the footprint rectangle (0 inside it).
            const double dx =
                std::max({bounds.box.min.x - point.x, 0.0, point.x - bounds.box.max.x});
            const double dz =
                std::max({bounds.box.min.z - point.z, 0.0, point.z - bounds.box.max.z});
            near[std::size_t(y) * std::size_t(request.width) + std::size_t(x)] =
                std::hypot(dx, dz) <= bounds.radius ? 1 : 0;
        }
    }
    return near;
}

// The pixels of `surface` whose four neighbours (within the image) are of it too. A pixel on a
// silhouette is a mixture whose value depends on how a renderer integrates the pixel (ours its
// 2 x 2 supersamples, the reference random points), not on its lighting: on the bunny under
// Blender's studio, whose bright lamp is behind its ears, silhouette pixels made 96 % of the
// product's squared error (relative RMS 0.155 over every pixel, 0.034 inside).
std::vector<std::uint8_t> interior_mask(const std::vector<oer::ReferenceSurface>& surfaces,
                                        int width, int height, oer::ReferenceSurface surface) {
    std::vector<std::uint8_t> mask(surfaces.size(), 0);
    const auto is = [&](int x, int y) {
        return x < 0 || y < 0 || x >= width || y >= height ||
               surfaces[std::size_t(y) * std::size_t(width) + std::size_t(x)] == surface;
    };
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            mask[std::size_t(y) * std::size_t(width) + std::size_t(x)] =
                is(x, y) && is(x - 1, y) && is(x + 1, y) && is(x, y - 1) && is(x, y + 1) ? 1 : 0;
        }
    }
    return mask;
}

// What a reference is compared on: its surfaces' interiors as masks, and its luminance.
struct ReferenceImage {
    oer::ReferenceFrame frame;
    int samples = 0;
    std::vector<double> luminance;
    oer::bench::BlockGrid grid;           // the blocks errors are measured over
    std::vector<double> block_luminance;  // per block, its mean
    std::vector<double> block_noise;      // per block, its mean's Monte Carlo noise
    std::vector<std::uint8_t> object_mask, ground_mask;
    std::vector<std::uint8_t> near_ground_mask;  // the ground pixels near the product
    std::vector<std::uint8_t> surface_mask;      // object or ground
};

ReferenceImage render_reference(const oer::FrameRequest& request, oer::Bounce bounce, int samples) {
    oer::ReferenceOptions options;
    options.bounce = bounce;
    options.samples = samples;
    ReferenceImage image;
    image.frame = oer::render_reference(request, options);
    image.samples = samples;
    image.luminance = oer::bench::frame_luminance(image.frame.linear);
    image.grid = {image.frame.width, image.frame.height, kErrorBlock};
    image.block_luminance = oer::bench::block_means(image.luminance, image.grid);
    image.block_noise = oer::bench::block_noise(image.frame.luminance_noise, image.grid);
    const std::vector<std::uint8_t> near = near_ground_footprint(request);
    const std::vector<oer::ReferenceSurface>& surfaces = image.frame.surfaces;
    const int width = image.frame.width, height = image.frame.height;
    image.object_mask = interior_mask(surfaces, width, height, oer::ReferenceSurface::Object);
    image.ground_mask = interior_mask(surfaces, width, height, oer::ReferenceSurface::Ground);
    for (std::size_t i = 0; i < surfaces.size(); ++i) {
        image.near_ground_mask.push_back(image.ground_mask[i] != 0 ? near[i] : 0);
        image.surface_mask.push_back(surfaces[i] != oer::ReferenceSurface::Background ? 1 : 0);
    }
    return image;
}

// A frame's luminance as compared with a reference: for a scale-fitted configuration, times
// the least-squares factor over the reference's object and ground (the thesis's best case).
// Its block means are over the reference's blocks, computed once for every surface.
struct ComparedFrame {
    std::vector<double> luminance;
    std::vector<double> block_luminance;
    double scale = 1.0;
};
ComparedFrame compared(const OurFrame& frame, const ReferenceImage& reference) {
    ComparedFrame out{frame.luminance, {}, 1.0};
    if (frame.configuration->scale_fitted) {
        out.scale = oer::bench::least_squares_scale(frame.luminance, reference.luminance,
                                                    reference.surface_mask);
        for (double& y : out.luminance) {
            y *= out.scale;
        }
    }
    out.block_luminance = oer::bench::block_means(out.luminance, reference.grid);
    return out;
}

// A surface of the reference as compared: its pixels (for the fidelity metric) and its whole
// blocks (for the error), and the reference's relative noise over those blocks.
struct Surface {
    const char* name;
    const std::vector<std::uint8_t>& mask;
    std::vector<std::uint8_t> block_mask;
    double noise;
    std::size_t pixels;
    std::size_t blocks;
};
std::vector<Surface> surfaces_of(const ReferenceImage& reference) {
    std::vector<Surface> list;
    const auto add = [&](const char* name, const std::vector<std::uint8_t>& mask) {
        std::vector<std::uint8_t> blocks = oer::bench::whole_blocks(mask, reference.grid);
        const auto block_count = std::size_t(std::count(blocks.begin(), blocks.end(), 1));
        if (block_count > 0) {
            const double noise = oer::bench::relative_noise(reference.block_noise,
                                                            reference.block_luminance, blocks);
            list.push_back({name, mask, std::move(blocks), noise,
                            std::size_t(std::count(mask.begin(), mask.end(), 1)), block_count});
        }
    };
    add("object", reference.object_mask);
    add("ground", reference.ground_mask);
    add("ground near", reference.near_ground_mask);
    return list;
}

// The relative RMS of luminance of a compared frame over a surface's blocks.
double block_error(const ComparedFrame& frame, const ReferenceImage& reference,
                   const Surface& surface) {
    return oer::bench::relative_rms_error(frame.block_luminance, reference.block_luminance,
                                          surface.block_mask);
}

// Whether `frame` is compared with the reference of `bounce`: a frame without occlusion with
// both, one with occlusion only with the reference of its transfer's mode.
bool compared_in(const OurFrame& frame, oer::Bounce bounce) {
    return !frame.transfer || frame.transfer->bounce == bounce;
}

// The reference for `request`, rendered again with more samples while its noise on a surface
// exceeds kNoiseFraction of the smallest error any of `frames` makes there. Monte Carlo noise
// falls as 1 / sqrt(samples), so the next count is the one that measured noise predicts, with
// a margin (the noise is itself an estimate), in steps of kSampleStep.
ReferenceImage converged_reference(const oer::FrameRequest& request, oer::Bounce bounce,
                                   const std::vector<OurFrame>& frames,
                                   const Arguments& arguments) {
    constexpr double kMargin = 1.25;
    constexpr int kSampleStep = 1024;
    int samples = arguments.min_samples;
    for (;;) {
        ReferenceImage reference = render_reference(request, bounce, samples);
        std::vector<ComparedFrame> compared_frames;
        for (const OurFrame& frame : frames) {
            if (compared_in(frame, bounce)) {
                compared_frames.push_back(compared(frame, reference));
            }
        }
        double needed = 0.0;  // the sample factor that the noisiest surface needs
        for (const Surface& surface : surfaces_of(reference)) {
            double smallest = 1e30;
            for (const ComparedFrame& frame : compared_frames) {
                smallest = std::min(smallest, block_error(frame, reference, surface));
            }
            const double ratio = surface.noise / (kNoiseFraction * smallest);
            needed = std::max(needed, ratio * ratio);
        }
        if (needed < 1.0 || samples >= arguments.max_samples) {
            return reference;
        }
        const double predicted = std::ceil(samples * needed * kMargin / kSampleStep) * kSampleStep;
        samples = int(std::min(predicted, double(arguments.max_samples)));
    }
}

// The rule's check (the "transfer" family) runs on the bunny under three worlds
// (overcast, studio lights, a sunlit forest), which bound the range.
bool checks_the_rule(const Scene& scene) {
    return scene.mesh_name == "bunny" &&
           (scene.world == "courtyard" || scene.world == "studio" || scene.world == "forest");
}

// A configuration's key among a scene's images: its name in lower case, each run of other
// characters one '_' ("plain SH": plain_sh, "OER, no occlusion": oer_no_occlusion).
std::string image_key(const std::string& name) {
    std::string key;
    for (const char c : name) {
        if (std::isalnum(static_cast<unsigned char>(c))) {
            key += char(std::tolower(c));
        } else if (!key.empty() && key.back() != '_') {
            key += '_';
        }
    }
    return key;
}

class Sweep {
  public:
    explicit Sweep(const Arguments& arguments) : arguments_(arguments) {
        fs::create_directories(arguments.out / "images");
    }

    const oer::GlInfo& info() const { return renderer_.info(); }

    void run(const Scene& scene, const std::map<std::string, std::shared_ptr<const oer::Rig>>& rigs,
             const std::vector<Configuration>& list) {
        const std::string stem = file_stem(scene.mesh_name + "-" + scene.world);
        json scene_json = {{"mesh", scene.mesh_name},
                           {"world", scene.world},
                           {"lights_found", rigs.at("default")->lights.size()},
                           {"order", rigs.at("default")->order},
                           {"images", json::object()}};
        std::vector<LightState> states{kAllOn};
        // The switched states for the bunny only: the references they need dominate the run.
        if (!rigs.at("default")->lights.empty() && scene.mesh_name == "bunny") {
            states.push_back(kFirstOff);
            states.push_back(kFirstHalf);
        }
        for (const LightState& state : states) {
            const std::vector<oer::Bounce> bounces =
                state.name == kAllOn.name
                    ? std::vector<oer::Bounce>{oer::Bounce::None, oer::Bounce::One}
                    : std::vector<oer::Bounce>{oer::Bounce::None};
            std::vector<OurFrame> frames;
            for (const Configuration& configuration : list) {
                if ((state.name != kAllOn.name && configuration.family != "pipeline") ||
                    (configuration.family == "transfer" && !checks_the_rule(scene))) {
                    continue;
                }
                const auto& rig = rigs.at(configuration.name);
                if (state.name != kAllOn.name && !same_first_light(*rig, *rigs.at("default"))) {
                    std::printf(
                        "  %s: %s finds another brightest light than the default; not "
                        "compared in state '%s'\n",
                        stem.c_str(), configuration.name.c_str(), state.name.c_str());
                    continue;
                }
                if (!configuration.occlusion) {
                    frames.push_back(render_ours(scene, rig, configuration, state, nullptr));
                    continue;
                }
                for (const oer::Bounce bounce : bounces) {
                    frames.push_back(render_ours(scene, rig, configuration, state,
                                                 transfer(scene.mesh_name, scene.objects, bounce,
                                                          configuration.transfer_rays)));
                }
            }
            const oer::FrameRequest request = frame_request(scene, rigs.at("default"), list.front(),
                                                            state, arguments_.compare_size);
            for (const oer::Bounce bounce : bounces) {
                const ReferenceImage reference =
                    converged_reference(request, bounce, frames, arguments_);
                std::printf(
                    "  %s, %s, bounce %s: reference %d samples (%.1f s), noise object "
                    "%.4f ground %.4f\n",
                    stem.c_str(), state.name.c_str(), to_string(bounce).c_str(), reference.samples,
                    reference.frame.render_ms / 1000.0, reference.frame.noise.object,
                    reference.frame.noise.ground);
                std::fflush(stdout);
                for (const OurFrame& frame : frames) {
                    if (compared_in(frame, bounce)) {
                        add_rows(scene, state, bounce, frame, reference);
                    }
                }
                if (state.name == kAllOn.name) {
                    write_images(stem, bounce, frames, reference, scene_json["images"]);
                }
            }
        }
        // The default's transfer, baked at the rule's ray count, per bounce mode.
        for (const oer::Bounce bounce : {oer::Bounce::None, oer::Bounce::One}) {
            const auto baked = transfer(scene.mesh_name, scene.objects, bounce, 0);
            scene_json["transfer"][to_string(bounce)] = {{"rays", baked->rays},
                                                         {"bake_ms", baked->bake_ms}};
        }
        scenes_.push_back(std::move(scene_json));
    }

    json to_json(const std::string& renderer) const {
        return {{"benchmark", "frame_sweep"},
                {"quick", arguments_.quick},
                {"compare_size", {arguments_.compare_size, arguments_.compare_size}},
                {"time_size", {arguments_.time_size, arguments_.time_size}},
                {"renderer", renderer},
                {"reference",
                 {{"min_samples", arguments_.min_samples},
                  {"max_samples", arguments_.max_samples},
                  {"noise_fraction", kNoiseFraction}}},
                {"scenes", scenes_},
                {"rows", rows_}};
    }

    std::string to_csv() const {
        static const char* const kColumns[] = {"mesh",
                                               "world",
                                               "config",
                                               "family",
                                               "state",
                                               "bounce",
                                               "surface",
                                               "lights",
                                               "order",
                                               "shadow_resolution",
                                               "shadow_filter",
                                               "occlusion",
                                               "transfer_rays",
                                               "transfer_order",
                                               "bake_ms",
                                               "frame_ms",
                                               "shadow_ms",
                                               "relative_rms",
                                               "fidelity_db",
                                               "pixels",
                                               "blocks",
                                               "reference_samples",
                                               "reference_noise",
                                               "noise_ratio",
                                               "scale_fitted"};
        std::string csv;
        for (const char* column : kColumns) {
            csv += std::string(csv.empty() ? "" : ",") + column;
        }
        csv += "\n";
        for (const json& row : rows_) {
            std::string line;
            for (const char* column : kColumns) {
                const json& value = row.at(column);
                line += std::string(line.empty() ? "" : ",") +
                        oer::bench::csv_field(value.is_string() ? value.get<std::string>()
                                                                : value.dump());
            }
            csv += line + "\n";
        }
        return csv;
    }

    const json& rows() const { return rows_; }

  private:
    static bool same_first_light(const oer::Rig& rig, const oer::Rig& reference) {
        return !rig.lights.empty() && !reference.lights.empty() &&
               glm::dot(rig.lights[0].direction, reference.lights[0].direction) >
                   std::cos(glm::radians(0.1));
    }

    // The transfer of a mesh's scene (its objects on the ground) in one bounce mode, baked at
    // `rays` per point (0: the rule's) the first time it is asked for. A transfer depends on the
    // objects and the ground, not on the world or the lights: every world of a mesh shares it.
    std::shared_ptr<const oer::SceneTransfer> transfer(const std::string& mesh_name,
                                                       const std::vector<oer::SceneObject>& objects,
                                                       oer::Bounce bounce, int rays) {
        std::shared_ptr<const oer::SceneTransfer>& baked = transfers_[{mesh_name, bounce, rays}];
        if (!baked) {
            oer::FrameRequest request;
            request.objects = objects;
            oer::TransferBakeOptions options;
            options.bounce = bounce;
            options.rays = rays;
            baked =
                std::make_shared<const oer::SceneTransfer>(oer::bake_transfer(request, options));
            std::printf("  %s: transfer baked, bounce %s, %d rays per point, %.0f ms\n",
                        mesh_name.c_str(), to_string(bounce).c_str(), baked->rays, baked->bake_ms);
            std::fflush(stdout);
        }
        return baked;
    }

    OurFrame render_ours(const Scene& scene, const std::shared_ptr<const oer::Rig>& rig,
                         const Configuration& configuration, const LightState& state,
                         const std::shared_ptr<const oer::SceneTransfer>& transfer) {
        OurFrame frame;
        frame.configuration = &configuration;
        frame.rig = rig;
        frame.transfer = transfer;
        oer::FrameRequest request =
            frame_request(scene, rig, configuration, state, arguments_.compare_size, transfer);
        request.linear = true;
        frame.linear = renderer_.render(request).linear;
        frame.luminance = oer::bench::frame_luminance(frame.linear);
        const std::string timing_key =
            configuration.name + (transfer ? ", bounce " + to_string(transfer->bounce) : "");
        if (state.name == kAllOn.name) {
            oer::FrameRequest timed =
                frame_request(scene, rig, configuration, state, arguments_.time_size, transfer);
            // A yaw no earlier frame used: the first frame renders its shadow maps.
            timed.environment_yaw = 1e-3 * double(++yaw_step_);
            frame.shadow_ms = renderer_.render(timed).timings_ms["shadow_pass"];
            std::vector<double> totals;
            for (int i = 0; i < kTimedFrames; ++i) {
                totals.push_back(renderer_.render(timed).timings_ms.at("total"));
            }
            frame.frame_ms = oer::bench::percentile(totals, 0.5);
            timings_[timing_key] = {frame.frame_ms, frame.shadow_ms};
        } else {
            std::tie(frame.frame_ms, frame.shadow_ms) = timings_.at(timing_key);
        }
        return frame;
    }

    void add_rows(const Scene& scene, const LightState& state, oer::Bounce bounce,
                  const OurFrame& frame, const ReferenceImage& reference) {
        const Configuration& c = *frame.configuration;
        const int size = arguments_.compare_size;
        const ComparedFrame ours_compared = compared(frame, reference);
        const oer::Rgba8Image ours = oer::bench::display_image(
            frame.linear, size, size, ours_compared.scale, 0.0, oer::ToneMapper::Neutral);
        const oer::Rgba8Image truth = oer::bench::display_image(reference.frame.linear, size, size,
                                                                1.0, 0.0, oer::ToneMapper::Neutral);
        for (const Surface& surface : surfaces_of(reference)) {
            const double error = block_error(ours_compared, reference, surface);
            rows_.push_back(
                {{"mesh", scene.mesh_name},
                 {"world", scene.world},
                 {"config", c.name},
                 {"family", c.family},
                 {"state", state.name},
                 {"bounce", to_string(bounce)},
                 {"surface", surface.name},
                 {"lights", frame.rig->lights.size()},
                 {"order", frame.rig->order},
                 {"shadow_resolution", c.shadows.resolution},
                 {"shadow_filter", !c.shadows.enabled                            ? "off"
                                   : c.shadows.filter == oer::ShadowFilter::Hard ? "hard"
                                                                                 : "pcf"},
                 {"occlusion", c.occlusion},
                 {"transfer_rays", frame.transfer ? frame.transfer->rays : 0},
                 {"transfer_order", frame.transfer ? oer::transfer_order(*frame.rig) : 0},
                 {"bake_ms", frame.transfer ? frame.transfer->bake_ms : 0.0},
                 {"frame_ms", frame.frame_ms},
                 {"shadow_ms", frame.shadow_ms},
                 {"relative_rms", error},
                 {"fidelity_db", oer::bench::fidelity_db(ours, truth, surface.mask)},
                 {"pixels", surface.pixels},
                 {"blocks", surface.blocks},
                 {"reference_samples", reference.samples},
                 {"reference_noise", surface.noise},
                 {"mean_luminance", oer::bench::masked_mean(ours_compared.luminance, surface.mask)},
                 {"reference_mean_luminance",
                  oer::bench::masked_mean(reference.luminance, surface.mask)},
                 {"noise_ratio", surface.noise / error},
                 {"scale_fitted", c.scale_fitted}});
        }
    }

    // The pipelines' frames and error maps against the direct reference, and the default's
    // against the one-bounce reference (the light it reflects, and its contact shadows).
    void write_images(const std::string& stem, oer::Bounce bounce,
                      const std::vector<OurFrame>& frames, const ReferenceImage& reference,
                      json& images) {
        const int size = arguments_.compare_size;
        const auto save = [&](const std::string& key, const oer::Rgba8Image& image) {
            const std::string name = "images/" + stem + "-" + file_stem(key) + ".png";
            write_png(image, arguments_.out / name);
            images[key] = name;
        };
        const bool one_bounce = bounce == oer::Bounce::One;
        save(one_bounce ? "reference_one_bounce" : "reference",
             oer::bench::display_image(reference.frame.linear, size, size, 1.0, 0.0,
                                       oer::ToneMapper::Neutral));
        for (const OurFrame& frame : frames) {
            const std::string& name = frame.configuration->name;
            if (frame.configuration->family != "pipeline" || !compared_in(frame, bounce) ||
                (one_bounce && name != "default")) {
                continue;
            }
            const std::string key = image_key(name) + (one_bounce ? "_one_bounce" : "");
            const ComparedFrame scaled = compared(frame, reference);
            save(key, oer::bench::display_image(frame.linear, size, size, scaled.scale, 0.0,
                                                oer::ToneMapper::Neutral));
            if (name != "thesis") {
                save("error_" + key,
                     oer::bench::error_map(scaled.luminance, reference.luminance,
                                           reference.surface_mask, size, size, kErrorMapFullScale));
            }
        }
    }

    const Arguments& arguments_;
    oer::bench::BenchRenderer renderer_;
    int yaw_step_ = 0;
    // All on, per configuration (and bounce, with occlusion): frame and shadow pass ms.
    std::map<std::string, std::pair<double, double>> timings_;
    std::map<std::tuple<std::string, oer::Bounce, int>, std::shared_ptr<const oer::SceneTransfer>>
        transfers_;  // per mesh, bounce and rays per point (0: the rule's)
    json scenes_ = json::array();
    json rows_ = json::array();
};

// The reference renderer shades every surface as Lambertian with the material's base colour
// (reference_renderer.hpp): the frames compared with it are shaded so too, so that the sweep
// measures the lighting, not a BRDF the reference does not have (a glTF's metallic-roughness
// material would add a specular term to ours alone).
std::shared_ptr<const oer::Mesh> lambertian(oer::Mesh mesh) {
    for (oer::Material& material : mesh.materials) {
        material.model = oer::ShadingModel::Lambertian;
    }
    return std::make_shared<const oer::Mesh>(std::move(mesh));
}

std::vector<MeshSource> mesh_sources(const Arguments& arguments) {
    std::vector<MeshSource> meshes{{"bunny", "/usr/share/glmark2/models/bunny.obj"}};
    if (arguments.quick) {
        return meshes;
    }
    if (arguments.mesh_dir) {
        meshes.push_back({"horse", (*arguments.mesh_dir / "horse.glb").string()});
        meshes.push_back({"cat", (*arguments.mesh_dir / "cat.glb").string()});
    } else {
        std::printf(
            "frame sweep: no --mesh-dir: horse and cat (glmark2's .3ds converted by "
            "scripts/accuracy-report.sh) are skipped\n");
    }
    meshes.push_back(
        {"engine",
         "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"});
    return meshes;
}

// The meshes the sweep renders: mesh_sources', less those --meshes leaves out.
std::vector<MeshSource> selected_meshes(const Arguments& arguments) {
    std::vector<MeshSource> meshes = mesh_sources(arguments);
    if (!arguments.meshes.empty()) {
        std::erase_if(meshes, [&](const MeshSource& mesh) {
            return std::find(arguments.meshes.begin(), arguments.meshes.end(), mesh.name) ==
                   arguments.meshes.end();
        });
    }
    if (meshes.empty()) {
        throw oer::Error(oer::ErrorKind::InvalidInput, "--meshes selects none of the meshes");
    }
    return meshes;
}

// The worlds each mesh is rendered under: the bunny under every one; the other meshes under the
// three worlds (overcast, studio lights, a sunlit forest), which bound the range.
bool rendered_under(const std::string& mesh, const std::string& world, const Arguments& arguments) {
    if (!arguments.worlds.empty() && std::find(arguments.worlds.begin(), arguments.worlds.end(),
                                               world) == arguments.worlds.end()) {
        return false;
    }
    if (arguments.quick) {
        return world == "forest" || world == "studio";
    }
    return mesh == "bunny" || world == "courtyard" || world == "studio" || world == "forest";
}

// Per scene and bounce mode, on the product and on the ground near it, the default's error
// beside OER's without occlusion and plain SH's, and the target: the default at most
// half of plain SH's, in both modes (each against the reference of its mode).
void print_summary(const json& rows) {
    // (mesh, world, bounce, surface) -> config -> error, all lights on
    std::map<std::tuple<std::string, std::string, std::string, std::string>,
             std::map<std::string, double>>
        errors;
    for (const json& row : rows) {
        if (row.at("state") == "all on" && row.at("family") == "pipeline" &&
            (row.at("surface") == "object" || row.at("surface") == "ground near")) {
            errors[{row.at("mesh"), row.at("world"), row.at("bounce"), row.at("surface")}]
                  [row.at("config")] = row.at("relative_rms");
        }
    }
    std::printf(
        "\nrelative RMS of luminance against the reference of the same bounce, all lights on:\n"
        "  %-8s %-10s %-6s %-12s %9s %9s %9s %10s\n",
        "mesh", "world", "bounce", "surface", "default", "OER", "plain SH", "def/plain");
    bool met = true;
    for (const auto& [key, by_config] : errors) {
        const auto& [mesh, world, bounce, surface] = key;
        const double ratio = by_config.at("default") / by_config.at("plain SH");
        met = met && ratio <= oer::bench::targets::kFrameErrorOverPlainSh;
        std::printf("  %-8s %-10s %-6s %-12s %9.4f %9.4f %9.4f %10.2f\n", mesh.c_str(),
                    world.c_str(), bounce.c_str(), surface.c_str(), by_config.at("default"),
                    by_config.at("OER, no occlusion"), by_config.at("plain SH"), ratio);
    }
    std::printf(
        "\ntarget: the default's error at most %.1fx plain SH's on the product and "
        "the ground near it, every scene, both bounce modes: %s\n",
        oer::bench::targets::kFrameErrorOverPlainSh, met ? "met" : "NOT met");
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Arguments arguments = parse_arguments(argc, argv);
        const std::vector<fs::path> worlds = oer::bench::blender_worlds();
        std::vector<std::pair<MeshSource, std::shared_ptr<const oer::Mesh>>> meshes;
        for (const MeshSource& source : selected_meshes(arguments)) {
            meshes.emplace_back(source, lambertian(oer::load_mesh_file(source.path)));
        }
        const std::vector<Configuration> list = configurations(arguments.quick);
        Sweep sweep(arguments);
        std::printf(
            "oer frame sweep%s: %zu configurations, %zu meshes, %zu worlds; compared at "
            "%dx%d, timed at %dx%d on %s\n",
            arguments.quick ? " (quick)" : "", list.size(), meshes.size(), worlds.size(),
            arguments.compare_size, arguments.compare_size, arguments.time_size,
            arguments.time_size, sweep.info().renderer.c_str());
        const auto started = oer::bench::Clock::now();
        for (const fs::path& world : worlds) {
            const std::string name = world.stem().string();
            if (std::none_of(meshes.begin(), meshes.end(), [&](const auto& mesh) {
                    return rendered_under(mesh.first.name, name, arguments);
                })) {
                continue;
            }
            const oer::LoadedImage loaded = oer::load_image_file(world.string());
            std::map<std::string, std::shared_ptr<const oer::Rig>> rigs;
            for (const Configuration& configuration : list) {
                rigs[configuration.name] = std::make_shared<const oer::Rig>(
                    oer::build_rig(loaded.image, loaded.repaired, configuration.rig));
            }
            const auto map = std::make_shared<const oer::HdrImage>(loaded.image);
            for (const auto& [source, mesh] : meshes) {
                if (!rendered_under(source.name, name, arguments)) {
                    continue;
                }
                sweep.run({source.name, name, map, {{mesh, glm::mat4(1.0f), std::nullopt}}}, rigs,
                          list);
            }
        }
        const json out = sweep.to_json(sweep.info().renderer);
        oer::bench::write_text_file((arguments.out / "frame_sweep.json").string(),
                                    out.dump(1) + "\n");
        oer::bench::write_text_file((arguments.out / "frame_sweep.csv").string(), sweep.to_csv());
        print_summary(out.at("rows"));
        std::printf("frame sweep: %zu rows in %.0f s; %s\n", out.at("rows").size(),
                    oer::bench::ms_since(started) / 1000.0, arguments.out.string().c_str());
        return 0;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "frame_sweep: %s\n", error.what());
        return 1;
    }
}
