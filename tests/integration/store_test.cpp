// The data folder across restarts: a rig computed before a restart is served after it without
// recomputation, and a damaged rig entry is detected, recomputed from its source and served
// correctly; concurrent uploads of one map compute its rig once, and of one mesh load it once.
#include <gtest/gtest.h>

#include <fstream>
#include <latch>
#include <thread>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

// The rig without what may differ between computations of the same rig.
Json comparable(Json rig) {
    rig.erase("cached");
    rig.erase("timings_ms");
    return rig;
}

Json get_rig(httplib::Client& client, const std::string& id) {
    const auto result = client.Get(("/v1/environments/" + id).c_str());
    if (!result || result->status != 200) {
        ADD_FAILURE() << "GET /v1/environments/" << id << ": "
                      << (result ? std::to_string(result->status) + " " + result->body
                                 : "no answer");
        return nullptr;
    }
    return expect_conforms("GET", "/v1/environments/{id}", result);
}

httplib::Result render_with(httplib::Client& client, const std::string& environment) {
    return post_json(client, "/v1/render",
                     {{"environment", environment},
                      {"objects", {{{"mesh", "default"}}}},
                      {"width", 48},
                      {"height", 32},
                      {"format", "png"},
                      {"samples", 1}});
}

// The answers of 4 clients that send the same upload at the same moment (released together by a
// latch), so that the later ones arrive while the first is still being processed.
template <class Upload>
std::vector<Json> at_once(const TestServer& server, Upload upload) {
    constexpr int kClients = 4;
    std::vector<Json> answers(kClients);
    std::latch ready(kClients);
    std::vector<std::thread> threads;
    for (int i = 0; i < kClients; ++i) {
        threads.emplace_back([&, i] {
            auto client = server.client();
            ready.arrive_and_wait();
            answers[std::size_t(i)] = upload(*client);
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    return answers;
}
}  // namespace

TEST(Store, ARigSurvivesARestartWithoutRecomputation) {
    TempRoot root;
    const std::string bytes = exr_bytes(three_disc_environment(128, 64).image);
    Json uploaded;
    std::string first_frame;
    {
        TestServer first(test_config(root.data()));
        auto client = first.client();
        uploaded = upload_environment(*client, bytes, "image/x-exr", "light_count=2");
        ASSERT_TRUE(uploaded.is_object());
        EXPECT_EQ(uploaded.at("cached"), false);
        EXPECT_EQ(scrape(*client).sum("oer_rigs_computed_total"), 1.0);
        const auto frame = render_with(*client, uploaded.at("id"));
        ASSERT_TRUE(frame);
        ASSERT_EQ(frame->status, 200) << frame->body;
        first_frame = frame->body;
    }
    TestServer second(test_config(root.data()));
    auto client = second.client();
    const std::string id = uploaded.at("id");
    const Json stored = get_rig(*client, id);
    ASSERT_TRUE(stored.is_object());
    EXPECT_EQ(comparable(stored), comparable(uploaded));
    const auto frame = render_with(*client, id);
    ASSERT_TRUE(frame);
    ASSERT_EQ(frame->status, 200) << frame->body;
    EXPECT_TRUE(frame->body == first_frame)
        << "the same request renders differently after a restart";
    EXPECT_EQ(scrape(*client).sum("oer_rigs_computed_total"), 0.0);

    const auto again = client->Post("/v1/environments?light_count=2", bytes, "image/x-exr");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 200) << again->body;
    const Json repeated = expect_conforms("POST", "/v1/environments", again);
    ASSERT_TRUE(repeated.is_object());
    EXPECT_EQ(repeated.at("cached"), true);
    EXPECT_EQ(repeated.at("id"), id);
    EXPECT_EQ(scrape(*client).sum("oer_rigs_computed_total"), 0.0);
}

TEST(Store, ADamagedRigEntryIsRecomputedFromItsSource) {
    TempRoot root;
    const std::string bytes = exr_bytes(three_disc_environment(128, 64).image);
    Json uploaded;
    {
        TestServer first(test_config(root.data()));
        auto client = first.client();
        uploaded = upload_environment(*client, bytes, "image/x-exr", "light_count=3");
        ASSERT_TRUE(uploaded.is_object());
    }
    const std::string id = uploaded.at("id");
    // The stored rig: the file under the data folder's rigs/ named after the rig's id
    // (server/include/oer/server/asset_store.hpp describes the layout).
    std::vector<std::filesystem::path> entries;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root.data())) {
        if (entry.is_regular_file() && entry.path().parent_path().filename() == "rigs" &&
            entry.path().filename().string().find(id) != std::string::npos) {
            entries.push_back(entry.path());
        }
    }
    ASSERT_EQ(entries.size(), 1u) << "expected one stored entry named after rig " << id;
    for (const bool truncate : {false, true}) {
        SCOPED_TRACE(truncate ? "truncated" : "one byte changed");
        {
            std::fstream file(entries[0], std::ios::in | std::ios::out | std::ios::binary);
            ASSERT_TRUE(file);
            std::string content((std::istreambuf_iterator<char>(file)), {});
            ASSERT_GT(content.size(), 200u);
            if (truncate) {
                content.resize(content.size() / 2);
            } else {
                // A digit in the middle of the payload: still JSON, different numbers.
                std::size_t at = content.size() / 2;
                while (at < content.size() &&
                       !std::isdigit(static_cast<unsigned char>(content[at]))) {
                    ++at;
                }
                ASSERT_LT(at, content.size());
                content[at] = content[at] == '7' ? '3' : '7';
            }
            file.close();
            std::ofstream out(entries[0], std::ios::binary | std::ios::trunc);
            out << content;
        }
        TestServer server(test_config(root.data()));
        auto client = server.client();
        const Json stored = get_rig(*client, id);
        ASSERT_TRUE(stored.is_object());
        EXPECT_EQ(comparable(stored), comparable(uploaded));
        EXPECT_EQ(scrape(*client).sum("oer_rigs_computed_total"), 1.0);
        const auto frame = render_with(*client, id);
        ASSERT_TRUE(frame);
        EXPECT_EQ(frame->status, 200);
        // Recomputed once, then stored again: a second read needs no computation.
        const Json again = get_rig(*client, id);
        EXPECT_EQ(comparable(again), comparable(uploaded));
        EXPECT_EQ(scrape(*client).sum("oer_rigs_computed_total"), 1.0);
    }
}

TEST(Store, ConcurrentUploadsOfOneMapComputeItsRigOnce) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    // Large enough that preprocessing (tens of milliseconds) overlaps every upload.
    const std::string bytes = exr_bytes(three_disc_environment(1024, 512).image);
    const std::vector<Json> answers = at_once(server, [&](httplib::Client& client) {
        return upload_environment(client, bytes, "image/x-exr", "light_count=2");
    });
    int computed_here = 0;
    for (const Json& answer : answers) {
        ASSERT_TRUE(answer.is_object());
        EXPECT_EQ(answer.at("id"), answers[0].at("id"));
        EXPECT_EQ(comparable(answer), comparable(answers[0]));
        computed_here += answer.at("cached") == false ? 1 : 0;
    }
    EXPECT_EQ(computed_here, 1);
    auto client = server.client();
    EXPECT_EQ(scrape(*client).sum("oer_rigs_computed_total"), 1.0);
}

TEST(Store, ConcurrentUploadsOfOneMeshLoadItOnce) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    // Large enough (4 MB) that loading it overlaps every concurrent upload.
    const std::string bytes = grid_obj(300);
    const std::vector<Json> answers = at_once(
        server, [&](httplib::Client& client) { return upload_mesh(client, bytes, "model/obj"); });
    int loaded_here = 0;
    for (const Json& answer : answers) {
        ASSERT_TRUE(answer.is_object());
        EXPECT_EQ(answer.at("id"), answers[0].at("id"));
        EXPECT_EQ(answer.at("counts").at("triangles"), 2 * 300 * 300);
        loaded_here += answer.at("cached") == false ? 1 : 0;
    }
    EXPECT_EQ(loaded_here, 1);
    auto client = server.client();
    EXPECT_EQ(scrape(*client).sum("oer_meshes_loaded_total"), 1.0);
}
