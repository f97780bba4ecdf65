// The hostile images of tests/data/hostile (small files whose headers claim far more pixels
// than their bytes can hold): each is refused, naming the claim and the bytes, quickly and
// without the memory its claim would take. The growth of resident memory while loading each is
// printed and held under max(64 MiB, 40 x the file's size).
#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"
#include "process_memory.hpp"

using namespace oer;
namespace fs = std::filesystem;

namespace {

std::vector<std::byte> read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> chars((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
    std::vector<std::byte> bytes(chars.size());
    std::memcpy(bytes.data(), chars.data(), chars.size());
    return bytes;
}

struct Cost {
    double seconds = 0.0;
    long resident_growth_kib = 0;
};

// Time and peak resident growth of body, which must throw an oer::Error of `kind` whose
// message contains every one of `needles`.
Cost refused_cost(const std::function<void()>& body, ErrorKind kind,
                  const std::vector<std::string>& needles, const std::string& context) {
    malloc_trim(0);  // freed memory back to the system, so that growth is new pages
    const bool reset = oer::testing::reset_peak_resident();
    EXPECT_TRUE(reset) << "/proc/self/clear_refs refused: the peak counts from the start";
    const long before = oer::testing::resident_kib();
    const auto start = std::chrono::steady_clock::now();
    try {
        body();
        ADD_FAILURE() << context << ": loaded";
    } catch (const Error& error) {
        EXPECT_EQ(int(error.kind()), int(kind)) << context << ": " << error.what();
        for (const std::string& needle : needles) {
            EXPECT_NE(std::string(error.what()).find(needle), std::string::npos)
                << context << ": '" << error.what() << "' does not say '" << needle << "'";
        }
    }
    Cost cost;
    cost.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    cost.resident_growth_kib = oer::testing::peak_resident_kib() - before;
    return cost;
}

struct Hostile {
    std::string file;
    std::string claim;   // "8192x8192"
    std::string scheme;  // what the minimum is made of, as the message says it
};

const std::vector<Hostile> kHostileImages = {
    {"radiance-8192x8192.hdr", "8192x8192", "RLE needs at least"},
    {"openexr-8192x4096-chunk-table.exr", "8192x4096", "chunk offset table"},
    {"openexr-8192x4096-zip-chunks.exr", "8192x4096", "deflate"},
    {"png-8192x4096.png", "8192x4096", "deflate"},
    {"jpeg-progressive-8192x4096.jpg", "8192x4096", "8x8 block"},
    {"jpeg-baseline-8192x4096.jpg", "8192x4096", "8x8 block"},
};

}  // namespace

TEST(HostileImages, ClaimsBeyondTheirBytesAreRefusedCheaply) {
    const fs::path folder = OER_HOSTILE_DATA_DIR;
    // Warm up OpenImageIO (plugin tables, thread pool) so that they are not counted.
    EXPECT_THROW(load_image_memory(read_bytes(folder / kHostileImages[0].file), "warm-up.hdr"),
                 Error);
    for (const Hostile& hostile : kHostileImages) {
        const std::vector<std::byte> bytes = read_bytes(folder / hostile.file);
        ASSERT_FALSE(bytes.empty()) << hostile.file;
        const std::string size = std::to_string(bytes.size()) + " bytes";
        const std::vector<std::string> needles = {hostile.file + ": claims " + hostile.claim +
                                                      " pixels but " + size + " cannot hold them",
                                                  hostile.scheme};
        for (const bool probe : {false, true}) {
            const Cost cost = refused_cost(
                [&] {
                    if (probe) {
                        probe_image_memory(bytes, hostile.file);
                    } else {
                        load_image_memory(bytes, hostile.file);
                    }
                },
                ErrorKind::InvalidInput, needles, hostile.file);
            const long bound_kib = std::max<long>(64 << 10, long(40 * bytes.size() / 1024));
            std::cout << "[          ] " << hostile.file << " (" << size << ", "
                      << (probe ? "probe" : "load") << "): refused in " << cost.seconds * 1e3
                      << " ms, resident +" << cost.resident_growth_kib << " KiB\n";
            EXPECT_LT(cost.seconds, 1.0) << hostile.file;
            EXPECT_LT(cost.resident_growth_kib, bound_kib) << hostile.file;
        }
    }
}
