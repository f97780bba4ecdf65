#pragma once
// A least-recently-used cache bounded by bytes rather than entries, because what it holds
// (encoded frames, decoded maps, meshes, rigs) ranges from kilobytes to hundreds of megabytes.
// Values are shared and immutable, so a reader keeps its value alive after the cache evicts it.
// Thread-safe.
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

#include "oer/core/error.hpp"

namespace oer::server {

struct LruCacheStats {
    std::uint64_t hits = 0;
    std::uint64_t misses = 0;
    std::size_t entries = 0;
    std::size_t bytes = 0;  // charged bytes: every entry's key size plus its value's charge
    std::size_t capacity_bytes = 0;
};

template <typename Value>
class SharedLruCache {
  public:
    using Stats = LruCacheStats;

    explicit SharedLruCache(std::size_t capacity_bytes) : capacity_bytes_(capacity_bytes) {}

    // The value and a hit (it becomes the most recently used), or nullptr and a miss.
    std::shared_ptr<const Value> get(const std::string& key) {
        const std::lock_guard lock(mutex_);
        const auto found = index_.find(key);
        if (found == index_.end()) {
            ++misses_;
            return nullptr;
        }
        ++hits_;
        recency_.splice(recency_.begin(), recency_, found->second);
        return found->second->value;
    }

    // Stores or replaces key's value as the most recently used entry, charged key.size() +
    // value_bytes, evicting the least recently used ones until the total fits. An entry charged
    // more than the capacity is not stored (and any older value under key is dropped, so a get
    // never sees a stale one). A null value throws oer::Error (Internal).
    void put(const std::string& key, std::shared_ptr<const Value> value, std::size_t value_bytes) {
        if (!value) {
            throw Error(ErrorKind::Internal, "LRU cache put: null value for key \"" + key + "\"");
        }
        const std::size_t charge = key.size() + value_bytes;
        const std::lock_guard lock(mutex_);
        if (const auto found = index_.find(key); found != index_.end()) {
            drop(found->second);
        }
        if (charge > capacity_bytes_) {
            return;
        }
        while (bytes_ + charge > capacity_bytes_) {
            drop(std::prev(recency_.end()));
        }
        recency_.push_front(Entry{key, std::move(value), charge});
        index_.emplace(key, recency_.begin());
        bytes_ += charge;
    }

    bool erase(const std::string& key) {  // true if key was there
        const std::lock_guard lock(mutex_);
        const auto found = index_.find(key);
        if (found == index_.end()) {
            return false;
        }
        drop(found->second);
        return true;
    }

    Stats stats() const {
        const std::lock_guard lock(mutex_);
        return Stats{hits_, misses_, index_.size(), bytes_, capacity_bytes_};
    }

  private:
    struct Entry {
        std::string key;
        std::shared_ptr<const Value> value;
        std::size_t charge;
    };
    using Recency = std::list<Entry>;  // front: most recently used

    void drop(typename Recency::iterator entry) {  // with mutex_ held
        bytes_ -= entry->charge;
        index_.erase(entry->key);
        recency_.erase(entry);
    }

    mutable std::mutex mutex_;
    const std::size_t capacity_bytes_;
    std::size_t bytes_ = 0;
    std::uint64_t hits_ = 0;
    std::uint64_t misses_ = 0;
    Recency recency_;
    std::unordered_map<std::string, typename Recency::iterator> index_;
};

}  // namespace oer::server
