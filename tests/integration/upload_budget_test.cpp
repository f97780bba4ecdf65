// The upload budget through the API: a map whose bytes really encode far more pixels than its
// size (a run-length .hdr of one colour) is refused 413 before it is decoded, and an upload that
// finds every slot taken is answered 503 with Retry-After at once, then succeeds once the slot
// is free. The hostile files whose headers claim more than their bytes hold are the image
// library's tests (tests/image/hostile_images_test.cpp).
#include <gtest/gtest.h>

#include <thread>

#include "http_support.hpp"
#include "process_memory.hpp"

using namespace oer;
using namespace oer::itest;
using oer::server::ProblemKind;

namespace {

// A Radiance RGBE map of one grey, every scanline in the "new" run-length encoding (Ward,
// Graphics Gems II, "Real Pixels", 1991): a marker 2 2 width/256 width%256, then per component
// runs of at most 127 equal bytes, two bytes each. About 8 bytes per 127 pixels.
std::string constant_rle_hdr(int width, int height) {
    std::string bytes = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) +
                        " +X " + std::to_string(width) + "\n";
    const unsigned char grey[4] = {128, 128, 128, 128};  // 0.5 in R, G and B
    for (int y = 0; y < height; ++y) {
        bytes += {char(2), char(2), char(width >> 8), char(width & 255)};
        for (const unsigned char component : grey) {
            for (int left = width; left > 0; left -= 127) {
                bytes += char(128 + std::min(left, 127));
                bytes += char(component);
            }
        }
    }
    return bytes;
}

httplib::Result post_map(httplib::Client& client, const std::string& bytes) {
    return client.Post("/v1/environments", bytes, "image/vnd.radiance");
}

}  // namespace

TEST(UploadBudgetOverHttp, AMapThatExpandsBeyondItsMultipleIs413BeforeDecoding) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    TestServer server(config);
    auto client = server.client();
    // 4096 x 2048 in 0.55 MB: decoding and preprocessing would take about 200 MiB, more than
    // max(64 MiB, 200 x 0.55 MB).
    const std::string bomb = constant_rle_hdr(4096, 2048);
    ASSERT_LT(bomb.size(), std::size_t(600'000));
    const long before = oer::testing::resident_kib();
    const auto refused = post_map(*client, bomb);
    const long growth_mib = (oer::testing::resident_kib() - before) / 1024;
    expect_problem("POST", "/v1/environments", refused, ProblemKind::LimitExceeded);
    ASSERT_TRUE(refused);
    EXPECT_NE(refused->body.find("a 4096x2048 map would take"), std::string::npos) << refused->body;
    EXPECT_NE(refused->body.find("200 times their size"), std::string::npos) << refused->body;
    // Refused from its header: nothing near its 96 MiB of pixels was allocated.
    EXPECT_LT(growth_mib, 32);
    // The same map at a scale its bytes may reach is accepted.
    EXPECT_EQ(post_map(*client, constant_rle_hdr(1024, 512))->status, 201);
}

TEST(UploadBudgetOverHttp, AnUploadThatFindsTheSlotsTakenIs503UntilOneIsFree) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.max_concurrent_uploads = 1;
    config.max_upload_expansion = 0;  // the large constant map below is allowed
    TestServer server(config);
    auto first_client = server.client();
    auto client = server.client();
    // Long enough to preprocess (about a second here) that the second upload meets it.
    const std::string large = constant_rle_hdr(4096, 2048);
    int first_status = 0;
    std::thread uploader([&] {
        const auto first = post_map(*first_client, large);
        first_status = first ? first->status : -1;
    });
    const bool decoding =
        eventually([&] { return scrape(*client).sum("oer_uploads_decoding") == 1.0; },
                   std::chrono::seconds(10));
    const auto refused = post_map(*client, constant_rle_hdr(64, 32));
    uploader.join();
    ASSERT_TRUE(decoding) << "the first upload was never seen decoding";
    expect_problem("POST", "/v1/environments", refused, ProblemKind::Unavailable);
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->get_header_value("Retry-After"), "1");
    EXPECT_NE(refused->body.find("as many uploads as it may at once (1 of 1"), std::string::npos)
        << refused->body;
    EXPECT_EQ(first_status, 201);
    EXPECT_EQ(scrape(*client).sum("oer_uploads_decoding"), 0.0);
    EXPECT_EQ(scrape(*client).sum("oer_upload_reserved_bytes"), 0.0);
    EXPECT_EQ(post_map(*client, constant_rle_hdr(64, 32))->status, 201);
}
