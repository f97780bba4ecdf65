#include "render_cost.hpp"

#include <set>
#include <sstream>

#include "http_errors.hpp"
#include "oer/core/size_text.hpp"
#include "oer/scene/scene_transfer.hpp"
#include "oer/transfer/transfer_bake.hpp"

namespace oer::server {

namespace {

// The lights a frame draws a shadow map for: every light whose weight is above zero (all of
// them when the request gives no weights), when shadows are on.
std::uint64_t shadowing_lights(const api::RenderSpec& spec, std::size_t rig_lights) {
    if (!spec.shadows.enabled) {
        return 0;
    }
    if (spec.lights.empty()) {
        return rig_lights;
    }
    std::uint64_t on = 0;
    for (std::size_t i = 0; i < spec.lights.size() && i < rig_lights; ++i) {
        on += spec.lights[i] > 0.0;
    }
    return on;
}

std::string seconds_text(double seconds) {
    std::ostringstream text;
    text.precision(3);
    text << seconds << " s";
    return text.str();
}

// The bounce vectors of the reflector slots that reflector_slots (transfer_bake.hpp) makes for
// these objects and the ground: each object's group alone, or past kMaxSeparateReflectors
// objects one group per mesh, colour and variant.
std::size_t bounce_vector_count(const api::RenderSpec& spec,
                                const std::vector<MeshSummary>& object_meshes,
                                const std::vector<std::string>& mesh_ids) {
    const bool merge = object_meshes.size() > kMaxSeparateReflectors;
    std::set<std::pair<std::string, std::string>> groups;
    std::size_t vectors = 1;  // the ground's
    for (std::size_t i = 0; i < object_meshes.size(); ++i) {
        const auto& colour = spec.objects[i].base_color;
        const std::string colour_key =
            (colour ? std::to_string(colour->r) + " " + std::to_string(colour->g) + " " +
                          std::to_string(colour->b)
                    : "") +
            "/" + spec.objects[i].base_color_material.value_or("") + "/" +
            spec.objects[i].variant.value_or("");
        if (!merge || groups.emplace(mesh_ids[i], colour_key).second) {
            vectors += object_meshes[i].bounce_vectors;
        }
    }
    return vectors;
}

}  // namespace

RenderCost estimate_render_cost(const api::RenderSpec& spec,
                                const std::vector<MeshSummary>& object_meshes,
                                const std::vector<std::string>& mesh_ids, std::size_t rig_lights,
                                double rays_per_phase) {
    RenderCost cost;
    std::set<std::string> counted;
    std::uint64_t triangles = 0;
    std::uint64_t points = 0;
    for (std::size_t i = 0; i < object_meshes.size(); ++i) {
        const MeshSummary& mesh = object_meshes[i];
        triangles += mesh.triangles;
        points += mesh.vertices;
        if (counted.insert(mesh_ids[i]).second) {
            cost.mesh_bytes += mesh.resident_bytes;
            cost.texture_bytes += mesh.texture_bytes;
        }
    }
    cost.gl_texture_bytes = cost.texture_bytes / 3 * 4;
    const std::uint64_t lights = shadowing_lights(spec, rig_lights);
    const std::uint64_t resolution = std::uint64_t(spec.shadows.resolution);
    cost.shadow_bytes = lights * resolution * resolution * 4;
    const std::uint64_t samples =
        std::uint64_t(spec.width) * std::uint64_t(spec.height) * std::uint64_t(spec.samples);
    cost.target_bytes = samples * kTargetBytesPerSample;
    // The geometry pass, each shadow map and the ground's visibility pass draw every triangle.
    cost.draw_seconds = double(triangles) *
                        double(1 + lights + (spec.ground != api::GroundChoice::Off ? 1 : 0)) /
                        kTrianglesPerSecond;
    cost.shade_seconds = double(samples) * double(1 + rig_lights) / kSampleLightsPerSecond;
    if (spec.occlusion && !object_meshes.empty()) {
        const std::uint64_t receivers = transfer_point_count(points);
        const bool bounce = spec.bounce == Bounce::One;
        // A direct vector and, under one bounce, the reflector slots' (transfer_bake.hpp: always
        // baked with the ground).
        const std::uint64_t vectors =
            1 + (bounce ? bounce_vector_count(spec, object_meshes, mesh_ids) : 0);
        const std::uint64_t floats_per_point =
            std::uint64_t(kTransferBakeOrder) * kTransferBakeOrder * vectors;
        cost.transfer_bytes = receivers * floats_per_point * sizeof(float);
        const double rays = double(receivers) * transfer_ray_count(points, rays_per_phase);
        cost.bake_seconds =
            double(receivers) * kBakeSecondsPerPoint + rays * (bounce ? 2.0 : 1.0) / kRaysPerSecond;
    }
    return cost;
}

void check_render_cost(const RenderCost& cost, const RenderBudgets& budgets) {
    const auto refuse = [&](const std::string& what, const std::string& estimate,
                            const std::string& budget, const std::string& parts,
                            const std::string& advice) {
        Problem refusal =
            problem(ProblemKind::LimitExceeded, "this render would take " + estimate + " of " +
                                                    what + ", over the server's budget of " +
                                                    budget + " (" + parts + "); " + advice);
        refusal.extensions["estimate"] = {{"memory_bytes", cost.memory_bytes()},
                                          {"seconds", cost.seconds()},
                                          {"transfer_bytes", cost.transfer_bytes}};
        refusal.extensions["budget"] = {{"memory_bytes", budgets.memory_bytes},
                                        {"seconds", budgets.seconds},
                                        {"transfer_bytes", budgets.transfer_bytes}};
        throw HttpError(std::move(refusal));
    };
    if (cost.transfer_bytes > budgets.transfer_bytes) {
        refuse("disk for its occlusion transfer", mebibytes(cost.transfer_bytes),
               mebibytes(budgets.transfer_bytes), "a transfer per vertex of its objects",
               "render with occlusion off, or fewer or smaller meshes");
    }
    if (cost.memory_bytes() > budgets.memory_bytes) {
        refuse("memory", mebibytes(cost.memory_bytes()), mebibytes(budgets.memory_bytes),
               "meshes " + mebibytes(cost.mesh_bytes) + " (textures " +
                   mebibytes(cost.texture_bytes) + ", and " + mebibytes(cost.gl_texture_bytes) +
                   " as GL holds them), frame targets " + mebibytes(cost.target_bytes) +
                   ", shadow maps " + mebibytes(cost.shadow_bytes) + ", transfer " +
                   mebibytes(cost.transfer_bytes),
               "ask for fewer pixels or samples, a lower shadow_resolution, fewer lights or "
               "fewer distinct meshes");
    }
    if (cost.seconds() > budgets.seconds) {
        refuse("rendering time", seconds_text(cost.seconds()), seconds_text(budgets.seconds),
               "drawing " + seconds_text(cost.draw_seconds) + ", shading " +
                   seconds_text(cost.shade_seconds) + ", baking the transfer " +
                   seconds_text(cost.bake_seconds),
               "ask for fewer objects or triangles, fewer pixels or samples, or occlusion off");
    }
}

}  // namespace oer::server
