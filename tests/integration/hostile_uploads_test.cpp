// The upload memory bound through the API: no upload of N bytes raises the server's resident
// memory by more than max(64 MiB, 40 x N), with 8 such uploads at once. Each hostile file of
// tests/data/hostile (a few hundred bytes whose header claims an 8k map or millions of
// vertices) is sent 8 times at once; every answer is a 4xx naming the problem, and the peak
// resident memory of the process (the server runs in it) stays within the bound.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "http_support.hpp"
#include "process_memory.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

constexpr int kAtOnce = 8;

struct HostileUpload {
    std::string file;
    std::string path;  // the route
    std::string media_type;
};

std::string read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST(HostileUploads, EightAtOnceStayWithinMaxOf64MiBAnd40TimesTheirSize) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.access_log = false;
    TestServer server(config);
    const std::vector<HostileUpload> uploads{
        {"radiance-8192x8192.hdr", "/v1/environments", "image/vnd.radiance"},
        {"openexr-8192x4096-chunk-table.exr", "/v1/environments", "image/x-exr"},
        {"openexr-8192x4096-zip-chunks.exr", "/v1/environments", "image/x-exr"},
        {"png-8192x4096.png", "/v1/environments", "image/png"},
        {"jpeg-baseline-8192x4096.jpg", "/v1/environments", "image/jpeg"},
        {"jpeg-progressive-8192x4096.jpg", "/v1/environments", "image/jpeg"},
        {"gltf-accessor-4000000-vertices.gltf", "/v1/meshes", "model/gltf+json"},
    };
    // Warm the server's thread-local and allocator state with one round first.
    for (const bool measured : {false, true}) {
        for (const HostileUpload& upload : uploads) {
            const std::string bytes =
                read_file(std::filesystem::path(OER_HOSTILE_DATA_DIR) / upload.file);
            ASSERT_FALSE(bytes.empty()) << upload.file;
            ASSERT_TRUE(oer::testing::reset_peak_resident());
            const long before = oer::testing::resident_kib();
            std::vector<int> statuses(kAtOnce);
            std::vector<std::string> details(kAtOnce);
            std::vector<std::thread> clients;
            for (int i = 0; i < kAtOnce; ++i) {
                clients.emplace_back([&, i] {
                    auto client = server.client();
                    const auto answer = client->Post(upload.path, bytes, upload.media_type);
                    statuses[std::size_t(i)] = answer ? answer->status : -1;
                    details[std::size_t(i)] = answer ? answer->body : "";
                });
            }
            for (std::thread& client : clients) {
                client.join();
            }
            const double growth = double(oer::testing::peak_resident_kib() - before) * 1024.0;
            if (!measured) {
                continue;
            }
            for (int i = 0; i < kAtOnce; ++i) {
                EXPECT_TRUE(statuses[std::size_t(i)] == 413 || statuses[std::size_t(i)] == 422)
                    << upload.file << ": " << statuses[std::size_t(i)] << " "
                    << details[std::size_t(i)];
            }
            const double bound = std::max(64.0 * (1 << 20), 40.0 * double(bytes.size()));
            EXPECT_LE(growth, bound) << upload.file;
            std::printf("%s (%zu bytes) x %d: peak resident +%.1f MiB (bound %.0f MiB): %s\n",
                        upload.file.c_str(), bytes.size(), kAtOnce, growth / double(1 << 20),
                        bound / double(1 << 20), details[0].substr(0, 160).c_str());
        }
    }
}
