#include "oer/server/byte_lru_cache.hpp"

#include "oer/error.hpp"

namespace oer::server {

ByteLruCache::ByteLruCache(std::size_t capacity_bytes) : capacity_bytes_(capacity_bytes) {}

std::shared_ptr<const std::string> ByteLruCache::get(const std::string& key) {
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

void ByteLruCache::put(const std::string& key, std::shared_ptr<const std::string> value) {
    if (!value) {
        throw Error(ErrorKind::Internal, "ByteLruCache::put: null value for key \"" + key + "\"");
    }
    const std::size_t charge = key.size() + value->size();
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

bool ByteLruCache::erase(const std::string& key) {
    const std::lock_guard lock(mutex_);
    const auto found = index_.find(key);
    if (found == index_.end()) {
        return false;
    }
    drop(found->second);
    return true;
}

ByteLruCache::Stats ByteLruCache::stats() const {
    const std::lock_guard lock(mutex_);
    return Stats{hits_, misses_, index_.size(), bytes_, capacity_bytes_};
}

void ByteLruCache::drop(Recency::iterator entry) {
    bytes_ -= entry->charge;
    index_.erase(entry->key);
    recency_.erase(entry);
}

}  // namespace oer::server
