// Renders whose cost is over the service's budgets (server/src/render_cost.hpp), at its default
// budgets: each is refused with 413 before any of it runs, within 2 s, naming its estimate and
// the budget, while the process's peak memory and its data folder stay as they were. Each case
// is one that, unrefused, took seconds to minutes, gigabytes of memory or of disk.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "http_support.hpp"
#include "oer/lighting/equirect.hpp"
#include "process_memory.hpp"

using namespace oer;
using namespace oer::itest;
using Clock = std::chrono::steady_clock;

namespace {

std::uint64_t folder_bytes(const std::filesystem::path& folder) {
    std::uint64_t bytes = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
        if (entry.is_regular_file()) {
            bytes += entry.file_size();
        }
    }
    return bytes;
}

class RenderBudget : public ::testing::Test {
  protected:
    void SetUp() override {
        server_ = std::make_unique<TestServer>(test_config(root_.data()));
        client_ = server_->client();
    }

    // POSTs body and checks the refusal: 413, limit-exceeded, within 2 s, its estimate over
    // the budget it names (`over`: memory_bytes, seconds or transfer_bytes), the detail
    // containing `says`, nothing held or stored afterwards.
    void expect_refused(const Json& body, const std::string& over, const std::string& says) {
        ASSERT_TRUE(oer::testing::reset_peak_resident());
        const long resident_before = oer::testing::peak_resident_kib();
        const std::uint64_t stored_before = folder_bytes(root_.data());
        const auto start = Clock::now();
        const auto result = post_json(*client_, "/v1/render", body);
        const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
        ASSERT_TRUE(result);
        expect_problem("POST", "/v1/render", result, server::ProblemKind::LimitExceeded);
        EXPECT_LT(seconds, 2.0);
        const Json problem = Json::parse(result->body);
        ASSERT_TRUE(problem.contains("estimate") && problem.contains("budget")) << result->body;
        EXPECT_GT(problem["estimate"][over].get<double>(), problem["budget"][over].get<double>())
            << result->body;
        EXPECT_NE(problem["detail"].get<std::string>().find(says), std::string::npos)
            << problem["detail"];
        EXPECT_LE(oer::testing::peak_resident_kib() - resident_before, 256 << 10);
        EXPECT_LE(folder_bytes(root_.data()), stored_before + (64 << 20));
    }

    std::string upload_obj(const std::string& text) {
        const Json mesh = upload_mesh(*client_, text, "model/obj");
        return mesh.value("id", "");
    }

    TempRoot root_;
    std::unique_ptr<TestServer> server_;
    std::unique_ptr<httplib::Client> client_;
};

// A dim sky with sixteen bright lamps around the horizon, alternately low and high.
HdrImage sixteen_lamps() {
    HdrImage image(512, 256);
    std::vector<glm::dvec3> lamps;
    for (int i = 0; i < 16; ++i) {
        const double azimuth = i * std::numbers::pi / 8.0;
        const double elevation = (i % 2 == 0 ? 20.0 : 50.0) * std::numbers::pi / 180.0;
        lamps.push_back({std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                         std::cos(elevation) * std::sin(azimuth)});
    }
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const glm::dvec3 d = equirect::pixel_direction(x, y, image.width, image.height);
            float value = 0.2f;
            for (const glm::dvec3& lamp : lamps) {
                if (glm::dot(d, lamp) > std::cos(4.0 * std::numbers::pi / 180.0)) {
                    value = 200.0f;
                }
            }
            float* pixel = &image.pixels[(std::size_t(y) * image.width + x) * 3];
            pixel[0] = pixel[1] = pixel[2] = value;
        }
    }
    return image;
}

Json objects_of(const std::string& mesh, int count) {
    Json objects = Json::array();
    for (int i = 0; i < count; ++i) {
        objects.push_back(
            {{"mesh", mesh},
             {"transform",
              {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, double(i % 8), 0, double(i / 8), 1}}});
    }
    return objects;
}

}  // namespace

// 64 copies of the built-in product with occlusion on: a 242 MB transfer and 14.5 s of baking.
TEST_F(RenderBudget, SixtyFourObjectsWithOcclusionAreRefusedForTheirTransfer) {
    expect_refused({{"environment", "default"},
                    {"objects", objects_of("default", 64)},
                    {"width", 64},
                    {"height", 64}},
                   "transfer_bytes", "of disk for its occlusion transfer");
}

// 64 copies of a mesh of 2 x 500^2 = 500 000 triangles: 32 million triangles drawn in each of
// the frame's passes.
TEST_F(RenderBudget, SixtyFourCopiesOfALargeMeshAreRefusedForTheirTime) {
    const std::string grid = upload_obj(grid_obj(500));
    ASSERT_FALSE(grid.empty());
    expect_refused({{"environment", "default"},
                    {"objects", objects_of(grid, 64)},
                    {"occlusion", false},
                    {"width", 64},
                    {"height", 64}},
                   "seconds", "of rendering time");
}

// Sixteen shadowing lights at 8192 x 8192: 4 GiB of shadow maps for a 64 x 64 frame.
TEST_F(RenderBudget, SixteenShadowMapsOf8192AreRefusedForTheirMemory) {
    const Json rig = upload_environment(*client_, exr_bytes(sixteen_lamps()), "image/x-exr",
                                        "light_count=16&max_lights=16&clusters=16");
    ASSERT_FALSE(::testing::Test::HasFatalFailure());
    ASSERT_EQ(rig.at("lights").size(), 16u) << rig.dump();
    expect_refused({{"environment", rig.at("id")},
                    {"objects", {{{"mesh", "default"}}}},
                    {"occlusion", false},
                    {"shadows", {{"resolution", 8192}}},
                    {"width", 64},
                    {"height", 64}},
                   "memory_bytes", "shadow maps 4096 MiB");
}

// The largest frame at the most samples: 4096 x 4096 x 8 samples of render targets (11 GiB).
TEST_F(RenderBudget, TheLargestFrameAtEightSamplesIsRefusedForItsMemory) {
    expect_refused({{"environment", "default"},
                    {"objects", {{{"mesh", "default"}}}},
                    {"occlusion", false},
                    {"samples", 8},
                    {"width", 4096},
                    {"height", 4096}},
                   "memory_bytes", "frame targets");
}

// What the budgets leave: the default scene, occluded, at the default size, renders.
TEST_F(RenderBudget, TheDefaultSceneRendersWithinTheBudgets) {
    const auto result = post_json(
        *client_, "/v1/render", {{"environment", "default"}, {"objects", {{{"mesh", "default"}}}}});
    ASSERT_TRUE(result);
    EXPECT_EQ(result->status, 200) << result->body;
}

// Each address's share of uncached rendering: one that asks for frame after frame is answered
// 429 with Retry-After once its share is spent, while another address still gets its frames,
// and frames from the cache never count.
TEST(RenderBudgetShare, AClientPastItsShareGets429WhileOthersAndCachedFramesAreServed) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.client_render_rate = 0.2;  // seconds of estimated work a second
    config.max_render_seconds = 2;    // the most a client saves up
    TestServer server(config);
    const auto flooder = load_client(server.port(), 1, 60);
    const auto other = load_client(server.port(), 2, 60);
    const auto frame = [](int yaw) {
        return "/v1/render?environment=default&mesh=default&width=512&height=512&occlusion=off"
               "&yaw=" +
               std::to_string(yaw);
    };
    int refused_at = -1;
    for (int yaw = 0; yaw < 40 && refused_at < 0; ++yaw) {
        const auto result = flooder->Get(frame(yaw));
        ASSERT_TRUE(result);
        if (result->status == 429) {
            refused_at = yaw;
            expect_problem("GET", "/v1/render", result, server::ProblemKind::TooManyRenders);
            EXPECT_GE(std::stoi(result->get_header_value("Retry-After")), 1);
        } else {
            ASSERT_EQ(result->status, 200) << result->body;
        }
    }
    ASSERT_GT(refused_at, 0) << "the flooding address was never refused";
    // Another address renders; the flooder's frames already rendered come from the cache.
    const auto others = other->Get(frame(-100));
    ASSERT_TRUE(others);
    EXPECT_EQ(others->status, 200) << others->body;
    const auto cached = flooder->Get(frame(0));
    ASSERT_TRUE(cached);
    EXPECT_EQ(cached->status, 200);
    EXPECT_EQ(cached->get_header_value("X-Oer-Cache"), "hit");
}
