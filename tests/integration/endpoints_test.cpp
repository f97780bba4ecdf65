// Every endpoint's happy path on a real server over loopback HTTP, each answer held to
// api/openapi.yaml (status, Content-Type, body schema, declared headers) and its values checked
// against the libraries computed independently here (the rig of the same bytes, the mesh of
// the same file, SH irradiance, decoded image sizes and colors).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <tuple>

#include <glm/geometric.hpp>

#include "http_support.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/mesh_json.hpp"
#include "oer/api/rig_json.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/api/version.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/mesh/mesh_loading.hpp"

using namespace oer;
using namespace oer::itest;
using oer::server::ProblemKind;

namespace {

ShWindow window_of(const Json& rig) {
    const Json& window = rig.at("sh").at("window");
    ShWindow result;
    result.kind = window_kind_from_string(window.at("kind").get<std::string>());
    result.cutoff = window.value("cutoff", 0.0);
    return result;
}

class Endpoints : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        root_ = new TempRoot();
        server::ServiceConfig config = test_config(root_->data());
        config.max_frame_width = 2000;  // distinguishable from the defaults in /v1/info
        config.max_frame_height = 1500;
        config.max_upload_bytes = 64ull << 20;
        config.warm_default_scene = true;  // as deployed: the metrics test counts on it
        server_ = new TestServer(config);
    }
    static void TearDownTestSuite() {
        delete server_;
        delete root_;
        server_ = nullptr;
        root_ = nullptr;
        rig_.reset();
    }
    void SetUp() override { client_ = server_->client(); }

    // The three-disc environment, uploaded once to the suite's server (each --gtest_repeat
    // round starts a new server, with an empty data folder).
    static const Json& rig() {
        if (!rig_) {
            auto client = server_->client();
            rig_ = upload_environment(*client, exr_bytes(three_disc_environment().image),
                                      "image/x-exr", "light_count=3&sh_order=3");
        }
        return *rig_;
    }

    static inline TempRoot* root_ = nullptr;
    static inline TestServer* server_ = nullptr;
    static inline std::optional<Json> rig_;
    std::unique_ptr<httplib::Client> client_;
};

}  // namespace

TEST_F(Endpoints, HealthAndReadinessAnswerTheirStatus) {
    const auto health = client_->Get("/healthz");
    EXPECT_EQ(expect_conforms("GET", "/healthz", health), Json({{"status", "ok"}}));
    EXPECT_EQ(health->status, 200);
    const auto ready = client_->Get("/readyz");
    EXPECT_EQ(expect_conforms("GET", "/readyz", ready), Json({{"status", "ready"}}));
    EXPECT_EQ(ready->status, 200);
}

TEST_F(Endpoints, InfoReportsVersionRendererAndTheConfiguredLimits) {
    const auto result = client_->Get("/v1/info");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200) << result->body;
    const Json info = expect_conforms("GET", "/v1/info", result);
    ASSERT_TRUE(info.is_object());
    EXPECT_EQ(info.at("version"), api::kVersion);
    EXPECT_FALSE(info.at("renderer").at("renderer").get<std::string>().empty());
    EXPECT_FALSE(info.at("renderer").at("vendor").get<std::string>().empty());
    EXPECT_EQ(info.at("limits").at("max_width"), 2000);
    EXPECT_EQ(info.at("limits").at("max_height"), 1500);
    EXPECT_EQ(info.at("limits").at("max_upload_bytes"), 64ull << 20);
    // The true limits: every sample count it lists renders (8 too, whatever GL_MAX_SAMPLES the
    // context has: frames are supersampled), one more than listed is refused, and a frame just
    // over max_samples_per_frame is 413.
    for (const Json& samples : info.at("limits").at("samples")) {
        const auto frame = client_->Get(
            ("/v1/render?environment=default&width=8&height=8&samples=" + samples.dump()).c_str());
        ASSERT_TRUE(frame);
        EXPECT_EQ(frame->status, 200) << samples << ": " << frame->body;
    }
    EXPECT_EQ(info.at("limits").at("samples").back(), 8);
    EXPECT_EQ(client_->Get("/v1/render?environment=default&width=8&height=8&samples=16")->status,
              422);
    const auto per_frame = info.at("limits").at("max_samples_per_frame").get<std::int64_t>();
    // 2000 x 1500 at 9 samples (the 3 x 3 grid of samples=8) is 27 M samples, over 16.8 M.
    ASSERT_GT(std::int64_t(2000) * 1500 * 9, per_frame);
    EXPECT_EQ(
        client_->Get("/v1/render?environment=default&width=2000&height=1500&samples=8")->status,
        413);
}

TEST_F(Endpoints, PresetsListTheDefaultEnvironmentAndProduct) {
    const auto result = client_->Get("/v1/presets");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200) << result->body;
    const Json presets = expect_conforms("GET", "/v1/presets", result);
    ASSERT_TRUE(presets.is_object());
    for (const char* kind : {"environments", "meshes"}) {
        bool has_default = false;
        for (const Json& preset : presets.at(kind)) {
            has_default = has_default || preset.at("id") == "default";
        }
        EXPECT_TRUE(has_default) << kind << ": " << presets.dump();
    }
}

// The browser client comes with the binary: the files of web/ as they are in the source tree
// (embedded at build time), each with its Content-Type, the SHA-256 of its text as a strong
// ETag (a 304 for it) and Cache-Control; no other name, and no way out of the embedded set.
TEST_F(Endpoints, WebClientAndApiSpecAreServedFromTheFilesEmbeddedAtBuildTime) {
    const std::filesystem::path web = OER_WEB_DIR;
    const auto source = [&](const std::string& name) {
        std::ifstream file(web / name, std::ios::binary);
        std::ostringstream text;
        text << file.rdbuf();
        return text.str();
    };
    const std::vector<std::tuple<std::string, std::string, std::string, std::string>> files = {
        {"/", "/", "index.html", "text/html; charset=utf-8"},
        {"/web/index.html", "/web/{file}", "index.html", "text/html; charset=utf-8"},
        {"/web/oer-viewer.js", "/web/{file}", "oer-viewer.js", "text/javascript; charset=utf-8"},
        {"/web/index.css", "/web/{file}", "index.css", "text/css; charset=utf-8"},
        // The API's contract as the server was built with it.
        {"/v1/openapi.yaml", "/v1/openapi.yaml", "../api/openapi.yaml", "application/yaml"},
    };
    for (const auto& [path, route, name, type] : files) {
        SCOPED_TRACE(path);
        const auto result = client_->Get(path);
        expect_conforms("GET", route, result);
        ASSERT_EQ(result->status, 200);
        const std::string text = source(name);
        ASSERT_FALSE(text.empty()) << web / name;
        EXPECT_EQ(result->body, text);
        EXPECT_EQ(result->get_header_value("Content-Type"), type);
        EXPECT_EQ(result->get_header_value("Cache-Control"), "no-cache");
        const std::string etag = result->get_header_value("ETag");
        // Appended rather than "\"" + hex: GCC 12 warns (-Wrestrict) on the inlined operator+.
        std::string expected_etag = "\"";
        expected_etag.append(api::sha256_hex(text)).append("\"");
        EXPECT_EQ(etag, expected_etag);
        const auto again = client_->Get(path, {{"If-None-Match", etag}});
        expect_conforms("GET", route, again);
        EXPECT_EQ(again->status, 304);
        EXPECT_TRUE(again->body.empty());
    }
    // The page's query is its view state, for the page to read.
    EXPECT_EQ(client_->Get("/?camera-orbit=10+20&exposure=1")->status, 200);
    for (const std::string path :
         {"/web/embed-test.html", "/web/README.md", "/web/..%2FCMakeLists.txt", "/web/.."}) {
        SCOPED_TRACE(path);
        expect_problem("GET", "/web/{file}", client_->Get(path), ProblemKind::NotFound);
    }
    EXPECT_EQ(client_->Get("/web/")->status, 404);
    EXPECT_EQ(client_->Get("/web/../CMakeLists.txt")->status, 404);
}

TEST_F(Endpoints, MetricsAreValidPrometheusTextCountingRequestsAndCaches) {
    const Metrics before = scrape(*client_);
    for (int i = 0; i < 3; ++i) {
        ASSERT_EQ(client_->Get("/healthz")->status, 200);
    }
    // A frame no other test asks for: one miss, then one hit of the frame cache.
    const std::string frame =
        "/v1/render?environment=default&mesh=default&width=40&height=30"
        "&yaw=123&samples=1";
    ASSERT_EQ(client_->Get(frame.c_str())->status, 200);
    ASSERT_EQ(client_->Get(frame.c_str())->status, 200);
    const auto result = client_->Get("/metrics");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200);
    expect_conforms("GET", "/metrics", result);
    const Metrics after = parse_prometheus(result->body);

    // The healthz series: found by its route label, whatever spelling the route has.
    std::string health_route;
    for (const Sample& sample : after.samples) {
        if (sample.name == "oer_http_requests_total" && sample.labels.count("route") &&
            sample.labels.at("route").find("healthz") != std::string::npos) {
            health_route = sample.labels.at("route");
        }
    }
    ASSERT_FALSE(health_route.empty()) << result->body;
    const std::map<std::string, std::string> health = {
        {"route", health_route}, {"method", "GET"}, {"status", "200"}};
    EXPECT_EQ(after.sum("oer_http_requests_total", health) -
                  before.sum("oer_http_requests_total", health),
              3.0);
    EXPECT_EQ(after.sum("oer_cache_misses_total", {{"cache", "frame"}}) -
                  before.sum("oer_cache_misses_total", {{"cache", "frame"}}),
              1.0);
    EXPECT_EQ(after.sum("oer_cache_hits_total", {{"cache", "frame"}}) -
                  before.sum("oer_cache_hits_total", {{"cache", "frame"}}),
              1.0);
    EXPECT_EQ(after.sum("oer_render_seconds_count") - before.sum("oer_render_seconds_count"), 1.0);
    // The default scene's transfer, baked at start-up: one hit for the rendered frame, no bake.
    EXPECT_EQ(after.sum("oer_cache_hits_total", {{"cache", "transfer"}}) -
                  before.sum("oer_cache_hits_total", {{"cache", "transfer"}}),
              1.0);
    EXPECT_EQ(
        after.sum("oer_transfers_computed_total") - before.sum("oer_transfers_computed_total"),
        0.0);
    EXPECT_TRUE(after.has("oer_transfer_seconds_count"));
    EXPECT_TRUE(std::any_of(after.samples.begin(), after.samples.end(), [](const Sample& sample) {
        return sample.name == "oer_cache_misses_total" && sample.labels.count("cache") &&
               sample.labels.at("cache") == "transfer";
    })) << "the transfer cache's series are not there from the first scrape";
    EXPECT_EQ(after.sum("oer_render_queue_depth"), 0.0);
    EXPECT_EQ(after.sum("oer_render_workers_ready"), 1.0);
    // Each gauge went up and back down around its computation (the process tests see it up).
    for (const char* computation : {"rig", "specular", "transfer"}) {
        EXPECT_EQ(after.sum("oer_computations_in_progress", {{"computation", computation}}), 0.0)
            << computation;
    }

    const std::map<std::string, std::string> families = {
        {"oer_http_requests_total", "counter"},  {"oer_http_request_seconds", "histogram"},
        {"oer_render_seconds", "histogram"},     {"oer_preprocess_seconds", "histogram"},
        {"oer_rigs_computed_total", "counter"},  {"oer_cache_hits_total", "counter"},
        {"oer_cache_misses_total", "counter"},   {"oer_render_queue_depth", "gauge"},
        {"oer_render_workers_ready", "gauge"},   {"oer_transfers_computed_total", "counter"},
        {"oer_transfer_seconds", "histogram"},   {"oer_computations_in_progress", "gauge"},
        {"oer_renders_skipped_total", "counter"}};
    for (const auto& [family, type] : families) {
        EXPECT_EQ(after.types.count(family) ? after.types.at(family) : "<absent>", type) << family;
    }
    // Histograms are cumulative and end in +Inf == _count; no per-asset labels anywhere.
    for (const Sample& sample : after.samples) {
        if (sample.name.size() > 7 && sample.name.substr(sample.name.size() - 7) == "_bucket" &&
            sample.labels.at("le") == "+Inf") {
            std::map<std::string, std::string> labels = sample.labels;
            labels.erase("le");
            const std::string family = sample.name.substr(0, sample.name.size() - 7);
            EXPECT_EQ(sample.value, after.sum(family + "_count", labels)) << family;
        }
        for (const auto& [key, value] : sample.labels) {
            EXPECT_FALSE(std::regex_search(value, std::regex("[0-9a-f]{64}")))
                << sample.name << " has a per-asset label " << key << "=" << value;
        }
    }
}

TEST_F(Endpoints, EnvironmentUploadGivesTheRigOfTheLibraryAndIsCachedByContent) {
    const Metrics before = scrape(*client_);
    const SyntheticEnvironment environment = three_disc_environment(128, 64);
    const std::string bytes = exr_bytes(environment.image);
    const std::string query = "light_count=3&sh_order=3&seed=7";
    const auto result = client_->Post(("/v1/environments?" + query).c_str(), bytes, "image/x-exr");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 201) << result->body;
    const Json rig = expect_conforms("POST", "/v1/environments", result);
    ASSERT_TRUE(rig.is_object());
    EXPECT_EQ(rig.at("cached"), false);

    // The id is the content hash of the bytes and the options; Location names it.
    const RigOptions options =
        api::parse_rig_options({{"light_count", "3"}, {"sh_order", "3"}, {"seed", "7"}});
    const std::string id = api::rig_id(api::sha256_hex(std::string_view(bytes)), options);
    EXPECT_EQ(rig.at("id"), id);
    EXPECT_EQ(result->get_header_value("Location"), "/v1/environments/" + id);

    // The rig is the library's rig of the same bytes.
    const LoadedImage loaded =
        load_image_memory(std::as_bytes(std::span(bytes.data(), bytes.size())), "upload.exr");
    Json expected = api::rig_to_json(build_rig(loaded, options), id);
    EXPECT_EQ(rig.at("source").at("dynamic_range"), "hdr");
    Json comparable = rig;
    comparable.erase("cached");
    comparable.erase("timings_ms");
    expected.erase("timings_ms");
    expect_json_near(comparable, expected, 1e-9, "rig");
    // ... whose lights are the three discs.
    ASSERT_EQ(rig.at("lights").size(), 3u);
    for (const glm::dvec3& disc : environment.light_directions) {
        double best = 0.0;
        for (const Json& light : rig.at("lights")) {
            const glm::dvec3 d{light.at("direction")[0].get<double>(),
                               light.at("direction")[1].get<double>(),
                               light.at("direction")[2].get<double>()};
            best = std::max(best, glm::dot(d, disc));
        }
        EXPECT_GT(best, std::cos(0.05)) << "no light found towards a disc";
    }

    // The same bytes and options again: 200, cached, the same rig, nothing recomputed.
    const auto again = client_->Post(("/v1/environments?" + query).c_str(), bytes, "image/x-exr");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->status, 200) << again->body;
    Json repeated = expect_conforms("POST", "/v1/environments", again);
    ASSERT_TRUE(repeated.is_object());
    EXPECT_EQ(repeated.at("cached"), true);
    EXPECT_EQ(repeated.at("id"), id);
    const Metrics after = scrape(*client_);
    EXPECT_EQ(after.sum("oer_rigs_computed_total") - before.sum("oer_rigs_computed_total"), 1.0);

    // GET gives the stored rig.
    const auto stored = client_->Get(("/v1/environments/" + id).c_str());
    ASSERT_TRUE(stored);
    ASSERT_EQ(stored->status, 200) << stored->body;
    Json got = expect_conforms("GET", "/v1/environments/{id}", stored);
    ASSERT_TRUE(got.is_object());
    got.erase("timings_ms");
    got.erase("cached");
    expect_json_near(got, comparable, 1e-12, "stored rig");
}

TEST_F(Endpoints, RadianceHdrUploadIsReadToo) {
    const SyntheticEnvironment environment = three_disc_environment(128, 64);
    const Json rig = upload_environment(*client_, hdr_bytes(environment.image),
                                        "image/vnd.radiance", "light_count=3");
    ASSERT_TRUE(rig.is_object());
    EXPECT_EQ(rig.at("source").at("width"), 128);
    EXPECT_EQ(rig.at("source").at("height"), 64);
    EXPECT_EQ(rig.at("lights").size(), 3u);
    EXPECT_EQ(rig.at("options").at("light_count"), 3);
}

// A phone's panorama (JPEG or PNG) is accepted under its own type, decoded from sRGB to linear
// (IEC 61966-2-1) and marked as of low dynamic range. A uniform grey map's radiance is its
// linear value everywhere, so the rig's first SH coefficient is that value times 2 sqrt(pi)
// (the integral of Y_00 over the sphere).
TEST_F(Endpoints, LdrPanoramasAreLinearisedFromSrgbAndMarked) {
    constexpr std::uint8_t kGrey = 188;
    const oer::Rgba8Image panorama{64, 32, [] {
                                       std::vector<std::uint8_t> pixels;
                                       for (int i = 0; i < 64 * 32; ++i) {
                                           pixels.insert(pixels.end(), {kGrey, kGrey, kGrey, 255});
                                       }
                                       return pixels;
                                   }()};
    const double encoded = kGrey / 255.0;
    const double linear = std::pow((encoded + 0.055) / 1.055, 2.4);
    const std::vector<std::uint8_t> png = oer::encode_png(panorama);
    const std::vector<std::uint8_t> jpeg = oer::encode_jpeg(panorama, 95);
    for (const auto& [bytes, type, tolerance] :
         {std::tuple{std::string(png.begin(), png.end()), "image/png", 1e-5},
          std::tuple{std::string(jpeg.begin(), jpeg.end()), "image/jpeg", 0.01}}) {
        SCOPED_TRACE(type);
        const Json rig = upload_environment(*client_, bytes, type, "light_count=0");
        ASSERT_TRUE(rig.is_object());
        EXPECT_EQ(rig.at("source").at("dynamic_range"), "ldr");
        EXPECT_EQ(rig.at("source").at("width"), 64);
        const double expected = linear * 2.0 * std::sqrt(std::acos(-1.0));
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(rig.at("sh").at("radiance")[0][c].get<double>(), expected,
                        tolerance * expected);
        }
    }
}

TEST_F(Endpoints, PreviewIsA512By256JpegShowingTheMap) {
    ASSERT_TRUE(rig().is_object());
    const std::string id = rig().at("id");
    const auto result = client_->Get(("/v1/environments/" + id + "/preview.jpg").c_str());
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200) << result->body;
    expect_conforms("GET", "/v1/environments/{id}/preview.jpg", result);
    const Rgba8Image preview = decode_image(result);
    ASSERT_EQ(preview.width, 512);
    ASSERT_EQ(preview.height, 256);
    // Each disc is bright (the brightest pixel within 4 pixels of its centre: the light's
    // number may be drawn over the centre); the sky far from every disc is dim.
    const auto luma = [&](glm::dvec3 direction, int reach = 0) {
        const glm::dvec2 p = equirect::position_of(direction, 512, 256);
        double brightest = 0.0;
        for (int dy = -reach; dy <= reach; ++dy) {
            for (int dx = -reach; dx <= reach; ++dx) {
                const int x = std::clamp(int(p.x) + dx, 0, 511);
                const int y = std::clamp(int(p.y) + dy, 0, 255);
                const std::uint8_t* rgb = &preview.pixels[(std::size_t(y) * 512 + x) * 4];
                brightest = std::max(brightest, (rgb[0] + rgb[1] + rgb[2]) / 3.0);
            }
        }
        return brightest;
    };
    for (const glm::dvec3& disc : three_disc_environment().light_directions) {
        EXPECT_GT(luma(disc, 4), 240.0);
    }
    EXPECT_LT(luma({0.0, -1.0, 0.0}), 120.0);
    EXPECT_LT(luma({0.0, 0.0, 1.0}), 120.0);
}

TEST_F(Endpoints, IrradianceExrIsTheRigsShIrradiance) {
    ASSERT_TRUE(rig().is_object());
    const std::string id = rig().at("id");
    const ShWindow window = window_of(rig());
    const ShRgb all = sh_of(rig().at("sh").at("radiance"));
    ShRgb without_second = all;
    without_second -= sh_of(rig().at("sh").at("per_light")[1]);
    for (const auto& [query, radiance] :
         {std::pair{std::string("?width=64&height=32"), all},
          std::pair{std::string("?width=64&height=32&lights=1,0,1"), without_second},
          std::pair{std::string(""), all}}) {
        const auto result =
            client_->Get(("/v1/environments/" + id + "/irradiance.exr" + query).c_str());
        ASSERT_TRUE(result);
        ASSERT_EQ(result->status, 200) << query << ": " << result->body;
        expect_conforms("GET", "/v1/environments/{id}/irradiance.exr", result);
        const LoadedImage loaded = load_image_memory(
            std::as_bytes(std::span(result->body.data(), result->body.size())), "irradiance.exr");
        const int width = query.empty() ? 128 : 64, height = query.empty() ? 64 : 32;
        ASSERT_EQ(loaded.image.width, width) << query;
        ASSERT_EQ(loaded.image.height, height) << query;
        const ShRgb irradiance = irradiance_coefficients(radiance, window);
        double largest = 0.0;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                const glm::dvec3 e =
                    irradiance.evaluate(equirect::pixel_direction(x, y, width, height));
                largest = std::max({largest, e.r, e.g, e.b});
            }
        }
        int checked = 0;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                // Negative irradiance (ringing) reads back as 0: the loader repairs it.
                const glm::dvec3 expected =
                    glm::max(irradiance.evaluate(equirect::pixel_direction(x, y, width, height)),
                             glm::dvec3(0.0));
                const float* got = loaded.image.at(x, y);
                for (int c = 0; c < 3; ++c) {
                    ASSERT_NEAR(got[c], expected[c], 0.01 * expected[c] + 1e-4 * largest)
                        << query << " pixel " << x << "," << y << " channel " << c;
                }
                ++checked;
            }
        }
        EXPECT_EQ(checked, width * height);
    }
}

TEST_F(Endpoints, MeshUploadsDescribeTheMeshAsTheLibraryLoadsIt) {
    const std::string obj = box_obj({-0.5, 0.0, -0.25}, {0.5, 0.75, 0.25});
    const std::string glb = box_glb({-1.0, -2.0, -3.0}, {1.0, 2.0, 3.0});
    for (const auto& [bytes, content_type, format] :
         {std::tuple{obj, std::string("model/obj"), MeshFormat::Obj},
          std::tuple{glb, std::string("model/gltf-binary"), MeshFormat::Glb}}) {
        const auto result = client_->Post("/v1/meshes", bytes, content_type.c_str());
        ASSERT_TRUE(result);
        ASSERT_EQ(result->status, 201) << content_type << ": " << result->body;
        Json mesh = expect_conforms("POST", "/v1/meshes", result);
        ASSERT_TRUE(mesh.is_object());
        const std::string id = api::sha256_hex(std::string_view(bytes));
        EXPECT_EQ(mesh.at("id"), id);
        EXPECT_EQ(mesh.at("cached"), false);
        EXPECT_EQ(result->get_header_value("Location"), "/v1/meshes/" + id);
        const Json expected =
            api::mesh_to_json(load_mesh_memory(std::as_bytes(std::span(bytes.data(), bytes.size())),
                                               "upload", format),
                              id, format);
        mesh.erase("cached");
        expect_json_near(mesh, expected, 1e-12, content_type);
        EXPECT_GT(mesh.at("counts").at("triangles"), 12);  // the box's 12, refined at upload

        const auto stored = client_->Get(("/v1/meshes/" + id).c_str());
        ASSERT_TRUE(stored);
        ASSERT_EQ(stored->status, 200);
        Json got = expect_conforms("GET", "/v1/meshes/{id}", stored);
        got.erase("cached");
        EXPECT_EQ(got, mesh);

        const auto again = client_->Post("/v1/meshes", bytes, content_type.c_str());
        ASSERT_TRUE(again);
        EXPECT_EQ(again->status, 200);
        EXPECT_EQ(expect_conforms("POST", "/v1/meshes", again).value("cached", false), true);
    }
    // application/octet-stream with an explicit format.
    const std::string other = box_obj({0, 0, 0}, {1, 1, 1});
    const auto result = client_->Post("/v1/meshes?format=obj", other, "application/octet-stream");
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 201) << result->body;
    const Json mesh = expect_conforms("POST", "/v1/meshes", result);
    EXPECT_EQ(mesh.at("format"), "obj");
    EXPECT_EQ(mesh.at("bounds").at("max"), Json({1, 1, 1}));
}

TEST_F(Endpoints, RenderAnswersFramesOfTheRequestedSizeAndFormat) {
    const auto get =
        client_->Get("/v1/render?environment=default&mesh=default&width=160&height=96&samples=1");
    ASSERT_TRUE(get);
    ASSERT_EQ(get->status, 200) << get->body;
    expect_conforms("GET", "/v1/render", get);
    EXPECT_EQ(get->get_header_value("Content-Type"), "image/jpeg");
    EXPECT_TRUE(std::regex_match(get->get_header_value("ETag"), std::regex("\"[0-9a-f]{64}\"")))
        << get->get_header_value("ETag");
    EXPECT_EQ(get->get_header_value("X-Oer-Cache"), "miss");
    EXPECT_FALSE(get->get_header_value("Server-Timing").empty());
    const Rgba8Image jpeg = decode_image(get);
    EXPECT_EQ(jpeg.width, 160);
    EXPECT_EQ(jpeg.height, 96);

    const auto png = post_json(*client_, "/v1/render",
                               {{"environment", "default"},
                                {"objects", {{{"mesh", "default"}}}},
                                {"width", 64},
                                {"height", 48},
                                {"format", "png"},
                                {"samples", 1}});
    ASSERT_TRUE(png);
    ASSERT_EQ(png->status, 200) << png->body;
    expect_conforms("POST", "/v1/render", png);
    EXPECT_EQ(png->get_header_value("Content-Type"), "image/png");
    const Rgba8Image decoded = decode_image(png);
    EXPECT_EQ(decoded.width, 64);
    EXPECT_EQ(decoded.height, 48);

    const auto exr = post_json(*client_, "/v1/render",
                               {{"environment", "default"},
                                {"objects", {{{"mesh", "default"}}}},
                                {"width", 32},
                                {"height", 24},
                                {"format", "exr"},
                                {"samples", 1}});
    ASSERT_TRUE(exr);
    ASSERT_EQ(exr->status, 200) << exr->body;
    expect_conforms("POST", "/v1/render", exr);
    EXPECT_EQ(exr->get_header_value("Content-Type"), "image/x-exr");
    const LoadedImage linear = load_image_memory(
        std::as_bytes(std::span(exr->body.data(), exr->body.size())), "frame.exr");
    EXPECT_EQ(linear.image.width, 32);
    EXPECT_EQ(linear.image.height, 24);
    EXPECT_EQ(linear.repaired.nan + linear.repaired.inf + linear.repaired.negative, 0u);
}

TEST_F(Endpoints, SolidBackgroundFillsAnEmptyFrameWithExactlyThatColor) {
    const auto result = post_json(*client_, "/v1/render",
                                  {{"environment", "default"},
                                   {"ground", false},
                                   {"background", "#FF8010"},
                                   {"format", "png"},
                                   {"width", 33},
                                   {"height", 17}});
    ASSERT_TRUE(result);
    ASSERT_EQ(result->status, 200) << result->body;
    expect_conforms("POST", "/v1/render", result);
    const Rgba8Image image = decode_image(result);
    ASSERT_EQ(image.width, 33);
    ASSERT_EQ(image.height, 17);
    for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
        ASSERT_EQ(image.pixels[i], 255) << i / 4;
        ASSERT_EQ(image.pixels[i + 1], 128) << i / 4;
        ASSERT_EQ(image.pixels[i + 2], 16) << i / 4;
        ASSERT_EQ(image.pixels[i + 3], 255) << i / 4;
    }
}
