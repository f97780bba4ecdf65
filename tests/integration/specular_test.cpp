// The specular cube of a rig in the service (EnvironmentRegistry::specular): made when a frame
// has a glossy material (the default product's stand), stored by rig id beside the rig, read
// back after a restart without recomputation, recomputed when its stored entry is damaged,
// made once for concurrent frames, and never made for a Lambertian scene (an OBJ) or a
// thesis-model rig; the built-in studio's cube is made before a warm server is ready, and
// otherwise at its first glossy frame.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <latch>
#include <thread>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

std::filesystem::path specular_entry(const TempRoot& root, const std::string& rig_id) {
    return root.data() / "specular" / (rig_id + ".sealed");
}

httplib::Result render(httplib::Client& client, const std::string& environment,
                       const std::string& mesh, int width = 48) {
    return post_json(client, "/v1/render",
                     {{"environment", environment},
                      {"objects", {{{"mesh", mesh}}}},
                      {"width", width},
                      {"height", 32},
                      {"format", "png"},
                      {"samples", 1}});
}

void expect_rendered(const httplib::Result& result) {
    ASSERT_TRUE(result) << "no answer";
    EXPECT_EQ(result->status, 200) << result->body;
}

double specular_computed(httplib::Client& client) {
    return scrape(client).sum("oer_specular_computed_total");
}

}  // namespace

TEST(Specular, GlossyProductStoresTheCubeWhichARestartReadsBack) {
    TempRoot root;
    const std::string bytes = exr_bytes(three_disc_environment(128, 64).image);
    std::string id;
    {
        TestServer first(test_config(root.data()));
        auto client = first.client();
        const Json uploaded = upload_environment(*client, bytes, "image/x-exr");
        ASSERT_TRUE(uploaded.is_object());
        id = uploaded.at("id");
        EXPECT_FALSE(std::filesystem::exists(specular_entry(root, id)))
            << "the upload alone made the cube";
        expect_rendered(render(*client, id, "default"));
        EXPECT_TRUE(std::filesystem::exists(specular_entry(root, id)));
        EXPECT_EQ(specular_computed(*client), 1.0);
        // Another frame of the same scene: the cube from memory.
        expect_rendered(render(*client, id, "default", 64));
        EXPECT_EQ(specular_computed(*client), 1.0);
        EXPECT_GE(scrape(*client).sum("oer_cache_hits_total", {{"cache", "specular"}}), 1.0);
        EXPECT_EQ(scrape(*client).sum("oer_specular_seconds_count"), 1.0);
    }
    TestServer second(test_config(root.data()));
    auto client = second.client();
    expect_rendered(render(*client, id, "default"));
    EXPECT_EQ(specular_computed(*client), 0.0) << "recomputed after a restart";
}

TEST(Specular, ADamagedStoredCubeIsRecomputed) {
    TempRoot root;
    const std::string bytes = exr_bytes(three_disc_environment(128, 64).image);
    std::string id;
    {
        TestServer first(test_config(root.data()));
        auto client = first.client();
        const Json uploaded = upload_environment(*client, bytes, "image/x-exr");
        ASSERT_TRUE(uploaded.is_object());
        id = uploaded.at("id");
        expect_rendered(render(*client, id, "default"));
    }
    const std::filesystem::path entry = specular_entry(root, id);
    ASSERT_TRUE(std::filesystem::exists(entry));
    const auto size = std::filesystem::file_size(entry);
    std::filesystem::resize_file(entry, size / 2);

    TestServer second(test_config(root.data()));
    auto client = second.client();
    expect_rendered(render(*client, id, "default"));
    EXPECT_EQ(specular_computed(*client), 1.0);
    EXPECT_EQ(std::filesystem::file_size(entry), size) << "not stored again whole";
    bool logged = false;
    for (const std::string& line : second.log_lines()) {
        logged =
            logged || line.find("specular cube of rig " + id + " computed in") != std::string::npos;
    }
    EXPECT_TRUE(logged) << "no log line for the computation";
}

TEST(Specular, ConcurrentFramesComputeTheCubeOnce) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json uploaded = upload_environment(
        *client, exr_bytes(three_disc_environment(256, 128).image), "image/x-exr");
    ASSERT_TRUE(uploaded.is_object());
    const std::string id = uploaded.at("id");
    constexpr int kClients = 4;
    std::latch ready(kClients);
    std::vector<std::thread> threads;
    std::vector<int> statuses(kClients, 0);
    for (int i = 0; i < kClients; ++i) {
        threads.emplace_back([&, i] {
            auto own = server.client();
            ready.arrive_and_wait();
            const auto result = render(*own, id, "default", 40 + 8 * i);
            statuses[std::size_t(i)] = result ? result->status : -1;
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    for (const int status : statuses) {
        EXPECT_EQ(status, 200);
    }
    EXPECT_EQ(specular_computed(*client), 1.0);
}

TEST(Specular, LambertianSceneAndThesisRigMakeNoCube) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json mesh =
        upload_mesh(*client, box_obj({-0.5, 0.0, -0.5}, {0.5, 1.0, 0.5}), "model/obj");
    ASSERT_TRUE(mesh.is_object());
    const Json lambertian_environment =
        upload_environment(*client, exr_bytes(three_disc_environment(96, 48).image), "image/x-exr");
    ASSERT_TRUE(lambertian_environment.is_object());
    const std::string lambertian_id = lambertian_environment.at("id");
    expect_rendered(render(*client, lambertian_id, mesh.at("id")));

    const Json thesis = upload_environment(*client, exr_bytes(three_disc_environment(64, 32).image),
                                           "image/x-exr", "model=thesis");
    ASSERT_TRUE(thesis.is_object());
    const std::string thesis_id = thesis.at("id");
    expect_rendered(render(*client, thesis_id, "default"));

    EXPECT_EQ(specular_computed(*client), 0.0);
    EXPECT_FALSE(std::filesystem::exists(specular_entry(root, lambertian_id)));
    EXPECT_FALSE(std::filesystem::exists(specular_entry(root, thesis_id)));
    EXPECT_TRUE(std::filesystem::is_empty(root.data() / "specular"));
}

TEST(Specular, TheBuiltInStudioIsPrefilteredAtItsFirstGlossyFrameNotAtStart) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json mesh =
        upload_mesh(*client, box_obj({-0.5, 0.0, -0.5}, {0.5, 1.0, 0.5}), "model/obj");
    ASSERT_TRUE(mesh.is_object());
    expect_rendered(render(*client, "default", mesh.at("id")));
    EXPECT_EQ(specular_computed(*client), 0.0) << "a matte frame prefiltered the studio";

    expect_rendered(render(*client, "default", "default"));
    expect_rendered(render(*client, "default", "default", 64));
    EXPECT_EQ(specular_computed(*client), 1.0);
    bool logged = false;
    for (const std::string& line : server.log_lines()) {
        logged =
            logged || line.find("specular cube of rig default computed in") != std::string::npos;
    }
    EXPECT_TRUE(logged) << "no log line for the studio's prefilter";
}

TEST(Specular, AWarmServerPrefiltersTheStudioAndBakesTheDefaultSceneBeforeItIsReady) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.warm_default_scene = true;
    TestServer server(config);
    auto client = server.client();
    EXPECT_EQ(specular_computed(*client), 1.0);
    EXPECT_EQ(scrape(*client).sum("oer_transfers_computed_total"), 1.0);
    expect_rendered(render(*client, "default", "default"));
    EXPECT_EQ(specular_computed(*client), 1.0) << "the first default frame prefiltered again";
}
