// Hostile glTF assets: a claim far beyond the bytes (tests/data/hostile), and JSON of many small
// values, made here (20 MB). Each is refused quickly, naming what is wrong, without the memory
// its claim or its parse would take; the growth of resident memory while loading each is
// printed and held under max(64 MiB, 40 x the asset's size).
#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "gltf_test_assets.hpp"
#include "process_memory.hpp"

using namespace oer;
using namespace oer::mesh_testing;

namespace {

struct Cost {
    double seconds = 0.0;
    long resident_growth_kib = 0;
};

Cost cost_of(const std::function<void()>& body) {
    malloc_trim(0);  // freed memory back to the system, so that growth is new pages
    EXPECT_TRUE(oer::testing::reset_peak_resident())
        << "/proc/self/clear_refs refused: the peak counts from the start";
    const long before = oer::testing::resident_kib();
    const auto start = std::chrono::steady_clock::now();
    body();
    Cost cost;
    cost.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    cost.resident_growth_kib = oer::testing::peak_resident_kib() - before;
    return cost;
}

void report_and_bound(const std::string& what, std::size_t bytes, const Cost& cost) {
    std::cout << "[          ] " << what << " (" << bytes << " bytes): " << cost.seconds * 1e3
              << " ms, resident +" << cost.resident_growth_kib << " KiB\n";
    if (oer::testing::kResidentMemoryIsTheProgramsOwn) {
        EXPECT_LT(cost.resident_growth_kib, std::max<long>(64 << 10, long(40 * bytes / 1024)))
            << what;
    }
}

// The one-triangle asset with `extras` (any JSON) as its first member.
std::string triangle_with_extras(const std::string& extras) {
    GltfBuilder b;
    b.positions(kTriangle);
    b.mesh(json::array({{{"attributes", {{"POSITION", 0}}}}}));
    b.node({{"mesh", 0}});
    const std::string text = b.gltf();
    return "{\"extras\":" + extras + "," + text.substr(1);
}

}  // namespace

TEST(HostileMeshes, AccessorClaimingMillionsOfVerticesOfA36ByteViewIsRefusedCheaply) {
    const std::vector<std::uint8_t> bytes =
        read_bytes(fs::path(OER_HOSTILE_DATA_DIR) / "gltf-accessor-4000000-vertices.gltf");
    ASSERT_FALSE(bytes.empty());
    const Cost cost = cost_of([&] {
        expect_error([&] { load_mesh_memory(as_bytes(bytes), "hostile.gltf", MeshFormat::Gltf); },
                     ErrorKind::InvalidInput,
                     {"hostile.gltf: mesh 0 primitive 0: POSITION: accessor 0 (4000000 elements of "
                      "12 bytes, stride 12, offset 0) runs past the end of bufferView 0 (36 "
                      "bytes)"});
    });
    report_and_bound("gltf-accessor-4000000-vertices.gltf", bytes.size(), cost);
    EXPECT_LT(cost.seconds, 1.0);
}

TEST(HostileMeshes, JsonOfTenMillionValuesIsRefusedWhileParsing) {
    // 20 MB: an array of 10^7 zeros in the asset's extras.
    std::string zeros = "[0";
    zeros.reserve(20'000'000);
    for (int i = 1; i < 10'000'000; ++i) {
        zeros += ",0";
    }
    zeros += "]";
    const std::string text = triangle_with_extras(zeros);
    zeros = std::string();
    const Cost cost = cost_of([&] {
        expect_error([&] { load_gltf_text(text); }, ErrorKind::LimitExceeded,
                     {"test.gltf: the JSON holds more than 131072 values, over the limit for a "
                      "glTF's JSON"});
    });
    report_and_bound("10^7 values", text.size(), cost);
    EXPECT_LT(cost.seconds, 1.0);
}

TEST(HostileMeshes, JsonJustUnderTheBoundLoadsWithinTheMemoryFigure) {
    // The costliest values a bounded document can hold: 65500 objects of one member each
    // (131000 values with the rest of the asset, under 2^17), through both parses (ours and
    // tinygltf's, which turns extras into tinygltf::Value).
    std::string objects = "[{\"k\":0}";
    for (int i = 1; i < 65'500; ++i) {
        objects += ",{\"k\":0}";
    }
    objects += "]";
    const std::string text = triangle_with_extras(objects);
    Cost cost = cost_of([&] { EXPECT_EQ(load_gltf_text(text, kUnrefined).triangle_count, 1u); });
    report_and_bound("2^17 values, loaded", text.size(), cost);
    // 100 objects more pass the bound.
    std::string more = objects.substr(0, objects.size() - 1);
    for (int i = 0; i < 100; ++i) {
        more += ",{\"k\":0}";
    }
    const std::string over = triangle_with_extras(more + "]");
    expect_error([&] { load_gltf_text(over); }, ErrorKind::LimitExceeded,
                 {"holds more than 131072 values"});
}
