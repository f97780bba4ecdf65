#pragma once
// The LRU cache of byte strings (encoded frames, previews): each entry is charged its key's and
// its value's size.
#include <memory>
#include <string>

#include "oer/server/shared_lru_cache.hpp"

namespace oer::server {

class ByteLruCache : public SharedLruCache<std::string> {
  public:
    using SharedLruCache<std::string>::SharedLruCache;

    // A null value throws oer::Error (Internal).
    void put(const std::string& key, std::shared_ptr<const std::string> value) {
        const std::size_t size = value ? value->size() : 0;
        SharedLruCache<std::string>::put(key, std::move(value), size);
    }
};

}  // namespace oer::server
