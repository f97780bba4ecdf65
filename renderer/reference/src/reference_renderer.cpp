#include "oer/reference/reference_renderer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <thread>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>

#include "environment_sampler.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/light_location.hpp"
#include "oer/lighting/sampling.hpp"
#include "oer/mesh/camera_rays.hpp"
#include "oer/reference/embree_scene.hpp"
#include "oer/reference/metallic_roughness_brdf.hpp"
#include "oer/reference/pixel_random.hpp"

namespace oer {

namespace {

using reference::EmbreeScene;
using reference::EnvironmentSampler;
using reference::PixelRandom;
using reference::SurfaceHit;

constexpr double kPi = std::numbers::pi;

// The renderer's environment background (shade.frag, SURFACE 0): the request's map as given,
// turned by the yaw, sampled bilinearly, repeating across the seam and clamped at the poles
// as its texture is.
glm::dvec3 background_radiance(const HdrImage& map, const glm::dvec3& world_direction,
                               double yaw_degrees) {
    const glm::dvec3 d = equirect::rotate_yaw(world_direction, -yaw_degrees);
    const double u = (std::atan2(d.z, d.x) + kPi) / (2.0 * kPi);
    const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
    const double x = u * map.width - 0.5, y = v * map.height - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const auto texel = [&map](long long tx, long long ty) {
        const long long w = map.width;
        const int column = int((tx % w + w) % w);
        const int row = int(std::clamp(ty, 0LL, (long long)map.height - 1));
        const float* p = map.at(column, row);
        return glm::dvec3(p[0], p[1], p[2]);
    };
    const long long ix = (long long)x0, iy = (long long)y0;
    return (1 - fy) * ((1 - fx) * texel(ix, iy) + fx * texel(ix + 1, iy)) +
           fy * ((1 - fx) * texel(ix, iy + 1) + fx * texel(ix + 1, iy + 1));
}

// Veach's power heuristic (beta = 2) for the strategy of density `chosen` against `other`.
double power_heuristic(double chosen, double other) {
    const double a = chosen * chosen, b = other * other;
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

class Tracer {
  public:
    Tracer(const EmbreeScene& scene, const EnvironmentSampler& environment,
           const ReferenceOptions& options, double offset)
        : scene_(scene), environment_(environment), options_(options), offset_(offset) {}

    // An estimate of the radiance a hit sends towards `viewer` (unit): its emission and the
    // light it reflects by its BRDF (metallic_roughness_brdf.hpp), L_in from the environment
    // where the way out is free and, while `bounces` remain, from the surface seen elsewhere
    // (itself lit the same way with one bounce fewer): a chrome bowl's inside reflects itself.
    glm::dvec3 outgoing(const SurfaceHit& hit, const glm::dvec3& viewer, PixelRandom& random,
                        int bounces) const {
        if (hit.unlit) {
            return hit.material.base_color;
        }
        const reference::MetallicRoughnessBrdf brdf(hit.material, hit.shading_normal, viewer);
        glm::dvec3 sum = hit.emissive;
        const bool mis = options_.sampling == ReferenceSampling::Mis && environment_.can_sample();
        if (mis) {
            const reference::EnvironmentSample light =
                environment_.sample(random.uniform(), random.uniform(), random.uniform());
            const double cosine = glm::dot(hit.shading_normal, light.direction);
            if (cosine > 0.0 && light.pdf > 0.0 &&
                !scene_.occluded(leave(hit, light.direction), light.direction, 0.0,
                                 reference::GroundReach::Infinite)) {
                sum += light.radiance * brdf.evaluate(light.direction) *
                       (cosine / light.pdf * power_heuristic(light.pdf, brdf.pdf(light.direction)));
            }
        }
        // A Lambertian surface has one lobe: no draw chooses it.
        const double lobe = hit.material.glossy ? random.uniform() : 1.0;
        const double u1 = random.uniform(), u2 = random.uniform();
        const std::optional<reference::BrdfSample> sample = brdf.sample(lobe, u1, u2);
        if (!sample) {
            return sum;
        }
        const glm::dvec3& direction = sample->direction;
        const std::optional<SurfaceHit> next = scene_.intersect(
            leave(hit, direction), direction, 0.0, reference::GroundReach::Infinite);
        if (!next) {
            const double weight =
                mis ? power_heuristic(sample->pdf, environment_.pdf(direction)) : 1.0;
            sum += environment_.radiance(direction) * sample->weight * weight;
        } else if (bounces > 0) {
            sum += sample->weight * outgoing(*next, -direction, random, bounces - 1);
        }
        return sum;
    }

  private:
    // The origin of a ray leaving a hit: off the surface, on the side the ray goes, by the
    // scene's offset (a fixed fraction of its size, far above float rounding at its scale).
    glm::dvec3 leave(const SurfaceHit& hit, const glm::dvec3& direction) const {
        const double side = glm::dot(hit.geometric_normal, direction) >= 0.0 ? 1.0 : -1.0;
        return hit.position + (side * offset_) * hit.geometric_normal;
    }

    const EmbreeScene& scene_;
    const EnvironmentSampler& environment_;
    const ReferenceOptions& options_;
    double offset_;
};

void validate(const FrameRequest& request, const ReferenceOptions& options) {
    if (!request.rig) {
        throw Error(ErrorKind::InvalidInput, "reference: the request has no rig");
    }
    if (!request.environment_map) {
        throw Error(ErrorKind::InvalidInput,
                    "reference: the request has no environment map (the reference lights with "
                    "the map itself, not its rig)");
    }
    if (request.width < 1 || request.height < 1) {
        throw Error(ErrorKind::InvalidInput, "reference: the frame is " +
                                                 std::to_string(request.width) + "x" +
                                                 std::to_string(request.height));
    }
    if (request.ground && request.ground_look != GroundLook::Opaque) {
        throw Error(ErrorKind::InvalidInput,
                    "reference: the reference draws the opaque ground only (a shadow catcher "
                    "is a ratio of two renderings, with and without the objects)");
    }
    if (options.samples < 2 || options.samples % 2 != 0) {
        throw Error(ErrorKind::InvalidInput,
                    "reference: samples must be even and at least 2 (two independent halves "
                    "estimate the noise), got " +
                        std::to_string(options.samples));
    }
    if (options.threads < 0) {
        throw Error(ErrorKind::InvalidInput,
                    "reference: threads must be 0 (every core) or more, got " +
                        std::to_string(options.threads));
    }
}

// The relative RMS noise of ReferenceNoise over the pixels of one surface kind.
double relative_noise(const std::vector<double>& halves_a, const std::vector<double>& halves_b,
                      const std::vector<ReferenceSurface>& surfaces, ReferenceSurface kind,
                      std::size_t& pixels) {
    double noise = 0.0, signal = 0.0;
    pixels = 0;
    for (std::size_t i = 0; i < surfaces.size(); ++i) {
        if (surfaces[i] != kind) {
            continue;
        }
        ++pixels;
        const double mean = 0.5 * (halves_a[i] + halves_b[i]);
        const double error = 0.5 * (halves_a[i] - halves_b[i]);
        noise += error * error;
        signal += mean * mean;
    }
    return signal > 0.0 ? std::sqrt(noise / signal) : 0.0;
}

}  // namespace

ReferenceFrame render_reference(const FrameRequest& request, const ReferenceOptions& options) {
    validate(request, options);
    const auto start = std::chrono::steady_clock::now();
    const int width = request.width, height = request.height;
    const SceneBounds frame = scene_bounds(request.objects);
    const EmbreeScene scene(request, frame);
    const EnvironmentSampler environment(*request.environment_map, *request.rig, request.lights,
                                         request.environment_yaw);
    const Camera camera =
        request.camera.value_or(frame_bounds(frame.box, 45.0f, float(width) / float(height)));
    const CameraRays rays = camera_rays(camera, width, height);
    const Tracer tracer(scene, environment, options, 1e-4 * double(frame.radius));
    const bool environment_background = request.background.kind == BackgroundKind::Environment;

    ReferenceFrame result;
    result.width = width;
    result.height = height;
    const std::size_t pixel_count = std::size_t(width) * std::size_t(height);
    result.linear.assign(pixel_count * 4, 0.0f);
    result.surfaces.assign(pixel_count, ReferenceSurface::Background);
    result.luminance_noise.assign(pixel_count, 0.0);
    std::vector<double> luminance_a(pixel_count, 0.0), luminance_b(pixel_count, 0.0);
    const int half = options.samples / 2;
    const int bounces = options.bounce == Bounce::One ? 1 : 0;

    const auto render_pixel = [&](int x, int y) {
        const std::size_t index = std::size_t(y) * std::size_t(width) + std::size_t(x);
        if (const auto centre = scene.intersect(rays.eye, rays.direction(x + 0.5, y + 0.5), 0.0,
                                                reference::GroundReach::Drawn)) {
            result.surfaces[index] =
                centre->ground ? ReferenceSurface::Ground : ReferenceSurface::Object;
        }
        PixelRandom random(options.seed, index);
        glm::dvec3 halves[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
        double coverage = 0.0;
        for (int s = 0; s < options.samples; ++s) {
            // A box filter over the pixel: a uniform point in it per sample.
            const glm::dvec3 direction = rays.direction(x + random.uniform(), y + random.uniform());
            const auto hit =
                scene.intersect(rays.eye, direction, 0.0, reference::GroundReach::Drawn);
            // The ground fades into the background far from the scene, as the renderer draws it
            // (SceneBounds::ground_weight); an object or the near ground is all surface.
            const double surface =
                !hit ? 0.0
                     : (hit->ground ? double(frame.ground_weight(float(glm::length(
                                          glm::dvec2(hit->position.x - frame.centre.x,
                                                     hit->position.z - frame.centre.z)))))
                                    : 1.0);
            glm::dvec3 radiance(0.0);
            if (surface > 0.0) {
                radiance = surface * tracer.outgoing(*hit, -direction, random, bounces);
                coverage += surface;
            }
            if (surface < 1.0 && environment_background) {
                radiance +=
                    (1.0 - surface) * background_radiance(*request.environment_map, direction,
                                                          request.environment_yaw);
                coverage += 1.0 - surface;
            }
            halves[s < half ? 0 : 1] += radiance;
        }
        const glm::dvec3 mean = (halves[0] + halves[1]) / double(options.samples);
        float* out = &result.linear[index * 4];
        out[0] = float(mean.r);
        out[1] = float(mean.g);
        out[2] = float(mean.b);
        out[3] = float(coverage / options.samples);
        luminance_a[index] = luminance(halves[0] / double(half));
        luminance_b[index] = luminance(halves[1] / double(half));
        result.luminance_noise[index] = 0.5 * (luminance_a[index] - luminance_b[index]);
    };

    const int thread_count = options.threads > 0
                                 ? options.threads
                                 : std::max(1, int(std::thread::hardware_concurrency()));
    std::atomic<int> next_row{0};
    const auto work = [&] {
        for (int y = next_row++; y < height; y = next_row++) {
            for (int x = 0; x < width; ++x) {
                render_pixel(x, y);
            }
        }
    };
    std::vector<std::thread> workers;
    for (int t = 1; t < thread_count; ++t) {
        workers.emplace_back(work);
    }
    work();
    for (std::thread& worker : workers) {
        worker.join();
    }

    result.noise.object = relative_noise(luminance_a, luminance_b, result.surfaces,
                                         ReferenceSurface::Object, result.noise.object_pixels);
    result.noise.ground = relative_noise(luminance_a, luminance_b, result.surfaces,
                                         ReferenceSurface::Ground, result.noise.ground_pixels);
    result.render_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace oer
