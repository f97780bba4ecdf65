// The transfer bake (transfer_bake.hpp) on the reference renderer's Embree scene, and the rules
// that size it. Formulas: P.-P. Sloan, J. Kautz and J. Snyder, "Precomputed Radiance Transfer
// for Real-Time Rendering in Dynamic, Low-Frequency Lighting Environments", SIGGRAPH 2002,
// section 5 (shadowed diffuse transfer, eq. 8, and its interreflected form, eq. 9, here one
// bounce); the cosine-weighted rays by P. Shirley and K. Chiu, "A Low Distortion Map Between
// Disk and Square", 1997 (oer/lighting/sampling.hpp).
#include "oer/transfer/transfer_bake.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <thread>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "oer/core/cancellation.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/sampling.hpp"
#include "oer/lighting/sh.hpp"
#include "oer/reference/embree_scene.hpp"
#include "oer/reference/pixel_random.hpp"
#include "oer/scene/scene_bounds.hpp"
#include "oer/transfer/transfer_lighting.hpp"

namespace oer {
namespace {

using reference::EmbreeScene;
using reference::GroundReach;
using reference::SurfaceHit;

constexpr int kCoefficients = sh_count(kTransferBakeOrder);
using Coefficients = std::array<double, kCoefficients>;

// The ground grid's texels per side. At 2 scene radii R each side of the centre (below) a texel
// is R / 16: the contact shadow of a sphere of radius r resting on the ground (R = sqrt(3) r)
// falls from full to half occlusion within 0.77 r (its view factor (1 + (d / r)^2)^(-3/2),
// tests/transfer, TransferBakeGround), over 7 texels; 4096 receivers, an eighth of the bunny's
// 35k vertices.
constexpr int kGroundResolution = 64;
// The grid's half side over the scene's bounding radius. The scene radius (half the bounding
// box's diagonal) rather than its horizontal extent alone, because how far a contact shadow
// reaches grows with the object's height too: at the grid's edge, 3.5 radii from the centre, a
// sphere resting on the ground still covers 2 % of the cosine-weighted hemisphere (the view
// factor of tests/transfer), the seam left where the frame goes on with the unoccluded transfer.
constexpr float kGroundHalfSizeOverRadius = 2.0f;
// Rays leave a receiver this far (times the scene radius) along its normal: the reference
// renderer's offset, far above float rounding at the scene's scale.
constexpr double kRayOffsetOverRadius = 1e-4;
// Every receiver's jitter comes from this seed and the receiver's index.
constexpr std::uint64_t kBakeSeed = 1;

// The rule of transfer_ray_count: a ray budget per bake phase shared by every receiver point,
// kTransferRayBudget (6 M) by default.
// Measured with bench/transfer_benchmark on the shared 2-core machine (AMD EPYC, AVX-512; the
// Stanford bunny's 34,835 vertices plus the 4,096 ground texels, 47 % of the rays blocked):
// Bounce::One costs 2.8 to 3.1 s of CPU at 144 rays per point and 3.4 to 3.7 s at 196, i.e.
// 1.4 s and 1.7 s of wall time on 2 free cores (the two threads share the points evenly; the
// bake's wall time on the shared machine, with other builds on both cores, is 2 to 3 times
// that). 144 keeps the bake's 2 s target (docs/design.md section 8) with a margin for the
// machine's noise; its error is about 1 % of the visible fraction (the contact shadow of a sphere
// on the ground, tests/transfer: RMS 0.98 % over 2416 texels at 144 rays, 0.15 % at 2304).
// Stratified rays come in strata x strata cells: 8 x 8 (64) at least, below which the
// occlusion of a single receiver is visibly noisy (the binomial error of a half-occluded point is
// 6 %), and 32 x 32 (1024) at most, where the binomial error is at most 1.6 % and the
// stratified one several times less, below the SH truncation's, so more rays only cost.
constexpr int kMinStrata = 8;
constexpr int kMaxStrata = 32;

// unoccluded_transfer (transfer_lighting.hpp) at the bake's order.
Coefficients unoccluded_coefficients(const glm::dvec3& n) {
    const std::vector<double> transfer = unoccluded_transfer(kTransferBakeOrder, n);
    Coefficients coefficients{};
    std::copy(transfer.begin(), transfer.end(), coefficients.begin());
    return coefficients;
}

// One receiver point: where its rays start and the hemisphere they cover, and where its vectors
// go (its slots in a TransferPoints, sized before the bake starts).
struct Receiver {
    glm::dvec3 position{0.0};
    glm::dvec3 normal{0.0, 1.0, 0.0};
    float* direct = nullptr;  // kCoefficients values
    float* bounce = nullptr;  // kCoefficients values per bounce vector of the reflector slots
    // An object's receiver in a scene with the ground, under Bounce::One: its direct transfer
    // with the plane counted as blocking (kCoefficients values), what it reflects from the map
    // alone, as the one-bounce reference's surfaces do.
    float* sky_direct = nullptr;
};

// SkyDirect[object][primitive]: every vertex's direct transfer with the ground blocking
// (Receiver::sky_direct), point-major as TransferPoints::direct.
using SkyDirect = std::vector<std::vector<std::vector<float>>>;

// The receiver's rays, as points (u1, u2) of the unit square numbered 0 to strata^2 - 1:
// strata x strata jittered cells, which sampling::cosine_direction maps onto the
// cosine-weighted hemisphere of the normal by the concentric map (Shirley and Chiu 1997), so
// the strata stay compact on the hemisphere. The jitter is the receiver's own PCG32 stream
// (seed, receiver index): both phases and any thread count trace the same rays.
template <class Visit>
void for_each_ray(std::uint64_t receiver_index, int strata, Visit&& visit) {
    reference::PixelRandom random(kBakeSeed, receiver_index);
    int ray = 0;
    for (int row = 0; row < strata; ++row) {
        for (int column = 0; column < strata; ++column) {
            const double u1 = (column + random.uniform()) / strata;
            const double u2 = (row + random.uniform()) / strata;
            visit(ray++, u1, u2);
        }
    }
}

// One bit per ray of every receiver: which rays phase 1 found to meet a surface (an object, or
// the ground plane), the only ones phase 2 traces again (an escaping ray reflects nothing). On
// the bunny about 70 % of the rays escape, which phase 2 would otherwise traverse the whole
// scene for again.
class RaysMeetingSurfaces {
  public:
    RaysMeetingSurfaces(std::size_t receivers, int rays)
        : words_per_receiver_((std::size_t(rays) + 63) / 64),
          bits_(receivers * words_per_receiver_, 0) {}
    void set(std::size_t receiver, int ray) {
        bits_[receiver * words_per_receiver_ + std::size_t(ray) / 64] |= 1ull << (ray % 64);
    }
    bool test(std::size_t receiver, int ray) const {
        return (bits_[receiver * words_per_receiver_ + std::size_t(ray) / 64] >> (ray % 64)) & 1u;
    }

  private:
    std::size_t words_per_receiver_;
    std::vector<std::uint64_t> bits_;
};

// Calls work(i) for i in [0, count) on `threads` threads, in chunks taken in turn; what work(i)
// writes depends on i alone, so the result does not depend on the thread count. Each thread
// looks at stop before each chunk: once it is requested no chunk starts, and the call throws
// (Cancelled) after the chunks under way end. Each chunk done is counted in progress, if given.
template <class Work>
void parallel_for(std::size_t count, int threads, const std::stop_token& stop,
                  BakeProgress* progress, const Work& work) {
    std::atomic<std::size_t> next{0};
    const auto run = [&] {
        for (std::size_t start = next.fetch_add(kBakeChunk);
             start < count && !stop.stop_requested(); start = next.fetch_add(kBakeChunk)) {
            const std::size_t end = std::min(count, start + kBakeChunk);
            for (std::size_t i = start; i < end; ++i) {
                work(i);
            }
            if (progress) {
                progress->done += end - start;
            }
        }
    };
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) {
        workers.emplace_back(run);
    }
    run();
    for (std::thread& worker : workers) {
        worker.join();
    }
    throw_if_stopped(stop, "the transfer bake");
}

std::size_t receiver_count(const std::vector<SceneObject>& objects) {
    std::size_t count = 0;
    for (const SceneObject& object : objects) {
        for (const Primitive& primitive : object.mesh->primitives) {
            count += primitive.positions.size();
        }
    }
    return count;
}

void validate(const FrameRequest& request, const TransferBakeOptions& options) {
    if (request.objects.empty()) {
        throw Error(ErrorKind::InvalidInput, "transfer bake: the request has no objects");
    }
    for (std::size_t o = 0; o < request.objects.size(); ++o) {
        if (!request.objects[o].mesh) {
            throw Error(ErrorKind::InvalidInput,
                        "transfer bake: object " + std::to_string(o) + " has no mesh");
        }
    }
    if (options.rays < 0 || options.threads < 0) {
        throw Error(ErrorKind::InvalidInput,
                    "transfer bake: rays and threads must be 0 (the rule, every core) or more, "
                    "got " +
                        std::to_string(options.rays) + " and " + std::to_string(options.threads));
    }
}

// The ground grid of oer/scene/scene_transfer.hpp under the scene (the frame's plane: y = the
// bounds' lowest y), centred on the objects' bounds in x and z, kGroundHalfSizeOverRadius radii
// each side.
GroundTransfer ground_grid(const SceneBounds& frame) {
    GroundTransfer ground;
    ground.centre = {frame.centre.x, frame.centre.z};
    ground.half_size = kGroundHalfSizeOverRadius * frame.radius;
    ground.height = frame.box.min.y;
    ground.resolution = kGroundResolution;
    ground.points.count = std::size_t(kGroundResolution) * kGroundResolution;
    return ground;
}

void size_points(TransferPoints& points, std::size_t count, std::size_t slots) {
    points.count = count;
    points.direct.assign(count * kCoefficients, 0.0f);
    points.bounce.assign(count * slots * kCoefficients, 0.0f);
}

// Every vertex of every primitive of every object, in world space (the normal by the
// inverse-transpose, as EmbreeScene and the renderer transform it), then the ground's texel
// centres facing +Y.
std::vector<Receiver> receivers_of(const FrameRequest& request, SceneTransfer& transfer,
                                   SkyDirect& sky_direct) {
    const std::size_t vectors = bounce_vectors(transfer.reflectors);
    std::vector<Receiver> receivers;
    for (std::size_t o = 0; o < request.objects.size(); ++o) {
        const SceneObject& object = request.objects[o];
        const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(object.transform)));
        for (std::size_t p = 0; p < object.mesh->primitives.size(); ++p) {
            const Primitive& primitive = object.mesh->primitives[p];
            TransferPoints& points = transfer.objects[o][p];
            for (std::size_t v = 0; v < points.count; ++v) {
                Receiver receiver;
                receiver.position =
                    glm::vec3(object.transform * glm::vec4(primitive.positions[v], 1.0f));
                receiver.normal = glm::normalize(glm::dvec3(normal_matrix * primitive.normals[v]));
                if (!std::isfinite(receiver.normal.x) || !std::isfinite(receiver.normal.y) ||
                    !std::isfinite(receiver.normal.z)) {
                    throw Error(ErrorKind::InvalidInput,
                                "transfer bake: object " + std::to_string(o) +
                                    " has no normal at a vertex (a singular transform?)");
                }
                receiver.direct = &points.direct[v * kCoefficients];
                receiver.bounce =
                    points.bounce.empty() ? nullptr : &points.bounce[v * vectors * kCoefficients];
                if (!sky_direct.empty()) {
                    receiver.sky_direct = &sky_direct[o][p][v * kCoefficients];
                }
                receivers.push_back(receiver);
            }
        }
    }
    if (transfer.ground) {
        GroundTransfer& ground = *transfer.ground;
        const double texel = 2.0 * ground.half_size / ground.resolution;
        for (int row = 0; row < ground.resolution; ++row) {
            for (int column = 0; column < ground.resolution; ++column) {
                const std::size_t index =
                    std::size_t(row) * std::size_t(ground.resolution) + std::size_t(column);
                Receiver receiver;
                receiver.position = {ground.centre.x - ground.half_size + (column + 0.5) * texel,
                                     ground.height,
                                     ground.centre.y - ground.half_size + (row + 0.5) * texel};
                receiver.direct = &ground.points.direct[index * kCoefficients];
                receiver.bounce = ground.points.bounce.empty()
                                      ? nullptr
                                      : &ground.points.bounce[index * vectors * kCoefficients];
                receivers.push_back(receiver);
            }
        }
    }
    return receivers;
}

// What a ray that hit surface point q reflects, per unit albedo over pi: on an object D(q), the
// direct transfer there, the barycentric interpolation of its triangle's three vertices'
// vectors (as the rasteriser interpolates them); on the ground D(q) - A_l Y_i(+Y), how much
// the ground there differs from the open ground (bilinear between the grid's texel centres,
// clamped to the outer texels in their outer half; zero beyond the grid), since the open
// ground's radiance is already in the lighting below the horizon (transfer_lighting.hpp).
class DirectAtHit {
  public:
    DirectAtHit(const FrameRequest& request, const SceneTransfer& transfer,
                const SkyDirect& sky_direct)
        : request_(request),
          transfer_(transfer),
          sky_direct_(sky_direct),
          open_ground_(unoccluded_coefficients({0, 1, 0})) {}

    // With the ground, what the object reflects of the map alone (Receiver::sky_direct), as the
    // one-bounce reference's surfaces do: the plane's own light is the ground's slot; without
    // it, of the whole map.
    Coefficients on_object(const SurfaceHit& hit) const {
        const std::vector<std::uint32_t>& indices =
            request_.objects[hit.object].mesh->primitives[hit.primitive].indices;
        const std::vector<float>& direct = sky_direct_.empty()
                                               ? transfer_.objects[hit.object][hit.primitive].direct
                                               : sky_direct_[hit.object][hit.primitive];
        const std::uint32_t* corner = &indices[3 * std::size_t(hit.triangle)];
        const double weights[3] = {1.0 - hit.u - hit.v, hit.u, hit.v};
        Coefficients result{};
        for (int k = 0; k < 3; ++k) {
            const float* vertex = &direct[std::size_t(corner[k]) * kCoefficients];
            for (int i = 0; i < kCoefficients; ++i) {
                result[std::size_t(i)] += weights[k] * double(vertex[i]);
            }
        }
        return result;
    }

    Coefficients on_ground(const glm::dvec3& position) const {
        Coefficients difference = ground_direct(position);
        for (std::size_t i = 0; i < difference.size(); ++i) {
            difference[i] -= open_ground_[i];
        }
        return difference;
    }

  private:
    Coefficients ground_direct(const glm::dvec3& position) const {
        const GroundTransfer& ground = *transfer_.ground;
        const double half = ground.half_size;
        const double dx = position.x - ground.centre.x, dz = position.z - ground.centre.y;
        if (std::abs(dx) > half || std::abs(dz) > half) {
            return open_ground_;
        }
        // Texel coordinates with texel centres at integers.
        const int resolution = ground.resolution;
        const double x =
            std::clamp((dx + half) / (2.0 * half) * resolution - 0.5, 0.0, double(resolution - 1));
        const double z =
            std::clamp((dz + half) / (2.0 * half) * resolution - 0.5, 0.0, double(resolution - 1));
        const int x0 = std::min(int(x), resolution - 2), z0 = std::min(int(z), resolution - 2);
        const double fx = x - x0, fz = z - z0;
        const auto texel = [&](int row, int column) {
            return &ground.points
                        .direct[(std::size_t(row) * std::size_t(resolution) + std::size_t(column)) *
                                kCoefficients];
        };
        const float *a = texel(z0, x0), *b = texel(z0, x0 + 1), *c = texel(z0 + 1, x0),
                    *d = texel(z0 + 1, x0 + 1);
        Coefficients result{};
        for (int i = 0; i < kCoefficients; ++i) {
            result[std::size_t(i)] =
                (1.0 - fz) * ((1.0 - fx) * a[i] + fx * b[i]) + fz * ((1.0 - fx) * c[i] + fx * d[i]);
        }
        return result;
    }

    const FrameRequest& request_;
    const SceneTransfer& transfer_;
    const SkyDirect& sky_direct_;
    Coefficients open_ground_;
};

// How a bake traces: strata x strata rays per receiver, on `threads` threads, each ray leaving
// its receiver `offset` along the normal.
struct RayLayout {
    int strata = 1;
    int rays = 1;
    int threads = 1;
    double offset = 0.0;
};

RayLayout ray_layout(const FrameRequest& request, const TransferBakeOptions& options,
                     const SceneBounds& frame) {
    RayLayout layout;
    // Rays come in strata x strata cells: a requested count is rounded down to a square.
    const int requested = options.rays > 0 ? options.rays : transfer_ray_count(request.objects);
    layout.strata = std::max(1, int(std::sqrt(double(requested))));
    layout.rays = layout.strata * layout.strata;
    layout.threads = options.threads > 0 ? options.threads
                                         : std::max(1, int(std::thread::hardware_concurrency()));
    layout.offset = kRayOffsetOverRadius * double(frame.radius);
    return layout;
}

// The bake's result before any ray: every vertex's and (with the ground) every ground texel's
// vectors allocated and zero.
SceneTransfer sized_transfer(const FrameRequest& request, const SceneBounds& frame, Bounce bounce,
                             int rays) {
    SceneTransfer transfer;
    transfer.order = kTransferBakeOrder;
    transfer.bounce = bounce;
    transfer.rays = rays;
    if (bounce == Bounce::One) {
        transfer.reflectors = reflector_slots(request);
    }
    const std::size_t slots = bounce_vectors(transfer.reflectors);
    transfer.objects.resize(request.objects.size());
    for (std::size_t o = 0; o < request.objects.size(); ++o) {
        const std::vector<Primitive>& primitives = request.objects[o].mesh->primitives;
        transfer.objects[o].resize(primitives.size());
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            size_points(transfer.objects[o][p], primitives[p].positions.size(), slots);
        }
    }
    if (request.ground) {
        transfer.ground = ground_grid(frame);
        size_points(transfer.ground->points, transfer.ground->points.count, slots);
    }
    return transfer;
}

// Where a hit's reflection goes: the index, among a receiver's bounce vectors, of each vector
// it adds to (kNone: none), per object and material, and for the ground.
class VectorsOfHit {
  public:
    static constexpr std::size_t kNone = std::size_t(-1);
    struct Vectors {
        std::size_t material = kNone;  // a Material slot's vector: D / N
        std::size_t native = kNone;    // a Native slot's first vector: albedo_c D / N for c
        std::size_t unit = kNone;      // a Unit slot's vector: D / N
    };

    VectorsOfHit(const FrameRequest& request, const std::vector<ReflectorSlot>& slots)
        : request_(request), objects_(request.objects.size()) {
        for (std::size_t o = 0; o < request.objects.size(); ++o) {
            objects_[o].resize(request.objects[o].mesh->materials.size());
        }
        std::size_t vector = 0;
        for (const ReflectorSlot& slot : slots) {
            for (const std::uint32_t o : slot.objects) {
                std::vector<Vectors>& materials = objects_[o];
                switch (slot.kind) {
                    case ReflectorSlot::Kind::Ground:
                        break;
                    case ReflectorSlot::Kind::Material:
                        materials[slot.material].material = vector;
                        break;
                    case ReflectorSlot::Kind::Native:
                        for (Vectors& material : materials) {
                            material.native = vector;
                        }
                        break;
                    case ReflectorSlot::Kind::Unit:
                        for (Vectors& material : materials) {
                            material.unit = vector;
                        }
                        break;
                }
            }
            if (slot.kind == ReflectorSlot::Kind::Ground) {
                ground_ = vector;
            }
            vector += std::size_t(slot.vectors());
        }
    }
    std::size_t ground() const { return ground_; }
    const Vectors& object(const SurfaceHit& hit) const {
        const int material = request_.objects[hit.object].mesh->primitives[hit.primitive].material;
        return objects_[hit.object][std::size_t(material)];
    }

  private:
    const FrameRequest& request_;
    std::vector<std::vector<Vectors>> objects_;  // [object][material]
    std::size_t ground_ = kNone;
};

// Room for every vertex's direct transfer with the ground blocking (Receiver::sky_direct): only
// a scene with the ground, under Bounce::One, needs it; otherwise empty.
SkyDirect sky_direct_slots(const FrameRequest& request, const SceneTransfer& transfer,
                           Bounce bounce) {
    SkyDirect sky_direct;
    if (request.ground && bounce == Bounce::One) {
        for (const std::vector<TransferPoints>& object : transfer.objects) {
            std::vector<std::vector<float>>& primitives = sky_direct.emplace_back();
            for (const TransferPoints& points : object) {
                primitives.emplace_back(points.direct.size());
            }
        }
    }
    return sky_direct;
}

// The two phases' work for one receiver, each writing that receiver's vectors alone.
class ReceiverTracer {
  public:
    ReceiverTracer(const EmbreeScene& scene, const RayLayout& layout, bool ground)
        : scene_(scene), layout_(layout), ground_(ground) {}

    // Phase 1, shadowed diffuse transfer (Sloan et al. 2002, eq. 8):
    //   direct_i = integral over the hemisphere of V(w) max(0, n . w) Y_i(w) dw,
    // with N cosine-distributed rays (density cos / pi) the estimate (pi / N) sum over the rays
    // that escape of Y_i(w). Written as A_l Y_i(n) - (pi / N) sum over the blocked rays of
    // Y_i(w): the same estimate, but with the exact integral A_l Y_i(n) of all rays in place of
    // the rays' own sum of it (a control variate whose mean is that integral). So a point that
    // nothing occludes holds A_l Y_i(n) exactly, with no sampling noise (direct . R is plain SH
    // irradiance there, and the grid's open edge meets the unoccluded ground beyond it without
    // a seam), and only the basis values of blocked rays are evaluated. With the ground, only
    // objects block: the plane's light is the lighting's below the horizon. Marks in `meeting`
    // the rays that met a surface.
    void trace_direct(std::size_t r, const Receiver& receiver, RaysMeetingSurfaces& meeting) const {
        const double ray_weight = std::numbers::pi / layout_.rays;
        const glm::dvec3 origin = receiver.position + layout_.offset * receiver.normal;
        Coefficients direct = unoccluded_coefficients(receiver.normal);
        Coefficients sky_direct = direct;
        Coefficients basis{};
        for_each_ray(r, layout_.strata, [&](int ray, double u1, double u2) {
            const glm::dvec3 direction = sampling::cosine_direction(receiver.normal, u1, u2);
            const RayBlocking blocking = blocking_of(origin, direction);
            if (!blocking.meets_surface) {
                return;
            }
            meeting.set(r, ray);
            sh_evaluate(kTransferBakeOrder, direction, basis);
            for (int i = 0; i < kCoefficients; ++i) {
                const double blocked = ray_weight * basis[std::size_t(i)];
                sky_direct[std::size_t(i)] -= blocked;
                if (blocking.meets_object) {
                    direct[std::size_t(i)] -= blocked;
                }
            }
        });
        std::copy(direct.begin(), direct.end(), receiver.direct);
        if (receiver.sky_direct != nullptr) {
            std::copy(sky_direct.begin(), sky_direct.end(), receiver.sky_direct);
        }
    }

    // Phase 2, one bounce of interreflected transfer (Sloan et al. 2002, eq. 9, its first
    // pass), once every direct vector exists: a ray that hits a surface point q brings q's
    // outgoing radiance rho(q) / pi * (D(q) . L), so per bounce vector of the reflector slots
    //   bounce_i = (pi / N) sum over the rays that hit the slot's surfaces of w(q) / pi D_i(q)
    // with w(q) = 1 (Ground, Material and Unit slots: unit albedo) or the hit's albedo in one
    // channel (a Native slot's three vectors); on the ground D(q) less the open ground's, which
    // the lighting already has (DirectAtHit). Over the rays of phase 1 that met a surface,
    // traced again to find what they hit rather than storing their hits.
    void trace_bounce(std::size_t r, const Receiver& receiver, const RaysMeetingSurfaces& meeting,
                      const DirectAtHit& direct_at, const VectorsOfHit& vectors_of,
                      std::size_t vectors) const {
        const glm::dvec3 origin = receiver.position + layout_.offset * receiver.normal;
        std::vector<Coefficients> bounce(vectors, Coefficients{});
        // (pi / N) (1 / pi) = 1 / N.
        const double weight = 1.0 / layout_.rays;
        const auto gather = [&](std::size_t vector, double scale, const Coefficients& reflected) {
            for (int i = 0; i < kCoefficients; ++i) {
                bounce[vector][std::size_t(i)] += scale * reflected[std::size_t(i)];
            }
        };
        for_each_ray(r, layout_.strata, [&](int ray, double u1, double u2) {
            if (!meeting.test(r, ray)) {
                return;
            }
            const glm::dvec3 direction = sampling::cosine_direction(receiver.normal, u1, u2);
            const std::optional<SurfaceHit> hit =
                scene_.intersect(origin, direction, 0.0, GroundReach::Infinite);
            if (!hit) {
                return;
            }
            if (hit->ground) {
                if (vectors_of.ground() != VectorsOfHit::kNone) {
                    gather(vectors_of.ground(), weight, direct_at.on_ground(hit->position));
                }
                return;
            }
            const Coefficients reflected = direct_at.on_object(*hit);
            const VectorsOfHit::Vectors& to = vectors_of.object(*hit);
            if (to.material != VectorsOfHit::kNone) {
                gather(to.material, weight, reflected);
            }
            if (to.native != VectorsOfHit::kNone) {
                for (std::size_t c = 0; c < 3; ++c) {
                    gather(to.native + c, weight * hit->material.base_color[int(c)], reflected);
                }
            }
            if (to.unit != VectorsOfHit::kNone) {
                gather(to.unit, weight, reflected);
            }
        });
        for (std::size_t v = 0; v < vectors; ++v) {
            std::copy(bounce[v].begin(), bounce[v].end(), receiver.bounce + v * kCoefficients);
        }
    }

  private:
    struct RayBlocking {
        bool meets_surface = false;  // an object or the ground plane
        bool meets_object = false;
    };

    // With the ground, a ray down from above it meets the infinite plane, whose own light is
    // the map's below the horizon in the lighting the direct vectors take
    // (transfer_lighting.hpp): only an object blocks it.
    RayBlocking blocking_of(const glm::dvec3& origin, const glm::dvec3& direction) const {
        RayBlocking blocking;
        if (ground_ && direction.y < 0.0) {
            const std::optional<SurfaceHit> hit =
                scene_.intersect(origin, direction, 0.0, GroundReach::Infinite);
            blocking.meets_surface = hit.has_value();
            blocking.meets_object = blocking.meets_surface && !hit->ground;
        } else {
            blocking.meets_surface = blocking.meets_object =
                scene_.occluded(origin, direction, 0.0, GroundReach::Infinite);
        }
        return blocking;
    }

    const EmbreeScene& scene_;
    const RayLayout& layout_;
    bool ground_;
};

// The materials a mesh's primitives draw by default, in the order they first use them.
std::vector<std::uint32_t> drawn_materials(const Mesh& mesh) {
    std::vector<std::uint32_t> materials;
    for (const Primitive& primitive : mesh.primitives) {
        const auto material = std::uint32_t(primitive.material);
        if (std::find(materials.begin(), materials.end(), material) == materials.end()) {
            materials.push_back(material);
        }
    }
    return materials;
}

// Per variant, per material drawn by default, the one material the variant draws in its place;
// nullopt when a variant draws two materials where the default draws one (its slots could not
// be weighed by one albedo).
std::optional<std::vector<std::map<int, int>>> variant_replacements(const Mesh& mesh) {
    std::vector<std::map<int, int>> replacements(mesh.variants.size());
    for (std::size_t v = 0; v < mesh.variants.size(); ++v) {
        for (const Primitive& primitive : mesh.primitives) {
            const int drawn = primitive.material_under(std::uint32_t(v));
            const auto [placed, inserted] = replacements[v].emplace(primitive.material, drawn);
            if (!inserted && placed->second != drawn) {
                return std::nullopt;
            }
        }
    }
    return replacements;
}

// Whether `mesh` reflects through one Material slot per material it draws (object_bounce_vectors).
bool reflects_per_material(const Mesh& mesh) {
    if (drawn_materials(mesh).size() > kMaxMaterialSlots || !variant_replacements(mesh)) {
        return false;
    }
    for (const Primitive& primitive : mesh.primitives) {
        // Vertex colours vary the albedo across a material, as a texture does.
        if (!primitive.colors.empty()) {
            return false;
        }
        for (const int material : primitive.materials_drawn()) {
            if (mesh.materials.at(std::size_t(material)).base_color_texture.present()) {
                return false;
            }
        }
    }
    return true;
}

// The groups of objects that share their slots: each object alone, or past
// kMaxSeparateReflectors objects those of one mesh, one colour and one variant.
std::vector<std::vector<std::uint32_t>> reflector_groups(const FrameRequest& request) {
    const bool merge = request.objects.size() > kMaxSeparateReflectors;
    std::vector<std::vector<std::uint32_t>> groups;
    for (std::uint32_t o = 0; o < request.objects.size(); ++o) {
        const SceneObject& object = request.objects[o];
        const auto same = [&](const std::vector<std::uint32_t>& group) {
            const SceneObject& first = request.objects[group.front()];
            return first.mesh == object.mesh && first.base_color == object.base_color &&
                   first.base_color_material == object.base_color_material &&
                   first.variant == object.variant;
        };
        const auto group = merge ? std::find_if(groups.begin(), groups.end(), same) : groups.end();
        if (group != groups.end()) {
            group->push_back(o);
        } else {
            groups.push_back({o});
        }
    }
    return groups;
}

}  // namespace

std::size_t object_bounce_vectors(const Mesh& mesh) {
    return reflects_per_material(mesh) ? drawn_materials(mesh).size() : 4;
}

bool reflectors_follow_colours(const FrameRequest& request) {
    return request.objects.size() > kMaxSeparateReflectors;
}

std::vector<ReflectorSlot> reflector_slots(const FrameRequest& request) {
    using Kind = ReflectorSlot::Kind;
    std::vector<ReflectorSlot> slots;
    if (request.ground) {
        slots.push_back({Kind::Ground, {}, 0, glm::vec3(kGroundAlbedo)});
    }
    for (const std::vector<std::uint32_t>& group : reflector_groups(request)) {
        const Mesh& mesh = *request.objects[group.front()].mesh;
        if (reflects_per_material(mesh)) {
            for (const std::uint32_t material : drawn_materials(mesh)) {
                slots.push_back({Kind::Material, group, material,
                                 glm::vec3(mesh.materials.at(material).base_color)});
            }
        } else {
            slots.push_back({Kind::Native, group, 0, glm::vec3(0.0f)});
            slots.push_back({Kind::Unit, group, 0, glm::vec3(0.0f)});
        }
    }
    return slots;
}

std::uint64_t transfer_point_count(std::uint64_t object_points) {
    return object_points + std::uint64_t(kGroundResolution) * kGroundResolution;
}

int transfer_ray_count(std::uint64_t object_points, double rays_per_phase) {
    // The ground's grid is counted whether or not a frame has the ground: the rule sees the
    // objects only, and an upper bound keeps the bake within its time.
    const double receivers = double(transfer_point_count(object_points));
    const int strata =
        std::clamp(int(std::sqrt(rays_per_phase / receivers)), kMinStrata, kMaxStrata);
    return strata * strata;
}

int transfer_ray_count(const std::vector<SceneObject>& objects, double rays_per_phase) {
    return transfer_ray_count(receiver_count(objects), rays_per_phase);
}

SceneTransfer bake_transfer(const FrameRequest& request, const TransferBakeOptions& options) {
    validate(request, options);
    const auto start = std::chrono::steady_clock::now();
    const SceneBounds frame = scene_bounds(request.objects);
    // The surfaces as their files draw them: a Native slot holds the file's albedos, whatever
    // colour or variant the frame that asked for the bake drew (the transfer's id leaves them
    // out, and bounce_weights re-weighs the slots for each frame's).
    FrameRequest as_filed = request;
    for (SceneObject& object : as_filed.objects) {
        object.base_color.reset();
        object.base_color_material.reset();
        object.variant.reset();
    }
    // The ground as the infinite plane alone: a face of an object lying on the plane is hit
    // before it, and a ray that leaves a vertex on the plane is not stopped by it at t = 0, so
    // the objects block the same rays with the ground as without it.
    const EmbreeScene scene(as_filed, frame, reference::GroundTracing::PlaneOnly);
    const RayLayout layout = ray_layout(request, options, frame);
    SceneTransfer transfer = sized_transfer(request, frame, options.bounce, layout.rays);
    SkyDirect sky_direct = sky_direct_slots(request, transfer, options.bounce);
    const std::vector<Receiver> receivers = receivers_of(request, transfer, sky_direct);

    const ReceiverTracer tracer(scene, layout, request.ground);
    RaysMeetingSurfaces meeting(receivers.size(), layout.rays);
    if (options.progress) {
        options.progress->total =
            receivers.size() * (options.bounce == Bounce::One ? std::size_t(2) : std::size_t(1));
    }
    parallel_for(receivers.size(), layout.threads, options.stop, options.progress,
                 [&](std::size_t r) { tracer.trace_direct(r, receivers[r], meeting); });
    if (options.bounce == Bounce::One) {
        const DirectAtHit direct_at(request, transfer, sky_direct);
        const VectorsOfHit vectors_of(request, transfer.reflectors);
        const std::size_t vectors = bounce_vectors(transfer.reflectors);
        parallel_for(
            receivers.size(), layout.threads, options.stop, options.progress, [&](std::size_t r) {
                tracer.trace_bounce(r, receivers[r], meeting, direct_at, vectors_of, vectors);
            });
    }
    transfer.bake_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return transfer;
}

}  // namespace oer
