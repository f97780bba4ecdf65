// The byte-bounded LRU cache: hit and miss counts, eviction order by recency, the byte bound
// (keys and values charged), oversized entries, replacement, and concurrent use.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/server/byte_lru_cache.hpp"

using oer::server::ByteLruCache;

namespace {

std::shared_ptr<const std::string> value(std::size_t size, char fill = 'v') {
    return std::make_shared<const std::string>(size, fill);
}

}  // namespace

TEST(ByteLruCache, CountsHitsAndMisses) {
    ByteLruCache cache(100);
    EXPECT_EQ(cache.get("a"), nullptr);
    cache.put("a", std::make_shared<const std::string>("alpha"));
    const auto got = cache.get("a");
    ASSERT_NE(got, nullptr);
    EXPECT_EQ(*got, "alpha");
    EXPECT_EQ(cache.get("b"), nullptr);
    const ByteLruCache::Stats stats = cache.stats();
    EXPECT_EQ(stats.hits, 1u);
    EXPECT_EQ(stats.misses, 2u);
    EXPECT_EQ(stats.entries, 1u);
    EXPECT_EQ(stats.bytes, 6u);  // key "a" + value "alpha"
    EXPECT_EQ(stats.capacity_bytes, 100u);
}

TEST(ByteLruCache, EvictsTheLeastRecentlyUsedUntilTheNewEntryFits) {
    ByteLruCache cache(30);
    cache.put("a", value(9));  // each entry is charged 10 bytes
    cache.put("b", value(9));
    cache.put("c", value(9));
    EXPECT_EQ(cache.stats().bytes, 30u);
    ASSERT_NE(cache.get("a"), nullptr);  // "b" is now the least recently used
    cache.put("d", value(9));
    EXPECT_EQ(cache.get("b"), nullptr);
    EXPECT_NE(cache.get("a"), nullptr);
    EXPECT_NE(cache.get("c"), nullptr);
    EXPECT_NE(cache.get("d"), nullptr);
    cache.put("e", value(19));  // needs two entries' room: "a" and "c" are the oldest
    EXPECT_EQ(cache.get("a"), nullptr);
    EXPECT_EQ(cache.get("c"), nullptr);
    EXPECT_NE(cache.get("d"), nullptr);
    EXPECT_NE(cache.get("e"), nullptr);
    EXPECT_EQ(cache.stats().entries, 2u);
    EXPECT_EQ(cache.stats().bytes, 30u);
}

TEST(ByteLruCache, ReplacingAValueRechargesItsBytes) {
    ByteLruCache cache(100);
    cache.put("key", value(50));
    cache.put("key", value(7, 'w'));
    EXPECT_EQ(*cache.get("key"), "wwwwwww");
    EXPECT_EQ(cache.stats().entries, 1u);
    EXPECT_EQ(cache.stats().bytes, 10u);
}

TEST(ByteLruCache, AnEntryLargerThanTheCapacityIsNotStoredAndDropsTheOldValue) {
    ByteLruCache cache(20);
    cache.put("a", value(5));
    cache.put("k", value(10));
    cache.put("k", value(20));  // 21 bytes with its key
    EXPECT_EQ(cache.get("k"), nullptr);
    EXPECT_NE(cache.get("a"), nullptr);
    EXPECT_EQ(cache.stats().entries, 1u);
    EXPECT_EQ(cache.stats().bytes, 6u);
    cache.put("x", value(19));  // exactly the capacity: stored, "a" evicted
    EXPECT_NE(cache.get("x"), nullptr);
    EXPECT_EQ(cache.get("a"), nullptr);
    EXPECT_EQ(cache.stats().bytes, 20u);
}

TEST(ByteLruCache, EraseRemovesOnce) {
    ByteLruCache cache(100);
    cache.put("a", value(3));
    EXPECT_TRUE(cache.erase("a"));
    EXPECT_FALSE(cache.erase("a"));
    EXPECT_EQ(cache.get("a"), nullptr);
    EXPECT_EQ(cache.stats().bytes, 0u);
    EXPECT_EQ(cache.stats().entries, 0u);
}

TEST(ByteLruCache, AValueOutlivesItsEviction) {
    ByteLruCache cache(10);
    cache.put("a", std::make_shared<const std::string>("12345678"));
    const auto held = cache.get("a");
    cache.put("b", value(9));
    EXPECT_EQ(cache.get("a"), nullptr);
    EXPECT_EQ(*held, "12345678");
}

TEST(ByteLruCache, ANullValueIsABug) {
    ByteLruCache cache(10);
    try {
        cache.put("a", nullptr);
        FAIL() << "no error";
    } catch (const oer::Error& error) {
        EXPECT_EQ(error.kind(), oer::ErrorKind::Internal);
    }
    EXPECT_EQ(cache.stats().entries, 0u);
}

TEST(ByteLruCache, ConcurrentPutsAndGetsKeepTheBoundAndTheCounts) {
    constexpr std::size_t kCapacity = 4000;
    ByteLruCache cache(kCapacity);
    constexpr int kThreads = 8, kOperations = 5000, kKeys = 64;
    std::vector<int> wrong_values(kThreads, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            for (int i = 0; i < kOperations; ++i) {
                // Each key always holds one value, of its own length and letter, so any mix-up
                // shows.
                const int k = (i * 7 + t * 13) % kKeys;
                const std::string key = "key" + std::to_string(k);
                const std::string expected(std::size_t(50 + k), char('A' + k % 26));
                if (i % 3 == 0) {
                    cache.put(key, std::make_shared<const std::string>(expected));
                } else if (const auto got = cache.get(key); got && *got != expected) {
                    ++wrong_values[t];
                }
            }
        });
    }
    for (auto& thread : threads) {
        thread.join();
    }
    EXPECT_EQ(wrong_values, std::vector<int>(kThreads, 0));
    const ByteLruCache::Stats stats = cache.stats();
    std::uint64_t gets_per_thread = 0;
    for (int i = 0; i < kOperations; ++i) {
        gets_per_thread += i % 3 != 0;
    }
    EXPECT_EQ(stats.hits + stats.misses, gets_per_thread * kThreads);
    EXPECT_GT(stats.hits, 0u);
    EXPECT_LE(stats.bytes, kCapacity);
    std::size_t charged = 0;
    for (int k = 0; k < kKeys; ++k) {
        const std::string key = "key" + std::to_string(k);
        if (const auto got = cache.get(key)) {
            charged += key.size() + got->size();
        }
    }
    EXPECT_EQ(charged, stats.bytes);
}
