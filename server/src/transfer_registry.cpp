#include "transfer_registry.hpp"

#include <algorithm>
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
constexpr int kTransferBakeVersion = 2;

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

// Calls visit(id) for every entry of kind in the store, a page at a time.
template <typename Visit>
void for_each_stored(AssetStore& store, DerivedKind kind, const Visit& visit) {
    constexpr std::size_t kPage = 1000;
    std::string after;
    for (;;) {
        const std::vector<std::string> ids = store.list(kind, after, kPage);
        for (const std::string& id : ids) {
            visit(id);
        }
        if (ids.size() < kPage) {
            return;
        }
        after = ids.back();
    }
}

// The record of the meshes a transfer's scene holds: their content ids (the preset's is part of
// the server and is never deleted), as JSON.
std::string meshes_record(const std::vector<std::string>& mesh_ids) {
    nlohmann::json meshes = nlohmann::json::array();
    for (const std::string& id : mesh_ids) {
        if (api::is_content_id(id)) {
            meshes.push_back(id);
        }
    }
    return nlohmann::json{{"meshes", meshes}}.dump();
}

// Whether a record names mesh_id; a record that cannot be read names none (its transfer then
// goes only by the quota).
bool record_holds(const std::string& record, const std::string& mesh_id) {
    const nlohmann::json parsed = nlohmann::json::parse(record, nullptr, false);
    if (!parsed.is_object() || !parsed.contains("meshes") || !parsed["meshes"].is_array()) {
        return false;
    }
    for (const nlohmann::json& id : parsed["meshes"]) {
        if (id.is_string() && id.get<std::string>() == mesh_id) {
            return true;
        }
    }
    return false;
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
        // Colours and variants are weights of the bounce's reflector slots, not part of the
        // bake, unless the scene has so many surfaces that the slots merge them by both.
        nlohmann::json base_color = nullptr;
        if (object.base_color && reflectors_follow_colours(request)) {
            base_color = {canonical(object.base_color->r), canonical(object.base_color->g),
                          canonical(object.base_color->b)};
        }
        objects.push_back(
            {{"mesh", mesh_ids[i]}, {"transform", transform}, {"base_color", base_color}});
        if (object.variant && reflectors_follow_colours(request)) {
            objects.back()["variant"] = *object.variant;
        }
        if (object.base_color && object.base_color_material && reflectors_follow_colours(request)) {
            objects.back()["base_color_material"] = *object.base_color_material;
        }
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
                                   std::size_t cache_bytes, double rays_per_phase,
                                   std::uint64_t store_bytes)
    : store_(store),
      metrics_(metrics),
      log_(std::move(log)),
      transfers_(metrics, CacheName::Transfer, cache_bytes),
      rays_per_phase_(rays_per_phase),
      store_budget_(store_bytes) {
    struct Found {
        std::chrono::system_clock::time_point written;
        std::string id;
        std::uint64_t bytes = 0;
    };
    std::vector<Found> found;
    for_each_stored(store_, DerivedKind::Transfer, [&](const std::string& id) {
        const auto info = store_.info(DerivedKind::Transfer, id);
        if (!info) {
            return;
        }
        if (!store_.contains(DerivedKind::TransferMeshes, id)) {
            log_("transfers: stored transfer " + id +
                 " has no record of its meshes (an older version stored it); removed");
            store_.remove(DerivedKind::Transfer, id);
            return;
        }
        found.push_back({info->written, id, info->bytes});
    });
    // A record whose transfer is missing: a removal or a disk-full write left it, or another
    // process is between writing the record and the transfer (seconds at most: spared).
    const auto abandoned_before = std::chrono::system_clock::now() - kAbandonedTemporaryAge;
    for_each_stored(store_, DerivedKind::TransferMeshes, [&](const std::string& id) {
        const auto info = store_.info(DerivedKind::TransferMeshes, id);
        if (info && info->written < abandoned_before &&
            !store_.contains(DerivedKind::Transfer, id)) {
            store_.remove(DerivedKind::TransferMeshes, id);
        }
    });
    std::sort(found.begin(), found.end(),
              [](const Found& a, const Found& b) { return a.written < b.written; });
    for (const Found& entry : found) {
        stored_[entry.id] = {entry.bytes, ++use_clock_};
        stored_bytes_ += entry.bytes;
    }
    metrics_.transfer_store_bytes.set(double(stored_bytes_));
    evict_over_budget();
}

std::shared_ptr<const SceneTransfer> TransferRegistry::transfer(
    const FrameRequest& request, const std::vector<std::string>& mesh_ids,
    const std::stop_token& stop, bool keep_in_memory) {
    const int rays = transfer_ray_count(request.objects, rays_per_phase_);
    const std::string id = transfer_id(request, mesh_ids, rays);
    auto transfer = transfers_
                        .upload(
                            id,
                            [&]() -> std::shared_ptr<const SceneTransfer> {
                                if (auto cached = transfers_.cached(id)) {
                                    return cached;
                                }
                                return load_stored(id, request);
                            },
                            [&](const std::stop_token& bake_stop) {
                                return bake(id, request, rays, bake_stop, mesh_ids, keep_in_memory);
                            },
                            stop)
                        .asset;
    // A frame that joined a bake ahead (which only stores what it bakes) keeps it in memory for
    // the frames after it.
    if (keep_in_memory && !transfers_.remembered(id)) {
        if (const std::uint64_t bytes = stored_file_bytes(id); bytes > 0) {
            transfers_.remember(id, transfer, bytes);
        }
    }
    note_use(id);
    evict_over_budget();
    return transfer;
}

std::string TransferRegistry::id_for(const FrameRequest& request,
                                     const std::vector<std::string>& mesh_ids,
                                     std::uint64_t object_points) const {
    return transfer_id(request, mesh_ids, transfer_ray_count(object_points, rays_per_phase_));
}

std::string TransferRegistry::id_of(const FrameRequest& request,
                                    const std::vector<std::string>& mesh_ids) const {
    return transfer_id(request, mesh_ids, transfer_ray_count(request.objects, rays_per_phase_));
}

bool TransferRegistry::ready(const std::string& id) {
    return transfers_.remembered(id) || store_.contains(DerivedKind::Transfer, id);
}

TransferPreparation TransferRegistry::preparation(const std::string& id) const {
    TransferPreparation answer;
    {
        const std::lock_guard lock(baking_mutex_);
        if (const auto baking = baking_.find(id); baking != baking_.end()) {
            answer.state = TransferPreparation::State::Baking;
            answer.fraction = baking->second->fraction();
            answer.elapsed_seconds = std::chrono::duration<double>(
                                         std::chrono::steady_clock::now() - baking->second->start)
                                         .count();
            return answer;
        }
    }
    if (store_.contains(DerivedKind::Transfer, id)) {
        answer.state = TransferPreparation::State::Ready;
        answer.fraction = 1.0;
    }
    return answer;
}

std::size_t TransferRegistry::remove_with_mesh(const std::string& mesh_id) {
    std::vector<std::string> holding;
    for_each_stored(store_, DerivedKind::TransferMeshes, [&](const std::string& id) {
        const auto record = store_.get_derived(DerivedKind::TransferMeshes, id);
        if (record && record_holds(*record, mesh_id)) {
            holding.push_back(id);
        }
    });
    for (const std::string& id : holding) {
        remove_stored(id);
    }
    if (!holding.empty()) {
        log_("transfers: removed " + std::to_string(holding.size()) +
             " stored transfer(s) of scenes holding mesh " + mesh_id);
    }
    return holding.size();
}

std::uint64_t TransferRegistry::stored_file_bytes(const std::string& id) const {
    const auto info = store_.info(DerivedKind::Transfer, id);
    return info ? info->bytes : 0;
}

std::uint64_t TransferRegistry::stored_bytes() const {
    const std::lock_guard lock(index_mutex_);
    return stored_bytes_;
}

void TransferRegistry::note_use(const std::string& id, std::optional<std::uint64_t> bytes) {
    const std::lock_guard lock(index_mutex_);
    const auto known = stored_.find(id);
    if (bytes) {
        if (known != stored_.end()) {
            stored_bytes_ -= known->second.bytes;
        }
        stored_[id] = {*bytes, ++use_clock_};
        stored_bytes_ += *bytes;
        metrics_.transfer_store_bytes.set(double(stored_bytes_));
    } else if (known != stored_.end()) {
        known->second.last_use = ++use_clock_;
    }
}

void TransferRegistry::evict_over_budget() {
    for (;;) {
        std::string victim;
        std::uint64_t victim_bytes = 0;
        std::uint64_t total = 0;
        {
            const std::lock_guard lock(index_mutex_);
            // The last one stays, whatever its size: a render's transfer is bounded on its own
            // (--max-transfer-bytes).
            if (stored_bytes_ <= store_budget_ || stored_.size() <= 1) {
                return;
            }
            const auto oldest = std::min_element(
                stored_.begin(), stored_.end(),
                [](const auto& a, const auto& b) { return a.second.last_use < b.second.last_use; });
            victim = oldest->first;
            victim_bytes = oldest->second.bytes;
            total = stored_bytes_;
        }
        log_("transfers: stored transfers take " + std::to_string(total) + " bytes, over the " +
             std::to_string(store_budget_) +
             " of --transfer-store-bytes; removed the least "
             "recently used, " +
             victim + " (" + std::to_string(victim_bytes) + " bytes)");
        metrics_.transfers_evicted.increment();
        remove_stored(victim);
    }
}

void TransferRegistry::remove_stored(const std::string& id) {
    // The transfer before its record: a crash between leaves a record without a transfer
    // (swept at start-up), never a transfer without its record.
    transfers_.remove(id, [&] {
        const bool removed = store_.remove(DerivedKind::Transfer, id);
        store_.remove(DerivedKind::TransferMeshes, id);
        return removed;
    });
    const std::lock_guard lock(index_mutex_);
    if (const auto known = stored_.find(id); known != stored_.end()) {
        stored_bytes_ -= known->second.bytes;
        stored_.erase(known);
        metrics_.transfer_store_bytes.set(double(stored_bytes_));
    }
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
            note_use(id, stored_file_bytes(id));
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

std::shared_ptr<const SceneTransfer> TransferRegistry::bake(
    const std::string& id, const FrameRequest& request, int rays, const std::stop_token& stop,
    const std::vector<std::string>& mesh_ids, bool keep_in_memory) {
    const InProgress in_progress(metrics_.transfers_in_progress);
    const auto start = std::chrono::steady_clock::now();
    TransferBakeOptions options;
    options.bounce = request.bounce;
    options.rays = rays;
    options.stop = stop;
    const auto progress = std::make_shared<BakeProgress>();
    options.progress = progress.get();
    {
        const std::lock_guard lock(baking_mutex_);
        baking_[id] = progress;
    }
    // Out of the list of bakes under way however the bake ends.
    struct Unlist {
        TransferRegistry& registry;
        const std::string& id;
        ~Unlist() {
            const std::lock_guard lock(registry.baking_mutex_);
            registry.baking_.erase(id);
        }
    } const unlist{*this, id};
    std::shared_ptr<const SceneTransfer> transfer;
    try {
        transfer = std::make_shared<const SceneTransfer>(bake_transfer(request, options));
    } catch (const Error& error) {
        if (error.kind() == ErrorKind::Cancelled) {
            log_("transfers: the bake of transfer " + id + " stopped after " +
                 std::to_string(int(std::lround(std::chrono::duration<double, std::milli>(
                                                    std::chrono::steady_clock::now() - start)
                                                    .count()))) +
                 " ms: no frame waits for it any more");
        }
        throw;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string encoded = encode_transfer(*transfer);
    metrics_.transfers_computed.increment();
    metrics_.transfer_seconds.observe(seconds);
    log_("transfers: transfer " + id + " of " + std::to_string(request.objects.size()) +
         " object(s) computed in " + std::to_string(int(std::lround(seconds * 1000.0))) + " ms, " +
         std::to_string(encoded.size()) + " bytes, " + std::to_string(transfer->rays) +
         " rays per point");
    // The record before the transfer, so that every stored transfer has one.
    const bool stored =
        store_.put_derived_if_room(DerivedKind::TransferMeshes, id, meshes_record(mesh_ids)) &&
        store_.put_derived_if_room(DerivedKind::Transfer, id, encoded);
    if (stored) {
        note_use(id, stored_file_bytes(id));
    }
    if (keep_in_memory || !stored) {
        transfers_.remember(id, transfer, encoded.size());
    }
    return transfer;
}

}  // namespace oer::server
