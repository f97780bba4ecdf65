// The GL context failing: oer-server run with glvnd's list of EGL vendors pointing at nothing
// (__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json, so libEGL finds no driver) starts without a
// renderer. It must stay alive and say why: /healthz 200, /readyz 503 with Retry-After and the
// cause, renders 503 with Retry-After (and not cacheable), while uploads, rigs and /v1/info work;
// on the API listener and on the admin listener alike.
#include <gtest/gtest.h>

#include "http_support.hpp"
#include "oer/api/content_id.hpp"
#include "server_process.hpp"

using namespace oer;
using namespace oer::itest;
using namespace oer::ptest;

namespace {

constexpr const char* kRendererFailure = "the renderer could not start";

// The renderer's retry interval (server/src/http_errors.hpp, kRendererRetrySeconds), which a
// client is told to wait.
constexpr const char* kRendererRetryAfter = "5";

void expect_unavailable(const std::string& method, const std::string& route,
                        const httplib::Result& result) {
    expect_problem(method, route, result, server::ProblemKind::Unavailable);
    if (!result) {
        return;
    }
    EXPECT_EQ(result->get_header_value("Retry-After"), kRendererRetryAfter) << route;
    const Json body = Json::parse(result->body, nullptr, false);
    EXPECT_NE(body.value("detail", std::string()).find(kRendererFailure), std::string::npos)
        << route << ": " << result->body;
}

void check_service_without_renderer(const ServerProcess& server) {
    ASSERT_NE(server.banner().find("renderer: not running"), std::string::npos)
        << "the renderer started although glvnd was given no EGL vendor (this test needs a "
           "glvnd libEGL, which reads __EGL_VENDOR_LIBRARY_FILENAMES):\n"
        << server.banner();
    auto client = server.client();

    // Probes: alive, not ready, and why.
    std::vector<httplib::Client*> probes{client.get()};
    std::unique_ptr<httplib::Client> admin;
    if (server.admin_port() >= 0) {
        admin = server.admin_client();
        probes.push_back(admin.get());
    }
    for (httplib::Client* probe : probes) {
        SCOPED_TRACE(probe == client.get() ? "API listener" : "admin listener");
        const auto health = probe->Get("/healthz");
        ASSERT_TRUE(health);
        EXPECT_EQ(health->status, 200);
        expect_unavailable("GET", "/readyz", probe->Get("/readyz"));
        const Metrics metrics = scrape(*probe);
        EXPECT_TRUE(metrics.has("oer_render_workers_ready"));
        EXPECT_EQ(metrics.sum("oer_render_workers_ready"), 0.0);
    }

    // Renders, by query and by JSON: 503 for a while, never kept by a cache for a day.
    const auto by_query = client->Get("/v1/render?environment=default&mesh=default&width=64");
    expect_unavailable("GET", "/v1/render", by_query);
    ASSERT_TRUE(by_query);
    EXPECT_EQ(by_query->get_header_value("Cache-Control").find("max-age"), std::string::npos)
        << "a 503 marked cacheable: " << by_query->get_header_value("Cache-Control");
    expect_unavailable("POST", "/v1/render",
                       post_json(*client, "/v1/render",
                                 {{"environment", "default"},
                                  {"objects", {{{"mesh", "default"}}}},
                                  {"width", 32},
                                  {"height", 32}}));

    // What needs no GL: uploads, rigs, previews, irradiance maps, meshes.
    const std::string map = exr_bytes(three_disc_environment(128, 64).image);
    const Json rig = upload_environment(*client, map, "image/x-exr", "light_count=3");
    ASSERT_TRUE(rig.is_object());
    EXPECT_EQ(rig.at("cached"), false);
    EXPECT_EQ(rig.at("lights").size(), 3u);
    const std::string id = rig.at("id");
    const auto stored = client->Get(("/v1/environments/" + id).c_str());
    Json read = expect_conforms("GET", "/v1/environments/{id}", stored);
    ASSERT_TRUE(read.is_object());
    Json uploaded = rig;
    uploaded.erase("cached");
    EXPECT_EQ(read, uploaded);
    const auto preview = client->Get(("/v1/environments/" + id + "/preview.jpg").c_str());
    ASSERT_TRUE(preview);
    ASSERT_EQ(preview->status, 200);
    EXPECT_EQ(decode_image(preview).width, 512);
    const auto irradiance = client->Get(("/v1/environments/" + id + "/irradiance.exr").c_str());
    ASSERT_TRUE(irradiance);
    EXPECT_EQ(irradiance->status, 200);
    const std::string box = box_obj({-0.5, 0.0, -0.5}, {0.5, 1.0, 0.5});
    const Json mesh = upload_mesh(*client, box, "model/obj");
    ASSERT_TRUE(mesh.is_object());
    EXPECT_EQ(mesh.at("id"), api::sha256_hex(box));
    const auto mesh_read = client->Get(("/v1/meshes/" + api::sha256_hex(box)).c_str());
    ASSERT_TRUE(mesh_read);
    EXPECT_EQ(mesh_read->status, 200);

    // What the service is: no renderer, and why.
    const Json info = expect_conforms("GET", "/v1/info", client->Get("/v1/info"));
    ASSERT_TRUE(info.is_object());
    EXPECT_TRUE(info.at("renderer").is_null()) << info.dump();
    const std::string error = info.value("renderer_error", std::string());
    EXPECT_NE(error.find(kRendererFailure), std::string::npos) << info.dump();
    EXPECT_NE(error.find("EGL"), std::string::npos) << info.dump();

    // Still alive after all that, and the log says so once, with the retry interval.
    const auto health = client->Get("/healthz");
    ASSERT_TRUE(health);
    EXPECT_EQ(health->status, 200);
    EXPECT_NE(server.log().find("error: the renderer could not start"), std::string::npos);
    EXPECT_NE(server.log().find("trying again every 5 s"), std::string::npos);
}

}  // namespace

TEST(NoRenderer, ProbesSayWhyRendersAre503AndTheRestOfTheApiWorks) {
    for (const char* admin_port : {"off", "0"}) {
        SCOPED_TRACE(std::string("--admin-port ") + admin_port);
        TempRoot root;
        ServerLaunch launch(root.data(), root.root());
        launch.options = {{"admin-port", admin_port}};
        launch.environment = {"__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json"};
        ServerProcess server(launch);
        ASSERT_FALSE(::testing::Test::HasFatalFailure());
        EXPECT_EQ(server.admin_port() >= 0, std::string(admin_port) == "0");
        check_service_without_renderer(server);
        // It stops cleanly while its renderer is still being retried.
        EXPECT_EQ(server.stop(), 0);
    }
}
