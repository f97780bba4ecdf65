#pragma once
// A least-recently-used cache bounded by bytes rather than entries, because what it holds
// (encoded frames, decoded assets) ranges from kilobytes to hundreds of megabytes. Values are
// shared and immutable, so a reader keeps its value alive after the cache evicts it.
#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

namespace oer::server {

class ByteLruCache {
  public:
    struct Stats {
        std::uint64_t hits = 0;
        std::uint64_t misses = 0;
        std::size_t entries = 0;
        std::size_t bytes = 0;  // charged bytes: every entry's key size plus value size
        std::size_t capacity_bytes = 0;
    };

    explicit ByteLruCache(std::size_t capacity_bytes);

    // The value and a hit (it becomes the most recently used), or nullptr and a miss.
    std::shared_ptr<const std::string> get(const std::string& key);

    // Stores or replaces key's value as the most recently used entry, evicting the least
    // recently used ones until the total fits. An entry charged more than the capacity is not
    // stored (and any older value under key is dropped, so a get never sees a stale one).
    // A null value throws oer::Error (Internal).
    void put(const std::string& key, std::shared_ptr<const std::string> value);

    bool erase(const std::string& key);  // true if key was there
    Stats stats() const;

  private:
    struct Entry {
        std::string key;
        std::shared_ptr<const std::string> value;
        std::size_t charge;
    };
    using Recency = std::list<Entry>;  // front: most recently used

    void drop(Recency::iterator entry);  // with mutex_ held

    mutable std::mutex mutex_;
    const std::size_t capacity_bytes_;
    std::size_t bytes_ = 0;
    std::uint64_t hits_ = 0;
    std::uint64_t misses_ = 0;
    Recency recency_;
    std::unordered_map<std::string, Recency::iterator> index_;
};

}  // namespace oer::server
