// Hotspots and picking end to end (docs/hotspots.md): POST and GET /v1/hotspots place points of
// the product in the frame a render request draws, from that frame's depth buffer; POST
// /v1/pick names the surface a pixel shows. Held to independent computations: each position
// against the projection of the point with the answer's camera (the X-Oer-Camera of the frame,
// glm's lookAt and perspective here, not the service's code), within half a pixel; each
// visibility against a ray cast from the eye to the point on the reference renderer's Embree
// scene of the same meshes, over random points and views.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

#include "http_support.hpp"
#include "oer/mesh/default_product.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/reference/embree_scene.hpp"
#include "oer/scene/point_placement.hpp"
#include "oer/scene/scene_bounds.hpp"

using namespace oer;
using namespace oer::itest;
using oer::server::ProblemKind;

namespace {

// The camera of an X-Oer-Camera header (`eye=x,y,z; target=...; up=...; fov_y=f`).
Camera camera_of(const std::string& header) {
    Camera camera;
    camera.eye = glm::vec3(camera_vector(header, "eye"));
    camera.target = glm::vec3(camera_vector(header, "target"));
    camera.up = glm::vec3(camera_vector(header, "up"));
    const std::size_t fov = header.find("fov_y=");
    EXPECT_NE(fov, std::string::npos) << header;
    camera.fov_y = fov == std::string::npos ? 45.0f : std::stof(header.substr(fov + 6));
    return camera;
}

// Where `point` lands in a width x height frame seen by `camera`, by the textbook matrices
// (image y down from the top); w <= 0 behind the eye.
struct Projected {
    double x, y, w;
};
Projected project(const Camera& camera, int width, int height, const glm::dvec3& point) {
    const glm::dmat4 view =
        glm::lookAt(glm::dvec3(camera.eye), glm::dvec3(camera.target), glm::dvec3(camera.up));
    const glm::dmat4 projection =
        glm::perspective(glm::radians(double(camera.fov_y)), double(width) / height, 0.01, 100.0);
    const glm::dvec4 clip = projection * view * glm::dvec4(point, 1.0);
    return {(clip.x / clip.w + 1.0) * 0.5 * width, (1.0 - clip.y / clip.w) * 0.5 * height, clip.w};
}

// The scene of these tests: the default product, and a box standing in front of it to its
// right, so that the objects hide each other as well as themselves.
constexpr double kBoxTransform[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.25, 0, 0.55, 1};
const std::string kBoxObj = box_obj({-0.15, 0.0, -0.15}, {0.15, 0.5, 0.15});

Json scene_body(const std::string& box_id) {
    Json transform = Json::array();
    for (const double v : kBoxTransform) {
        transform.push_back(v);
    }
    return {{"environment", "default"},
            {"objects", {{{"mesh", "default"}}, {{"mesh", box_id}, {"transform", transform}}}}};
}

struct LocalScene {
    std::vector<std::shared_ptr<const Mesh>> meshes;
    std::vector<glm::mat4> transforms;
};

LocalScene local_scene() {
    LocalScene scene;
    scene.meshes.push_back(std::make_shared<const Mesh>(make_default_product()));
    scene.meshes.push_back(std::make_shared<const Mesh>(load_mesh_memory(
        std::as_bytes(std::span(kBoxObj.data(), kBoxObj.size())), "box.obj", MeshFormat::Obj)));
    scene.transforms.push_back(glm::mat4(1.0f));
    glm::mat4 box{1.0f};
    for (int i = 0; i < 16; ++i) {
        box[i / 4][i % 4] = float(kBoxTransform[i]);
    }
    scene.transforms.push_back(box);
    return scene;
}

// A random surface point: its request member, and its position and front normal computed here.
struct Spot {
    Json member;
    glm::dvec3 position;
    glm::dvec3 normal;
};

Spot random_surface_spot(std::mt19937& random, const LocalScene& scene, const std::string& name) {
    const std::size_t object = std::uniform_int_distribution<std::size_t>(0, 1)(random);
    const Mesh& mesh = *scene.meshes[object];
    const std::size_t primitive =
        std::uniform_int_distribution<std::size_t>(0, mesh.primitives.size() - 1)(random);
    const Primitive& p = mesh.primitives[primitive];
    const std::size_t triangle =
        std::uniform_int_distribution<std::size_t>(0, p.indices.size() / 3 - 1)(random);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double a = unit(random), b = unit(random);
    if (a + b > 1.0) {
        a = 1.0 - a;
        b = 1.0 - b;
    }
    const glm::dvec3 weights{1.0 - a - b, a, b};
    glm::dvec3 corners[3];
    for (int k = 0; k < 3; ++k) {
        corners[k] = glm::dvec3(scene.transforms[object] *
                                glm::vec4(p.positions[p.indices[3 * triangle + k]], 1.0f));
    }
    Spot spot;
    spot.position = weights.x * corners[0] + weights.y * corners[1] + weights.z * corners[2];
    spot.normal = glm::normalize(glm::cross(corners[1] - corners[0], corners[2] - corners[0]));
    spot.member = {{"name", name},
                   {"object", object},
                   {"primitive", primitive},
                   {"triangle", triangle},
                   {"barycentric", {weights.x, weights.y, weights.z}}};
    return spot;
}

}  // namespace

// Random views (orbits at random yaw, pitch, distance, field of view and frame shape, with and
// without the floor), random points on both objects' triangles, and points facing the eye in the
// scene's box and just behind the surfaces (which only the depth can hide): every position within
// half a pixel of the projection with the answer's camera, and every visibility as a ray cast says,
// but within two pixels of a silhouette or a pixel footprint of the tolerance's edge (at most 5 %
// of them).
TEST(HotspotsPlacement, PositionsAreTheCameraProjectionAndVisibilityAgreesWithRayCasting) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json box = upload_mesh(*client, kBoxObj, "model/obj");
    ASSERT_FALSE(HasFatalFailure());
    const LocalScene scene = local_scene();
    ASSERT_EQ(box.at("counts").at("triangles").get<std::size_t>(),
              scene.meshes[1]->primitives[0].indices.size() / 3)
        << "the box as loaded here is the box the service holds";

    std::mt19937 random(31);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    constexpr int kViews = 12;
    constexpr int kSpotsPerView = 12;
    constexpr int kPointsPerView = 10;
    const int sizes[][2] = {{320, 240}, {256, 256}, {200, 300}};
    double largest_error = 0.0;
    int agreed = 0, excused = 0, visible = 0, hidden = 0, hidden_by_depth = 0, outside = 0;
    double slowest_ms = 0.0;
    for (int view = 0; view < kViews; ++view) {
        Json body = scene_body(box.at("id"));
        const int* size = sizes[view % 3];
        body["width"] = size[0];
        body["height"] = size[1];
        const bool ground = view % 2 == 0;
        body["ground"] = ground;
        body["camera"] = {{"orbit",
                           {{"yaw", -180.0 + 360.0 * unit(random)},
                            {"pitch", -25.0 + 80.0 * unit(random)},
                            {"distance", 1.6 + 2.0 * unit(random)}}},
                          {"fov_y", 25.0 + 40.0 * unit(random)}};
        std::vector<Spot> spots;
        for (int i = 0; i < kSpotsPerView; ++i) {
            spots.push_back(random_surface_spot(random, scene, "s" + std::to_string(i)));
            body["hotspots"].push_back(spots.back().member);
        }
        const auto start = std::chrono::steady_clock::now();
        const auto result = post_json(*client, "/v1/hotspots", body);
        slowest_ms = std::max(slowest_ms, 1000.0 * seconds_since(start));
        const Json answer = expect_conforms("POST", "/v1/hotspots", result);
        ASSERT_FALSE(HasFatalFailure());
        ASSERT_EQ(result->get_header_value("X-Oer-Camera"), answer.at("camera"));
        const Camera camera = camera_of(answer.at("camera"));

        FrameRequest request;
        request.ground = ground;
        for (std::size_t o = 0; o < scene.meshes.size(); ++o) {
            request.objects.push_back({scene.meshes[o], scene.transforms[o], std::nullopt});
        }
        const reference::EmbreeScene rays(request, scene_bounds(request.objects));
        const double pixel_per_depth =
            2.0 * std::tan(glm::radians(double(camera.fov_y)) / 2.0) / size[1];
        // Whether the surface a ray from the eye meets is as near as `point`, within the
        // service's tolerance (oer/scene/point_placement.hpp).
        const glm::dvec3 eye(camera.eye);
        const auto ray_reaches = [&](const glm::dvec3& point) {
            const double distance = glm::length(point - eye);
            const auto hit =
                rays.intersect(eye, (point - eye) / distance, 0.0, reference::GroundReach::Drawn);
            return !hit ||
                   unoccluded_by(distance, glm::length(hit->position - eye), pixel_per_depth);
        };
        // Each placement against the projection, its facing against the normal, and its
        // visibility against a ray cast.
        const auto judge = [&](const Json& placed, const Spot& spot, const std::string& what) {
            EXPECT_EQ(placed.at("name"), spot.member.at("name"));
            const Projected expected = project(camera, size[0], size[1], spot.position);
            const bool in_frame = expected.w > 0.0 && expected.x >= 0.0 && expected.x < size[0] &&
                                  expected.y >= 0.0 && expected.y < size[1];
            EXPECT_EQ(placed.at("in_frame"), in_frame) << what;
            if (expected.w > 0.0) {
                const double error = std::max(std::abs(placed.at("x").get<double>() - expected.x),
                                              std::abs(placed.at("y").get<double>() - expected.y));
                largest_error = std::max(largest_error, error);
                EXPECT_LE(error, 0.5) << what;
            }
            if (!in_frame) {
                ++outside;
                return;
            }
            const bool facing = glm::dot(spot.normal, eye - spot.position) > 0.0;
            EXPECT_EQ(placed.at("facing"), facing) << what;
            const bool reaches = ray_reaches(spot.position);
            const bool reference = facing && reaches;
            const bool service = placed.at("visible");
            (reference ? visible : hidden) += 1;
            hidden_by_depth += facing && !reaches ? 1 : 0;
            if (service == reference) {
                ++agreed;
                return;
            }
            // A point within two pixels of a silhouette, where the depth buffer's samples around
            // it see another surface than the point's ray, may go either way: there the rays two
            // pixels aside reach the point's depth on one side and not on another. So may one
            // whose occluder lies within a pixel footprint of the tolerance's edge (the depth
            // buffer holds the levels of detail drawn, the ray the full mesh).
            const glm::dvec3 right =
                glm::normalize(glm::cross(glm::dvec3(camera.target) - eye, glm::dvec3(camera.up)));
            const glm::dvec3 up =
                glm::normalize(glm::cross(right, glm::dvec3(camera.target) - eye));
            const double distance = glm::length(spot.position - eye);
            const double step = 2.0 * pixel_per_depth * distance;
            int reaching = 0;
            for (const glm::dvec3& aside : {right, -right, up, -up}) {
                reaching += ray_reaches(spot.position + step * aside) ? 1 : 0;
            }
            const auto hit = rays.intersect(eye, (spot.position - eye) / distance, 0.0,
                                            reference::GroundReach::Drawn);
            const double edge = distance * (1.0 - kOcclusionTolerancePixels * pixel_per_depth);
            const bool near_edge = hit && std::abs(glm::length(hit->position - eye) - edge) <
                                              pixel_per_depth * distance;
            const bool excusable = (reaching != 0 && reaching != 4) || near_edge;
            EXPECT_TRUE(excusable)
                << what << ": the service says " << (service ? "visible" : "hidden")
                << ", a ray cast " << (reference ? "visible" : "hidden")
                << ", away from any silhouette";
            excused += excusable ? 1 : 0;
        };
        for (int i = 0; i < kSpotsPerView; ++i) {
            judge(answer.at("hotspots").at(i), spots[std::size_t(i)],
                  "view " + std::to_string(view) + " surface spot " + std::to_string(i));
        }
        // Points anywhere in the scene's box, and points just behind the objects' surfaces as the
        // eye sees them, their normals towards the eye: only the depth can hide them.
        const Bounds box = scene_bounds(request.objects).box;
        Json volume = body;
        volume["hotspots"] = Json::array();
        std::vector<Spot> points;
        for (int i = 0; i < kPointsPerView; ++i) {
            Spot point;
            if (i % 2 == 0) {
                point.position =
                    glm::dvec3(box.min) + glm::dvec3(unit(random), unit(random), unit(random)) *
                                              glm::dvec3(box.max - box.min);
            } else {
                // Behind a surface point, as the eye sees it, by two pixel footprints past the
                // tolerance to a tenth of the distance more: clearly hidden where it is seen.
                const glm::dvec3 on = random_surface_spot(random, scene, "behind").position;
                const double beyond = (kOcclusionTolerancePixels + 2.0) * pixel_per_depth;
                point.position = on + (beyond + 0.1 * unit(random)) * (on - eye);
            }
            point.normal = glm::normalize(eye - point.position);
            point.member = {{"name", "p" + std::to_string(i)},
                            {"position", {point.position.x, point.position.y, point.position.z}},
                            {"normal", {point.normal.x, point.normal.y, point.normal.z}}};
            volume["hotspots"].push_back(point.member);
            points.push_back(point);
        }
        const Json volume_answer =
            expect_conforms("POST", "/v1/hotspots", post_json(*client, "/v1/hotspots", volume));
        ASSERT_FALSE(HasFatalFailure());
        for (int i = 0; i < kPointsPerView; ++i) {
            judge(volume_answer.at("hotspots").at(i), points[std::size_t(i)],
                  "view " + std::to_string(view) + " point " + std::to_string(i));
        }
    }
    std::printf(
        "hotspots: %d points in frame over %d views (%d outside), %d visible and %d "
        "hidden by ray casting (%d of them facing the eye, hidden by a surface in front); %d "
        "agree, %d differ where either answer may be right; largest position error %.2e px; "
        "slowest answer %.1f ms\n",
        visible + hidden, kViews, outside, visible, hidden, hidden_by_depth, agreed, excused,
        largest_error, slowest_ms);
    EXPECT_GE(visible + hidden, 100);
    EXPECT_GE(visible, 20) << "too few visible points to tell a working test from a broken one";
    EXPECT_GE(hidden, 20) << "too few hidden points to tell a working test from a broken one";
    EXPECT_GE(hidden_by_depth, 20) << "too few points that only the depth hides";
    EXPECT_LE(excused, (visible + hidden) / 20) << "more than 5 % differ, even near silhouettes";
}

// The GET form places the same points as the body, and point hotspots (a position and a
// normal) as the surface hotspots there.
TEST(HotspotsPlacement, TheQueryFormAndPointHotspotsPlaceAsTheBodyDoes) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json body = {{"environment", "default"},
                       {"objects", {{{"mesh", "default"}}}},
                       {"width", 300},
                       {"height", 200},
                       {"camera", {{"orbit", {{"yaw", 20}, {"pitch", 10}}}}},
                       {"hotspots",
                        {{{"name", "front"}, {"position", {0.0, 1.0, 0.4}}, {"normal", {0, 0, 1}}},
                         {{"name", "surface"},
                          {"object", 0},
                          {"triangle", 3},
                          {"barycentric", {0.2, 0.3, 0.5}}}}}};
    const Json by_body =
        expect_conforms("POST", "/v1/hotspots", post_json(*client, "/v1/hotspots", body));
    const Json by_query = expect_conforms(
        "GET", "/v1/hotspots",
        client->Get("/v1/hotspots?environment=default&mesh=default&width=300&height=200&yaw=20&"
                    "pitch=10&hotspot=front:point:0,1,0.4,0,0,1&"
                    "hotspot=surface:surface:0,0,3,0.2,0.3,0.5"));
    ASSERT_FALSE(HasFatalFailure());
    EXPECT_EQ(by_body, by_query);
}

// A pixel that shows the product names its surface, which, given back as a hotspot, lands on
// that pixel and is visible; a pixel of the background or the floor shows no product.
TEST(HotspotsPick, APickedSurfaceIsAHotspotThatLandsOnItsPixelVisibly) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    Json body = {{"environment", "default"},
                 {"objects", {{{"mesh", "default"}}}},
                 {"width", 256},
                 {"height", 256},
                 {"camera", {{"orbit", {{"yaw", 35}, {"pitch", 12}}}}}};
    int hits = 0;
    for (const auto& [x, y] : {std::pair{128.5, 100.5}, {128.5, 60.5}, {128.5, 128.5}}) {
        body["pixel"] = {x, y};
        const Json picked =
            expect_conforms("POST", "/v1/pick", post_json(*client, "/v1/pick", body));
        ASSERT_FALSE(HasFatalFailure());
        if (!picked.at("hit")) {
            continue;
        }
        ++hits;
        Json hotspots = body;
        hotspots.erase("pixel");
        hotspots["hotspots"] = {{{"name", "picked"},
                                 {"object", picked.at("object")},
                                 {"primitive", picked.at("primitive")},
                                 {"triangle", picked.at("triangle")},
                                 {"barycentric", picked.at("barycentric")}}};
        const Json placed =
            expect_conforms("POST", "/v1/hotspots", post_json(*client, "/v1/hotspots", hotspots));
        ASSERT_FALSE(HasFatalFailure());
        const Json& spot = placed.at("hotspots").at(0);
        EXPECT_NEAR(spot.at("x").get<double>(), x, 1e-3);
        EXPECT_NEAR(spot.at("y").get<double>(), y, 1e-3);
        EXPECT_TRUE(spot.at("visible").get<bool>()) << spot.dump();
    }
    EXPECT_EQ(hits, 3) << "the dress form's torso and its stand are at these pixels";
    body["pixel"] = {2.5, 2.5};
    const Json sky = expect_conforms("POST", "/v1/pick", post_json(*client, "/v1/pick", body));
    EXPECT_FALSE(sky.value("hit", true));
    EXPECT_FALSE(sky.contains("triangle"));
}

// Every malformed or hostile member is a problem naming it, never a crash.
TEST(HotspotsErrors, EachBadMemberIsAProblemNamingIt) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json base = {{"environment", "default"}, {"objects", {{{"mesh", "default"}}}}};
    const auto with = [&](const Json& hotspot) {
        Json body = base;
        body["hotspots"] = Json::array({hotspot});
        return body;
    };
    const Json surface = {
        {"name", "a"}, {"object", 0}, {"triangle", 0}, {"barycentric", {1.0, 0.0, 0.0}}};
    const auto expect_invalid = [&](const Json& body, const std::string& parameter) {
        expect_problem("POST", "/v1/hotspots", post_json(*client, "/v1/hotspots", body),
                       ProblemKind::InvalidParameter, parameter);
    };
    Json far_triangle = surface;
    far_triangle["triangle"] = 100000000;
    expect_invalid(with(far_triangle), "hotspots/0/triangle");
    Json far_primitive = surface;
    far_primitive["primitive"] = 999;
    expect_invalid(with(far_primitive), "hotspots/0/primitive");
    Json far_object = surface;
    far_object["object"] = 1;
    expect_invalid(with(far_object), "hotspots/0/object");
    Json negative = surface;
    negative["triangle"] = -1;
    expect_invalid(with(negative), "hotspots/0/triangle");
    Json weights = surface;
    weights["barycentric"] = {0.5, 0.5, 0.5};
    expect_invalid(with(weights), "hotspots/0/barycentric");
    Json bad_name = surface;
    bad_name["name"] = "a b";
    expect_invalid(with(bad_name), "hotspots/0/name");
    expect_invalid(with({{"name", "p"}, {"position", {0, 1, 0}}, {"normal", {0, 0, 0}}}),
                   "hotspots/0/normal");
    expect_invalid(with({{"name", "p"}, {"position", {0, 1, 0}}, {"object", 0}}), "hotspots/0");
    expect_invalid(with({{"name", "p"}, {"extra", 1}}), "hotspots/0/extra");
    Json twice = base;
    twice["hotspots"] = Json::array({surface, surface});
    expect_invalid(twice, "hotspots/1/name");
    expect_invalid(base, "hotspots");
    Json many = base;
    for (int i = 0; i < 300; ++i) {
        Json spot = surface;
        spot["name"] = "h" + std::to_string(i);
        many["hotspots"].push_back(spot);
    }
    expect_problem("POST", "/v1/hotspots", post_json(*client, "/v1/hotspots", many),
                   ProblemKind::LimitExceeded, "hotspots");
    expect_problem("GET", "/v1/hotspots",
                   client->Get("/v1/hotspots?environment=default&mesh=default&hotspot=a:surface:"
                               "0,0,99999999,1,0,0"),
                   ProblemKind::InvalidParameter, "hotspot");
    expect_problem("GET", "/v1/hotspots",
                   client->Get("/v1/hotspots?environment=default&mesh=default&hotspot=a:cone:1"),
                   ProblemKind::InvalidParameter, "hotspot");
    Json pick = base;
    pick["pixel"] = {600, 10};
    expect_problem("POST", "/v1/pick", post_json(*client, "/v1/pick", pick),
                   ProblemKind::InvalidParameter, "pixel/0");
    pick["pixel"] = "middle";
    expect_problem("POST", "/v1/pick", post_json(*client, "/v1/pick", pick),
                   ProblemKind::InvalidParameter, "pixel");
    pick["pixel"] = {10, 10};
    pick["objects"][0]["mesh"] = std::string(64, 'a');
    expect_problem("POST", "/v1/pick", post_json(*client, "/v1/pick", pick), ProblemKind::UnknownId,
                   "objects/0/mesh");
    expect_problem("POST", "/v1/hotspots",
                   client->Post("/v1/hotspots", "{\"hotspots\": [", "application/json"),
                   ProblemKind::MalformedRequest);
    expect_problem("POST", "/v1/hotspots", client->Post("/v1/hotspots", "{}", "text/plain"),
                   ProblemKind::UnsupportedMediaType);
}
