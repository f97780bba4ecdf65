#include "transfer_registry.hpp"

#include <chrono>
#include <cmath>

#include <nlohmann/json.hpp>

#include "oer/api/content_id.hpp"
#include "oer/api/render_request.hpp"
#include "oer/core/error.hpp"
#include "oer/scene/scene_rules.hpp"
#include "oer/transfer/transfer_bake.hpp"
#include "oer/transfer/transfer_codec.hpp"

namespace oer::server {

namespace {

// Raised whenever the bake (transfer_bake.cpp) would give other values for the same scene, or
// the stored form (transfer_codec.cpp) changes: every stored transfer of an older bake then has
// an id no frame asks for, so none is ever served. It also stands for the preset product
// (make_default_product), whose id `default` does not change with its geometry.
constexpr int kTransferBakeVersion = 1;

// -0 and 0 are one value (one scene, one id).
double canonical(float value) {
    return double(value) + 0.0;
}

// Why a transfer read from the store cannot be drawn with request, or empty when it fits. Its id
// hashes everything the bake reads, so a misfit is an entry of a bake that differs from this
// one; its receivers would not be the scene's vertices, and the renderer must never see it.
std::string misfit(const SceneTransfer& transfer, const FrameRequest& request) {
    if (transfer.order != kTransferBakeOrder) {
        return "its order is " + std::to_string(transfer.order);
    }
    return transfer_misfit(transfer, request);
}

}  // namespace

std::string transfer_id(const FrameRequest& request, const std::vector<std::string>& mesh_ids,
                        int rays) {
    if (mesh_ids.size() != request.objects.size()) {
        throw Error(ErrorKind::Internal, "transfer_id: " + std::to_string(mesh_ids.size()) +
                                             " mesh id(s) for " +
                                             std::to_string(request.objects.size()) + " object(s)");
    }
    nlohmann::json objects = nlohmann::json::array();
    for (std::size_t i = 0; i < request.objects.size(); ++i) {
        const SceneObject& object = request.objects[i];
        nlohmann::json transform = nlohmann::json::array();
        for (int column = 0; column < 4; ++column) {
            for (int row = 0; row < 4; ++row) {
                transform.push_back(canonical(object.transform[column][row]));
            }
        }
        nlohmann::json base_color = nullptr;
        if (object.base_color) {
            base_color = {canonical(object.base_color->r), canonical(object.base_color->g),
                          canonical(object.base_color->b)};
        }
        objects.push_back(
            {{"mesh", mesh_ids[i]}, {"transform", transform}, {"base_color", base_color}});
    }
    const nlohmann::json bake = {{"objects", objects},
                                 {"ground", request.ground},
                                 {"bounce", api::to_string(request.bounce)},
                                 {"rays", rays},
                                 {"order", kTransferBakeOrder}};
    return api::sha256_hex("oer-transfer-v" + std::to_string(kTransferBakeVersion) + "\n" +
                           bake.dump());
}

TransferRegistry::TransferRegistry(AssetStore& store, ServiceMetrics& metrics, Log log,
                                   std::size_t cache_bytes, double rays_per_phase)
    : store_(store),
      metrics_(metrics),
      log_(std::move(log)),
      transfers_(metrics, CacheName::Transfer, cache_bytes),
      rays_per_phase_(rays_per_phase) {}

std::shared_ptr<const SceneTransfer> TransferRegistry::transfer(
    const FrameRequest& request, const std::vector<std::string>& mesh_ids) {
    const int rays = transfer_ray_count(request.objects, rays_per_phase_);
    const std::string id = transfer_id(request, mesh_ids, rays);
    return transfers_
        .upload(
            id,
            [&]() -> std::shared_ptr<const SceneTransfer> {
                if (auto cached = transfers_.cached(id)) {
                    return cached;
                }
                return load_stored(id, request);
            },
            [&] { return bake(id, request, rays); })
        .asset;
}

std::shared_ptr<const SceneTransfer> TransferRegistry::load_stored(const std::string& id,
                                                                   const FrameRequest& request) {
    const auto stored = store_.get_derived(DerivedKind::Transfer, id);
    if (!stored) {
        return nullptr;
    }
    std::string problem;
    try {
        auto transfer = std::make_shared<const SceneTransfer>(decode_transfer(*stored));
        problem = misfit(*transfer, request);
        if (problem.empty()) {
            transfers_.remember(id, transfer, stored->size());
            return transfer;
        }
    } catch (const Error& error) {
        // Sealed yet undecodable: written by another version, or a bug.
        problem = error.what();
    }
    log_("transfers: stored transfer " + id + " is unreadable or does not fit its scene (" +
         problem + "); dropped");
    store_.remove(DerivedKind::Transfer, id);
    return nullptr;
}

std::shared_ptr<const SceneTransfer> TransferRegistry::bake(const std::string& id,
                                                            const FrameRequest& request, int rays) {
    const InProgress in_progress(metrics_.transfers_in_progress);
    const auto start = std::chrono::steady_clock::now();
    TransferBakeOptions options;
    options.bounce = request.bounce;
    options.rays = rays;
    auto transfer = std::make_shared<const SceneTransfer>(bake_transfer(request, options));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string encoded = encode_transfer(*transfer);
    metrics_.transfers_computed.increment();
    metrics_.transfer_seconds.observe(seconds);
    log_("transfers: transfer " + id + " of " + std::to_string(request.objects.size()) +
         " object(s) computed in " + std::to_string(int(std::lround(seconds * 1000.0))) + " ms, " +
         std::to_string(encoded.size()) + " bytes, " + std::to_string(transfer->rays) +
         " rays per point");
    store_.put_derived_if_room(DerivedKind::Transfer, id, encoded);
    transfers_.remember(id, transfer, encoded.size());
    return transfer;
}

}  // namespace oer::server
