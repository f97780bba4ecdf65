#pragma once
// The lookup and upload path that environments and meshes share: a preset id answered from
// memory, content ids from an LRU of decoded assets in front of the asset store, and uploads
// of one content id coalesced, so that concurrent uploads of the same bytes (and options)
// decode and store them once: the later ones wait for the first and answer as cached (or with
// its error). What differs between kinds (how an asset is decoded, stored and read back) comes
// in as functions.
//
// Making an asset may be stopped (a transfer bake whose frames' clients have gone): each caller
// of upload() brings its own stop token, and the making is asked to stop (through the token
// make() receives) only once every caller waiting for it has had its stop requested; a caller
// whose stop is requested stops waiting at once (throwing Cancelled) while the others keep
// waiting for the asset. A caller that comes while a stopped making winds down waits for it to
// end and starts a making of its own.
//
// Removal: remove() takes the store lock exclusively, while every read or write of the store
// through this registry (read_stored, make, guarded) holds it shared; so a removal waits for the
// uploads and reads under way, and none of them can put back in memory or in the store what it
// removed. Readers that got the asset before keep it (shared ownership): a frame in flight
// finishes.
#include <chrono>
#include <cstddef>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <span>
#include <stop_token>
#include <string>
#include <string_view>
#include <vector>

#include "oer/api/content_id.hpp"
#include "oer/core/cancellation.hpp"
#include "oer/core/error.hpp"
#include "oer/server/asset_store.hpp"
#include "oer/server/shared_lru_cache.hpp"
#include "service_metrics.hpp"

namespace oer::server {

// Bytes held in a string (an upload's body, a stored source) as the span the decoders read.
inline std::span<const std::byte> as_bytes(std::string_view text) {
    return std::as_bytes(std::span(text.data(), text.size()));
}

// An entry of a listing (GET /v1/environments, GET /v1/meshes).
struct ListedAsset {
    std::string id;
    std::string source_id;  // the uploaded file's content id (a mesh's is its id)
    // The uploaded file's size and extension; nullopt when it is no longer stored (a damaged
    // store: the entry still answers, its map must be uploaded again).
    std::optional<StoredEntryInfo> source;
    std::chrono::system_clock::time_point stored;  // when the entry was stored
};

// One page of a listing in ascending order of id. A page may hold fewer than the limit (an
// entry that could not be read is left out); next_after, when set, is the cursor of the next.
struct ListedPage {
    std::vector<ListedAsset> entries;
    std::optional<std::string> next_after;
};

// The page of ids (in ascending order, as the store lists up to limit + 1 of them after the
// cursor): the first limit described (an id describe() gives nothing for is left out), and
// next_after when more follow. A limit of 0 is a bug of the caller (oer::Error, Internal).
template <typename Describe>
ListedPage listed_page(std::vector<std::string> ids, std::size_t limit, Describe describe) {
    if (limit == 0) {
        throw Error(ErrorKind::Internal, "a listing's page holds at least one entry");
    }
    ListedPage page;
    if (ids.size() > limit) {
        ids.resize(limit);
        page.next_after = ids.back();
    }
    for (const std::string& id : ids) {
        if (std::optional<ListedAsset> entry = describe(id)) {
            page.entries.push_back(std::move(*entry));
        }
    }
    return page;
}

template <typename Asset>
class AssetRegistry {
  public:
    using Pointer = std::shared_ptr<const Asset>;
    using Make = std::function<Pointer()>;
    using MakeStoppable = std::function<Pointer(const std::stop_token&)>;

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
        const std::shared_lock store_lock(store_mutex_);
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

    // known(): the asset when id is there already (cached), else nullptr; it runs without the
    // store lock, so it may call find() (and guarded() for writes). make(): decodes, stores and
    // remember()s it, under the store lock; run once per id however many uploads of it overlap.
    Upload upload(const std::string& id, const Make& known, const Make& make) {
        return upload(id, known, [&](const std::stop_token&) { return make(); }, {});
    }

    // The same, for a making that can be stopped: make's token is stopped once every caller
    // waiting for id has had its `stop` requested (see the top of this file). Throws oer::Error
    // (Cancelled) once this caller's stop is requested.
    Upload upload(const std::string& id, const Make& known, const MakeStoppable& make,
                  const std::stop_token& stop) {
        for (;;) {
            if (auto found = known()) {
                return {std::move(found), true};
            }
            std::unique_lock lock(in_flight_mutex_);
            const auto running = in_flight_.find(id);
            if (running != in_flight_.end()) {
                const Making making = running->second;
                lock.unlock();
                if (!making.callers->join()) {
                    // Stopping: wait for it to end (whatever its outcome), then start again.
                    making.result.wait();
                    continue;
                }
                const std::stop_callback leave(stop, [&] { making.callers->leave(); });
                while (making.result.wait_for(kStopPollInterval) != std::future_status::ready) {
                    throw_if_stopped(stop, "the wait for " + id);
                }
                return {making.result.get(), true};
            }
            // Finished between known() above and this lock: remembered before it left
            // in_flight_.
            if (auto finished = assets_.get(id)) {
                return {std::move(finished), true};
            }
            std::promise<Pointer> promise;
            const auto callers = std::make_shared<Callers>();
            callers->join();
            in_flight_.emplace(id, Making{promise.get_future().share(), callers});
            lock.unlock();
            const auto finish = [&] {
                const std::lock_guard finished_lock(in_flight_mutex_);
                in_flight_.erase(id);
            };
            try {
                const std::stop_callback leave(stop, [&] { callers->leave(); });
                Pointer made = [&] {
                    const std::shared_lock store_lock(store_mutex_);
                    return make(callers->token());
                }();
                promise.set_value(made);
                finish();
                return {std::move(made), false};
            } catch (...) {
                promise.set_exception(std::current_exception());
                finish();
                throw;
            }
        }
    }

    // Whether id is in memory, without counting a hit or a miss (a caller that only asks).
    bool remembered(const std::string& id) { return assets_.get(id) != nullptr; }

    void remember(const std::string& id, const Pointer& asset, std::size_t charge) {
        assets_.put(id, asset, charge);
    }

    // Runs action (a read or write of the store outside find and upload's make) under the
    // store lock, shared.
    template <typename Action>
    auto guarded(Action action) {
        const std::shared_lock store_lock(store_mutex_);
        return action();
    }

    // Runs erase_stored() (which removes id's entries from the store, and says whether there
    // were any) with the store lock held exclusively, then forgets id in memory.
    bool remove(const std::string& id, const std::function<bool()>& erase_stored) {
        const std::unique_lock store_lock(store_mutex_);
        const bool removed = erase_stored();
        assets_.erase(id);
        return removed;
    }

  private:
    // How often a caller waiting for another's making looks at its own stop token.
    static constexpr std::chrono::milliseconds kStopPollInterval{50};

    // The callers waiting for one making; the last to leave stops it.
    class Callers {
      public:
        // Counts a caller in; false when the making is stopping already.
        bool join() {
            const std::lock_guard lock(mutex_);
            if (source_.stop_requested()) {
                return false;
            }
            ++count_;
            return true;
        }
        void leave() {
            const std::lock_guard lock(mutex_);
            if (--count_ == 0) {
                source_.request_stop();
            }
        }
        std::stop_token token() const { return source_.get_token(); }

      private:
        std::mutex mutex_;
        std::stop_source source_;
        int count_ = 0;
    };

    struct Making {
        std::shared_future<Pointer> result;
        std::shared_ptr<Callers> callers;
    };

    ServiceMetrics& metrics_;
    const CacheName cache_;
    Pointer preset_;
    SharedLruCache<Asset> assets_;
    // Assets being made, by id.
    std::mutex in_flight_mutex_;
    std::map<std::string, Making> in_flight_;
    // Shared by reads and writes of the store, exclusive for removals.
    std::shared_mutex store_mutex_;
};

}  // namespace oer::server
