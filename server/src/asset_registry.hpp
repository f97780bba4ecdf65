#pragma once
// The lookup and upload path that environments and meshes share: a preset id answered from
// memory, content ids from an LRU of decoded assets in front of the asset store, and uploads
// of one content id coalesced, so that concurrent uploads of the same bytes (and options)
// decode and store them once: the later ones wait for the first and answer as cached (or with
// its error). What differs between kinds (how an asset is decoded, stored and read back) comes
// in as functions.
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "oer/api/content_id.hpp"
#include "oer/server/shared_lru_cache.hpp"
#include "service_metrics.hpp"

namespace oer::server {

template <typename Asset>
class AssetRegistry {
  public:
    using Pointer = std::shared_ptr<const Asset>;
    using Make = std::function<Pointer()>;

    struct Upload {
        Pointer asset;
        bool cached = false;  // the asset was there already: nothing was decoded or computed
    };

    AssetRegistry(ServiceMetrics& metrics, CacheName cache, std::size_t cache_bytes)
        : metrics_(metrics), cache_(cache), assets_(cache_bytes) {}

    void set_preset(Pointer preset) { preset_ = std::move(preset); }

    // The preset for kDefaultPresetId; nullptr for an id that is not a content id; else the
    // cached asset, or read_stored(), which may return nullptr (nothing stored under id) and
    // should remember() what it read.
    Pointer find(const std::string& id, const Make& read_stored) {
        if (id == api::kDefaultPresetId) {
            return preset_;
        }
        if (!api::is_content_id(id)) {
            return nullptr;
        }
        if (auto known = cached(id)) {
            return known;
        }
        return read_stored();
    }

    // The asset remembered under id (any id, the preset's too), counted as a cache hit, or
    // nullptr, counted as a miss.
    Pointer cached(const std::string& id) {
        if (auto known = assets_.get(id)) {
            metrics_.cache(cache_, true);
            return known;
        }
        metrics_.cache(cache_, false);
        return nullptr;
    }

    // known(): the asset when id is there already (cached), else nullptr. make(): decodes,
    // stores and remember()s it; run once per id however many uploads of it overlap.
    Upload upload(const std::string& id, const Make& known, const Make& make) {
        if (auto found = known()) {
            return {std::move(found), true};
        }
        std::promise<Pointer> promise;
        {
            std::unique_lock lock(in_flight_mutex_);
            const auto running = in_flight_.find(id);
            if (running != in_flight_.end()) {
                const auto making = running->second;
                lock.unlock();
                return {making.get(), true};
            }
            // Finished between known() above and this lock: remembered before it left
            // in_flight_.
            if (auto finished = assets_.get(id)) {
                return {std::move(finished), true};
            }
            in_flight_.emplace(id, promise.get_future().share());
        }
        const auto finish = [&] {
            const std::lock_guard lock(in_flight_mutex_);
            in_flight_.erase(id);
        };
        try {
            Pointer made = make();
            promise.set_value(made);
            finish();
            return {std::move(made), false};
        } catch (...) {
            promise.set_exception(std::current_exception());
            finish();
            throw;
        }
    }

    void remember(const std::string& id, const Pointer& asset, std::size_t charge) {
        assets_.put(id, asset, charge);
    }

  private:
    ServiceMetrics& metrics_;
    const CacheName cache_;
    Pointer preset_;
    SharedLruCache<Asset> assets_;
    // Assets being made, by id.
    std::mutex in_flight_mutex_;
    std::map<std::string, std::shared_future<Pointer>> in_flight_;
};

}  // namespace oer::server
