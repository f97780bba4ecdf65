// Frames over HTTP: what switching a light and shadows do to the pixels (against ray-cast
// geometry and the rig's SH irradiance), a colour variant, the ETag round trip and the frame
// cache, concurrent clients, and back-pressure (503 when the render queue is full, never a hang).
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <thread>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "http_support.hpp"
#include "oer/lighting/irradiance.hpp"
#include "ray_geometry.hpp"

using namespace oer;
using namespace oer::itest;
using oer::server::ProblemKind;
using oer::testing::hits_box;
using oer::testing::pixel_ray;

namespace {

constexpr double kPi = std::numbers::pi;

double srgb_encode(double linear) {
    linear = std::clamp(linear, 0.0, 1.0);
    return 255.0 *
           (linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055);
}

glm::dvec3 rgb_at(const Rgba8Image& image, int x, int y) {
    const std::uint8_t* p = &image.pixels[(std::size_t(y) * image.width + x) * 4];
    return {double(p[0]), double(p[1]), double(p[2])};
}

double max_abs(glm::dvec3 v) {
    return std::max({std::abs(v.r), std::abs(v.g), std::abs(v.b)});
}

}  // namespace

// A box on the ground under three small bright lights, PNG with no tone mapping (a clamp), so
// that every ground pixel can be predicted: 0.8 / pi times the SH irradiance at +Y of the lights
// that reach it, times 2^exposure, sRGB-encoded. Switching light k off must leave the ground in
// k's shadow untouched (k never reached it) and darken the rest by exactly k's part; switching
// shadows off must change the ground in some light's shadow and nothing else.
TEST(RenderLighting, SwitchingALightChangesExactlyTheGroundItReaches) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json rig = upload_environment(*client, exr_bytes(three_disc_environment().image),
                                        "image/x-exr", "light_count=3&sh_order=3");
    ASSERT_TRUE(rig.is_object());
    ASSERT_EQ(rig.at("lights").size(), 3u);
    const glm::dvec3 low{-0.3, 0.0, -0.3}, high{0.3, 0.6, 0.3};
    const Json mesh = upload_mesh(*client, box_obj(low, high), "model/obj");
    ASSERT_TRUE(mesh.is_object());

    std::vector<glm::dvec3> directions;
    for (const Json& light : rig.at("lights")) {
        directions.push_back({light.at("direction")[0].get<double>(),
                              light.at("direction")[1].get<double>(),
                              light.at("direction")[2].get<double>()});
    }
    ShWindow window;
    window.kind = window_kind_from_string(rig.at("sh").at("window").at("kind").get<std::string>());
    window.cutoff = rig.at("sh").at("window").value("cutoff", 0.0);
    const glm::dvec3 up{0, 1, 0};
    const glm::dvec3 ground_all =
        0.8 / kPi *
        irradiance_coefficients(sh_of(rig.at("sh").at("radiance")), window).evaluate(up);
    std::vector<glm::dvec3> ground_light;
    for (int k = 0; k < 3; ++k) {
        ground_light.push_back(
            0.8 / kPi *
            irradiance_coefficients(sh_of(rig.at("sh").at("per_light")[k]), window).evaluate(up));
    }
    // Exposure that puts the fully lit ground at about 0.7 of white.
    const double exposure = std::log2(0.7 / std::max({ground_all.r, ground_all.g, ground_all.b}));
    const double scale = std::exp2(exposure);

    Camera camera;
    camera.eye = {0.0f, 4.0f, 3.0f};
    camera.target = {0.0f, 0.2f, 0.0f};
    camera.fov_y = 50.0f;
    const glm::dvec3 eye(camera.eye);
    const int size = 160;
    // Ground pixels by the lights whose shadow covers them; only pixels whose neighbours two
    // pixels away agree (away from every edge), within 1.2 of the box (on the plane for sure).
    const auto occluders = [&](int x, int y) -> std::optional<int> {
        const glm::dvec3 ray = pixel_ray(camera, size, size, x, y);
        if (ray.y >= 0.0 || hits_box(eye, ray, low, high)) {
            return std::nullopt;
        }
        const glm::dvec3 point = eye + (-eye.y / ray.y) * ray;
        if (glm::length(point) > 1.2) {
            return std::nullopt;
        }
        int mask = 0;
        for (int k = 0; k < 3; ++k) {
            mask |= hits_box(point, directions[k], low, high) ? 1 << k : 0;
        }
        return mask;
    };
    std::vector<int> classes(std::size_t(size * size), -1);
    for (int y = 2; y < size - 2; ++y) {
        for (int x = 2; x < size - 2; ++x) {
            const auto mask = occluders(x, y);
            bool stable = mask.has_value();
            for (const auto& [dx, dy] : {std::pair{-2, 0}, {2, 0}, {0, -2}, {0, 2}}) {
                stable = stable && occluders(x + dx, y + dy) == mask;
            }
            classes[std::size_t(y * size + x)] = stable ? *mask : -1;
        }
    }
    const auto render = [&](const std::vector<bool>& lights, bool shadows) {
        const Json body = {
            {"environment", rig.at("id")},
            {"objects", {{{"mesh", mesh.at("id")}}}},
            {"ground", true},
            // The prediction is the unoccluded lighting of docs/design.md section 2 (the ground
            // sees the whole residual map); occlusion darkens the ground near the box.
            {"occlusion", false},
            {"camera",
             {{"eye", {camera.eye.x, camera.eye.y, camera.eye.z}},
              {"target", {camera.target.x, camera.target.y, camera.target.z}},
              {"fov_y", camera.fov_y}}},
            {"lights", lights},
            {"width", size},
            {"height", size},
            {"format", "png"},
            {"tonemap", "none"},
            {"exposure", exposure},
            {"background", "#000000"},
            {"samples", 1},
            {"shadows", {{"enabled", shadows}, {"filter", "hard"}, {"resolution", 2048}}}};
        const auto result = post_json(*client, "/v1/render", body);
        EXPECT_TRUE(result && result->status == 200) << (result ? result->body : "no answer");
        return result && result->status == 200 ? decode_image(result) : Rgba8Image{};
    };
    // The predicted sRGB value of a ground pixel in the shadow of `mask`, lights `on` on.
    const auto predicted = [&](int mask, int on) {
        glm::dvec3 linear = ground_all;
        for (int k = 0; k < 3; ++k) {
            if (!(on & (1 << k)) || (mask & (1 << k))) {
                linear -= ground_light[k];
            }
        }
        return glm::dvec3(srgb_encode(linear.r * scale), srgb_encode(linear.g * scale),
                          srgb_encode(linear.b * scale));
    };

    const Rgba8Image all_on = render({true, true, true}, true);
    ASSERT_EQ(all_on.width, size);
    int per_class[8] = {};
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const int mask = classes[std::size_t(y * size + x)];
            if (mask >= 0) {
                ++per_class[mask];
                ASSERT_LE(max_abs(rgb_at(all_on, x, y) - predicted(mask, 7)), 2.5)
                    << "pixel " << x << "," << y << " in the shadow of lights " << mask;
            }
        }
    }
    for (int k = 0; k < 3; ++k) {
        const int bit = 1 << k;
        int in_shadow = 0;
        for (int mask = 0; mask < 8; ++mask) {
            in_shadow += (mask & bit) ? per_class[mask] : 0;
        }
        ASSERT_GT(in_shadow, 50) << "light " << k << " casts no checkable shadow";
        std::vector<bool> lights{true, true, true};
        lights[std::size_t(k)] = false;
        const Rgba8Image one_off = render(lights, true);
        ASSERT_EQ(one_off.width, size);
        int unchanged = 0, darkened = 0;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const int mask = classes[std::size_t(y * size + x)];
                if (mask < 0) {
                    continue;
                }
                const glm::dvec3 before = rgb_at(all_on, x, y), after = rgb_at(one_off, x, y);
                if (mask & bit) {
                    ASSERT_LE(max_abs(after - before), 1.0)
                        << "pixel " << x << "," << y << " lies in the shadow of light " << k
                        << " but changed when it was switched off";
                    ++unchanged;
                } else {
                    ASSERT_LE(max_abs(after - predicted(mask, 7 & ~bit)), 2.5)
                        << "pixel " << x << "," << y << " with light " << k << " off";
                    ASSERT_GT(glm::dot(before - after, glm::dvec3(1.0)), 3.0)
                        << "pixel " << x << "," << y << " lit by light " << k
                        << " did not darken when it was switched off";
                    ++darkened;
                }
            }
        }
        EXPECT_GT(unchanged, 50) << k;
        EXPECT_GT(darkened, 500) << k;
    }
    // Shadows off: every light reaches every ground pixel; only shadowed ground changes.
    const Rgba8Image no_shadows = render({true, true, true}, false);
    ASSERT_EQ(no_shadows.width, size);
    int changed = 0;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const int mask = classes[std::size_t(y * size + x)];
            if (mask < 0) {
                continue;
            }
            const double difference = max_abs(rgb_at(no_shadows, x, y) - rgb_at(all_on, x, y));
            if (mask == 0) {
                ASSERT_LE(difference, 1.0) << "unshadowed pixel " << x << "," << y << " changed";
            } else {
                ASSERT_LE(max_abs(rgb_at(no_shadows, x, y) - predicted(0, 7)), 2.5)
                    << "pixel " << x << "," << y << " with shadows off";
                changed += difference > 2.0;
            }
        }
    }
    EXPECT_GT(changed, 100);
}

// One light at weights 1, 0.5 and 0 over GET (docs/design.md section 2, dimmable lights): where the
// light reaches, the half-weight frame lies strictly between on and off (in linear terms
// halfway, up to the 8-bit encoding); weight 0 is the POST body's `false`, byte for byte.
TEST(RenderLighting, AHalfWeightLightGivesAFrameBetweenOnAndOff) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json rig = upload_environment(*client, exr_bytes(three_disc_environment().image),
                                        "image/x-exr", "light_count=1&sh_order=3");
    ASSERT_TRUE(rig.is_object());
    ASSERT_EQ(rig.at("lights").size(), 1u);
    const glm::dvec3 low{-0.3, 0.0, -0.3}, high{0.3, 0.6, 0.3};
    const Json mesh = upload_mesh(*client, box_obj(low, high), "model/obj");
    ASSERT_TRUE(mesh.is_object());
    // Exposure that puts the fully lit ground at about 0.7 of white, as a query's text.
    ShWindow window;
    window.kind = window_kind_from_string(rig.at("sh").at("window").at("kind").get<std::string>());
    window.cutoff = rig.at("sh").at("window").value("cutoff", 0.0);
    const glm::dvec3 ground_all =
        0.8 / kPi *
        irradiance_coefficients(sh_of(rig.at("sh").at("radiance")), window).evaluate({0, 1, 0});
    const std::string exposure =
        std::to_string(std::log2(0.7 / std::max({ground_all.r, ground_all.g, ground_all.b})));
    const std::string query = "/v1/render?environment=" + rig.at("id").get<std::string>() +
                              "&mesh=" + mesh.at("id").get<std::string>() +
                              "&eye=0,4,3&target=0,0.2,0&fov_y=50&width=96&height=96"
                              "&format=png&tonemap=none&exposure=" +
                              exposure + "&samples=1&shadow_filter=hard";
    const auto render = [&](const std::string& lights) {
        const auto result = client->Get((query + "&lights=" + lights).c_str());
        EXPECT_TRUE(result && result->status == 200) << (result ? result->body : "no answer");
        return result && result->status == 200 ? decode_image(result) : Rgba8Image{};
    };
    const Rgba8Image on = render("1"), half = render("0.5"), off = render("0");
    ASSERT_EQ(on.width, 96);
    ASSERT_EQ(half.width, 96);
    ASSERT_EQ(off.width, 96);
    const auto linear = [](double encoded) {
        const double c = encoded / 255.0;
        return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    };
    const auto luminance = [&](const Rgba8Image& image, int x, int y) {
        const glm::dvec3 c = rgb_at(image, x, y);
        return 0.2126 * linear(c.r) + 0.7152 * linear(c.g) + 0.0722 * linear(c.b);
    };
    // The pixels the light reaches: those it brightens, away from white (clamped).
    double sum_on = 0.0, sum_half = 0.0, sum_off = 0.0;
    int reached = 0;
    for (int y = 0; y < 96; ++y) {
        for (int x = 0; x < 96; ++x) {
            const double l_on = luminance(on, x, y), l_off = luminance(off, x, y);
            if (l_on - l_off < 0.02 || max_abs(rgb_at(on, x, y)) >= 255.0) {
                continue;
            }
            sum_on += l_on;
            sum_half += luminance(half, x, y);
            sum_off += l_off;
            ++reached;
        }
    }
    ASSERT_GT(reached, 2000);
    const double mean_on = sum_on / reached, mean_half = sum_half / reached,
                 mean_off = sum_off / reached;
    EXPECT_GT(mean_half, mean_off);
    EXPECT_LT(mean_half, mean_on);
    EXPECT_NEAR(mean_half, 0.5 * (mean_on + mean_off), 0.02 * (mean_on - mean_off));

    Json body = {{"environment", rig.at("id")},
                 {"objects", {{{"mesh", mesh.at("id")}}}},
                 {"camera", {{"eye", {0, 4, 3}}, {"target", {0, 0.2, 0}}, {"fov_y", 50}}},
                 {"lights", {false}},
                 {"width", 96},
                 {"height", 96},
                 {"format", "png"},
                 {"tonemap", "none"},
                 {"exposure", std::stod(exposure)},
                 {"samples", 1},
                 {"shadows", {{"filter", "hard"}}}};
    const auto posted = post_json(*client, "/v1/render", body);
    const auto got = client->Get((query + "&lights=0").c_str());
    ASSERT_TRUE(posted && got);
    ASSERT_EQ(posted->status, 200) << posted->body;
    EXPECT_EQ(posted->get_header_value("ETag"), got->get_header_value("ETag"));
    EXPECT_EQ(posted->body, got->body);
}

// A colour variant over GET (base_color, every mesh of the query): the default product against
// a black background with no ground, its plain materials (fabric 0.85, 0.80, 0.75, a dark
// stand) against a red base color. The red frame's product pixels are red-dominant, the plain
// one's are not; the GET form and the JSON body's objects[0].base_color are one request (one
// ETag, the same bytes), and another one than the plain product's.
TEST(RenderMaterials, AQueryBaseColorRecolorsTheProduct) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string query =
        "/v1/render?environment=default&mesh=default&width=96&height=96&format=png&samples=1"
        "&ground=off&shadows=off&background=%23000000";
    struct Counts {
        int product = 0;
        int red = 0;
    };
    const auto count = [](const Rgba8Image& image) {
        Counts counts;
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x) {
                const glm::dvec3 c = rgb_at(image, x, y);
                if (max_abs(c) < 16.0) {
                    continue;  // the black background, and the darkest of the stand
                }
                ++counts.product;
                counts.red += c.r > 2.0 * std::max(c.g, c.b);
            }
        }
        return counts;
    };
    const auto plain = client->Get(query.c_str());
    const auto red = client->Get((query + "&base_color=0.8,0.05,0.05").c_str());
    ASSERT_TRUE(plain && red);
    ASSERT_EQ(plain->status, 200) << plain->body;
    ASSERT_EQ(red->status, 200) << red->body;
    const Counts plain_counts = count(decode_image(plain)), red_counts = count(decode_image(red));
    ASSERT_GT(plain_counts.product, 400);  // the dress form: about 8 % of the frame
    EXPECT_LT(plain_counts.red, plain_counts.product / 50);
    EXPECT_GT(red_counts.red, red_counts.product / 2);
    EXPECT_NE(red->get_header_value("ETag"), plain->get_header_value("ETag"));

    const Json body = {{"environment", "default"},
                       {"objects", {{{"mesh", "default"}, {"base_color", {0.8, 0.05, 0.05}}}}},
                       {"width", 96},
                       {"height", 96},
                       {"format", "png"},
                       {"samples", 1},
                       {"ground", false},
                       {"shadows", {{"enabled", false}}},
                       {"background", "#000000"}};
    const auto posted = post_json(*client, "/v1/render", body);
    ASSERT_TRUE(posted);
    ASSERT_EQ(posted->status, 200) << posted->body;
    EXPECT_EQ(posted->get_header_value("ETag"), red->get_header_value("ETag"));
    EXPECT_EQ(posted->body, red->body);
}

// GET and POST forms of one request share their ETag; If-None-Match gives 304 without a body;
// the second identical request comes from the frame cache.
TEST(RenderCaching, EtagRoundTripAndFrameCache) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string query =
        "/v1/render?environment=default&mesh=default&yaw=40&pitch=10"
        "&distance=3&width=96&height=64&samples=1";
    const auto first = client->Get(query.c_str());
    ASSERT_TRUE(first);
    ASSERT_EQ(first->status, 200) << first->body;
    expect_conforms("GET", "/v1/render", first);
    const std::string etag = first->get_header_value("ETag");
    ASSERT_FALSE(etag.empty());
    EXPECT_EQ(first->get_header_value("X-Oer-Cache"), "miss");

    const auto second = client->Get(query.c_str());
    ASSERT_TRUE(second);
    ASSERT_EQ(second->status, 200);
    EXPECT_EQ(second->get_header_value("X-Oer-Cache"), "hit");
    EXPECT_EQ(second->get_header_value("ETag"), etag);
    // A cached frame has no Server-Timing, which the spec therefore does not require.
    expect_conforms("GET", "/v1/render", second);
    EXPECT_EQ(second->body, first->body);

    const auto revalidated = client->Get(query.c_str(), {{"If-None-Match", etag}});
    ASSERT_TRUE(revalidated);
    EXPECT_EQ(revalidated->status, 304);
    EXPECT_TRUE(revalidated->body.empty());
    EXPECT_EQ(revalidated->get_header_value("ETag"), etag);
    expect_conforms("GET", "/v1/render", revalidated);

    const auto stale =
        client->Get(query.c_str(), {{"If-None-Match", "\"" + std::string(64, '0') + "\""}});
    ASSERT_TRUE(stale);
    EXPECT_EQ(stale->status, 200);
    EXPECT_EQ(stale->body, first->body);

    const Json body = {{"environment", "default"},
                       {"objects", {{{"mesh", "default"}}}},
                       {"camera", {{"orbit", {{"yaw", 40}, {"pitch", 10}, {"distance", 3}}}}},
                       {"width", 96},
                       {"height", 64},
                       {"samples", 1}};
    const auto posted = post_json(*client, "/v1/render", body);
    ASSERT_TRUE(posted);
    ASSERT_EQ(posted->status, 200) << posted->body;
    EXPECT_EQ(posted->get_header_value("ETag"), etag);
    EXPECT_EQ(posted->get_header_value("X-Oer-Cache"), "hit");
    EXPECT_EQ(posted->body, first->body);
    const auto posted_revalidated =
        post_json(*client, "/v1/render", body, {{"If-None-Match", etag}});
    ASSERT_TRUE(posted_revalidated);
    EXPECT_EQ(posted_revalidated->status, 304);
    EXPECT_TRUE(posted_revalidated->body.empty());

    // A different request has a different ETag.
    Json other = body;
    other["width"] = 97;
    const auto different = post_json(*client, "/v1/render", other);
    ASSERT_TRUE(different);
    ASSERT_EQ(different->status, 200);
    EXPECT_NE(different->get_header_value("ETag"), etag);
}

// Eight clients at once, each with its own camera, on a server without a frame cache and with
// two render workers: every frame is byte for byte the frame of the same request alone.
TEST(RenderConcurrency, EightClientsAtOnceGetTheFramesTheyWouldGetAlone) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.frame_cache_bytes = 0;
    config.render_workers = 2;
    config.http_threads = 12;
    TestServer server(config);
    const auto request = [](int i) {
        return Json{{"environment", "default"},
                    {"objects", {{{"mesh", "default"}}}},
                    {"camera", {{"orbit", {{"yaw", -150 + 40 * i}, {"pitch", 5 + 3 * i}}}}},
                    {"width", 96},
                    {"height", 96},
                    {"format", "png"},
                    {"samples", 1}};
    };
    constexpr int kClients = 8;
    std::vector<std::string> together(kClients);
    std::vector<int> statuses(kClients, 0);
    std::atomic<int> waiting{kClients};
    std::vector<std::thread> threads;
    for (int i = 0; i < kClients; ++i) {
        threads.emplace_back([&, i] {
            auto client = server.client();
            --waiting;
            while (waiting.load() > 0) {
                std::this_thread::yield();
            }
            const auto result = post_json(*client, "/v1/render", request(i));
            if (result) {
                statuses[std::size_t(i)] = result->status;
                together[std::size_t(i)] = result->body;
            }
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    auto client = server.client();
    for (int i = 0; i < kClients; ++i) {
        ASSERT_EQ(statuses[std::size_t(i)], 200)
            << "client " << i << ": " << together[std::size_t(i)];
        const auto alone = post_json(*client, "/v1/render", request(i));
        ASSERT_TRUE(alone);
        ASSERT_EQ(alone->status, 200);
        EXPECT_EQ(alone->get_header_value("X-Oer-Cache"), "miss");
        EXPECT_TRUE(alone->body == together[std::size_t(i)])
            << "client " << i << "'s frame differs";
        const Rgba8Image image =
            decode_8bit(std::vector<std::uint8_t>(alone->body.begin(), alone->body.end()));
        EXPECT_EQ(image.width, 96);
        for (int j = 0; j < i; ++j) {
            EXPECT_NE(together[std::size_t(i)], together[std::size_t(j)])
                << "clients " << i << " and " << j << " got the same frame for different cameras";
        }
    }
}

// One worker and room for one waiting render: of many slow renders sent at once, those over
// capacity are answered 503 with Retry-After within a second (after the pool's half-second
// admission wait, render_pool.hpp), and every request is answered.
TEST(RenderBackPressure, RequestsOverCapacityGet503PromptlyAndNoneHang) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.max_queue_depth = 1;
    config.render_workers = 1;
    config.frame_cache_bytes = 0;
    config.http_threads = 12;
    // As deployed: the studio's specular cube is made at start. Cold, the burst's first glossy
    // frame prefilters it on the request threads before admission, and every request waits for
    // it (1.8 s under AddressSanitizer in a CI run) before it can be refused.
    config.warm_default_scene = true;
    TestServer server(config);
    constexpr int kRequests = 8;
    struct Outcome {
        int status = 0;
        double seconds = 0.0;
        std::string retry_after;
        std::optional<httplib::Result> result;
    };
    std::vector<Outcome> outcomes(kRequests);
    std::atomic<int> waiting{kRequests};
    std::vector<std::thread> threads;
    for (int i = 0; i < kRequests; ++i) {
        threads.emplace_back([&, i] {
            auto client = server.client(180);
            const Json body = {{"environment", "default"},
                               {"objects", {{{"mesh", "default"}}}},
                               {"camera", {{"orbit", {{"yaw", 10 * i}}}}},
                               {"width", 1024},
                               {"height", 1024},
                               {"samples", 8},
                               {"shadows", {{"resolution", 4096}}}};
            --waiting;
            while (waiting.load() > 0) {
                std::this_thread::yield();
            }
            const auto start = std::chrono::steady_clock::now();
            auto result = post_json(*client, "/v1/render", body);
            Outcome& outcome = outcomes[std::size_t(i)];
            outcome.seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (result) {
                outcome.status = result->status;
                outcome.retry_after = result->get_header_value("Retry-After");
            }
            outcome.result.emplace(std::move(result));
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    // Two kinds of 503: a request refused at the door (no place in the queue within the
    // admission wait of 0.5 s), which must be prompt, and, on a heavily loaded machine, a
    // request admitted to the queue whose frame was not rendered before the request deadline.
    int rendered = 0, refused = 0, timed_out = 0;
    for (int i = 0; i < kRequests; ++i) {
        const Outcome& outcome = outcomes[std::size_t(i)];
        ASSERT_TRUE(outcome.status == 200 || outcome.status == 503)
            << "request " << i << " got " << outcome.status << " after " << outcome.seconds << " s";
        if (outcome.status == 503) {
            EXPECT_FALSE(outcome.retry_after.empty()) << "503 without Retry-After";
            expect_problem("POST", "/v1/render", *outcome.result, ProblemKind::Unavailable);
            const std::string detail = Json::parse((*outcome.result)->body).value("detail", "");
            if (detail.find("not rendered within") != std::string::npos) {
                ++timed_out;
                EXPECT_GE(outcome.seconds, config.request_timeout_seconds) << detail;
            } else {
                ++refused;
                // 0.5 s of admission wait, with room for a loaded machine's scheduling.
                EXPECT_LT(outcome.seconds, 2.0) << "request " << i << " waited for its 503";
            }
        } else {
            ++rendered;
        }
    }
    EXPECT_GE(rendered + timed_out, 1);
    // At most one rendering and one waiting when the burst arrives, and one more admitted if a
    // frame finishes within the admission wait.
    EXPECT_GE(refused, kRequests - 3) << rendered << " rendered, " << timed_out << " timed out";
}

// A request that stops waiting (its deadline passed) takes its frame with it: a worker that
// reaches the frame afterwards skips it (oer_renders_skipped_total), and one under way stops it
// between passes (oer_renders_stopped_total), instead of rendering it for nobody, so that
// clients who gave up do not cost the ones still waiting. One worker, a 1 s deadline, four
// frames of seconds each sent at once: none is rendered to the end.
TEST(RenderDeadline, FramesWhoseRequestGaveUpAreSkipped) {
    TempRoot root;
    server::ServiceConfig config = test_config(root.data());
    config.render_workers = 1;
    config.max_queue_depth = 4;
    config.frame_cache_bytes = 0;
    config.request_timeout_seconds = 1;
    TestServer server(config);
    auto metrics_client = server.client();
    const Metrics before = scrape(*metrics_client);
    constexpr int kRequests = 4;
    std::vector<int> statuses(kRequests, 0);
    std::vector<std::string> retry_after(kRequests);
    std::vector<std::thread> threads;
    for (int i = 0; i < kRequests; ++i) {
        threads.emplace_back([&, i] {
            auto client = server.client(30);
            const Json body = {{"environment", "default"},
                               {"objects", {{{"mesh", "default"}}}},
                               {"camera", {{"orbit", {{"yaw", 10 * i}}}}},
                               {"width", 1024},
                               {"height", 1024},
                               {"samples", 4},
                               {"shadows", {{"resolution", 4096}}}};
            const auto result = post_json(*client, "/v1/render", body);
            if (result) {
                statuses[std::size_t(i)] = result->status;
                retry_after[std::size_t(i)] = result->get_header_value("Retry-After");
            }
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    int refused = 0;
    for (int i = 0; i < kRequests; ++i) {
        ASSERT_TRUE(statuses[std::size_t(i)] == 200 || statuses[std::size_t(i)] == 503)
            << "request " << i << ": " << statuses[std::size_t(i)];
        if (statuses[std::size_t(i)] == 503) {
            ++refused;
            EXPECT_EQ(retry_after[std::size_t(i)], "1");
        }
    }
    // A frame of 1024x1024 pixels at 4 samples takes seconds on llvmpipe: every request gives up.
    ASSERT_GE(refused, kRequests - 1) << "the frames were rendered within the 1 s deadline";
    const auto ended = [&] {
        const Metrics now = scrape(*metrics_client);
        const auto counted = [&](const std::string& name) {
            return now.sum(name) - before.sum(name);
        };
        return std::array{counted("oer_render_seconds_count"), counted("oer_renders_skipped_total"),
                          counted("oer_renders_stopped_total")};
    };
    ASSERT_TRUE(eventually(
        [&] {
            const auto [rendered, skipped, stopped] = ended();
            return rendered + skipped + stopped == kRequests;
        },
        std::chrono::seconds(120)))
        << "the worker did not get through the four frames";
    const auto [rendered, skipped, stopped] = ended();
    // Only frames answered 200 are rendered to the end; the one under way when its request gave
    // up is stopped, the others are skipped.
    EXPECT_EQ(rendered, double(kRequests - refused));
    EXPECT_LE(stopped, 1.0);
    EXPECT_GE(skipped, double(refused - 1));
}

namespace {}  // namespace

// A frame names the camera it is seen from (X-Oer-Camera), the automatic framing's included, and
// a cached frame too: an orbit built from that header draws the same pixels, and so continues
// from the framing without a jump (what the web client's zoom relies on).
TEST(RenderCamera, TheHeaderNamesTheAutomaticFramingSoAnOrbitFromItDrawsTheSameFrame) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const std::string common =
        "/v1/render?environment=default&mesh=default&width=96&height=64&samples=1&format=png";
    const auto framed = client->Get(common.c_str());
    ASSERT_TRUE(framed);
    ASSERT_EQ(framed->status, 200) << framed->body;
    const std::string header = framed->get_header_value("X-Oer-Camera");
    const glm::dvec3 eye = camera_vector(header, "eye");
    const glm::dvec3 target = camera_vector(header, "target");
    const glm::dvec3 offset = eye - target;
    const double distance = glm::length(offset);
    // The automatic framing is the default orbit (yaw 30, pitch 15) about the scene's centre.
    EXPECT_NEAR(glm::degrees(std::atan2(offset.x, offset.z)), 30.0, 1e-3) << header;
    EXPECT_NEAR(glm::degrees(std::asin(offset.y / distance)), 15.0, 1e-3) << header;
    EXPECT_NE(distance, 3.0) << "the dress form's framing is not the fixed default distance";

    const auto cached = client->Get(common.c_str());
    ASSERT_TRUE(cached);
    EXPECT_EQ(cached->get_header_value("X-Oer-Cache"), "hit");
    EXPECT_EQ(cached->get_header_value("X-Oer-Camera"), header);

    char orbit[256];
    std::snprintf(orbit, sizeof orbit, "&yaw=30&pitch=15&distance=%.6f&target=%.6f,%.6f,%.6f",
                  distance, target.x, target.y, target.z);
    const auto continued = client->Get((common + orbit).c_str());
    ASSERT_TRUE(continued);
    ASSERT_EQ(continued->status, 200) << continued->body;
    const Rgba8Image a = decode_image(framed);
    const Rgba8Image b = decode_image(continued);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    int largest = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        largest = std::max(largest, std::abs(int(a.pixels[i]) - int(b.pixels[i])));
    }
    // The orbit from the header (printed here to six decimals) moves the camera by far less than
    // a pixel.
    EXPECT_LE(largest, 2) << "the orbit from X-Oer-Camera draws another frame";
}

// With the ground on, an orbit under the floor is drawn from just above it (pitch raised until
// the eye is 3 degrees above the dress form's lowest y, where the floor lies), and the frame's
// X-Oer-Camera names that camera; a look-at eye under the floor is 422 naming `eye`.
TEST(RenderCamera, AnOrbitUnderTheFloorIsRaisedAboveItAndTheHeaderSaysSo) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const auto mesh = client->Get("/v1/meshes/default");
    ASSERT_TRUE(mesh);
    const double floor = Json::parse(mesh->body).at("bounds").at("min")[1];
    const std::string common =
        "/v1/render?environment=default&mesh=default&width=32&height=32&samples=1";
    const auto framed = client->Get((common + "&yaw=30&pitch=-60").c_str());
    ASSERT_TRUE(framed);
    ASSERT_EQ(framed->status, 200) << framed->body;
    const std::string header = framed->get_header_value("X-Oer-Camera");
    const glm::dvec3 offset = camera_vector(header, "eye") - camera_vector(header, "target");
    const double distance = glm::length(offset);
    EXPECT_NEAR(camera_vector(header, "eye").y - floor, distance * std::sin(glm::radians(3.0)),
                1e-3 * distance)
        << header;
    EXPECT_GT(glm::degrees(std::asin(offset.y / distance)), -60.0) << header;
    expect_problem("GET", "/v1/render",
                   client->Get((common + "&eye=0,-0.5,3&target=0,1,0").c_str()),
                   ProblemKind::InvalidParameter, "eye");
}
