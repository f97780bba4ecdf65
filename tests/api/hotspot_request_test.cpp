// The hotspots' and the pick's requests (oer/api/hotspot_request.hpp): both forms read alike,
// every bad member refused naming it, the limits, and a surface hotspot's point and normal
// against the triangle's.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "oer/api/hotspot_request.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/malformed_request.hpp"
#include "oer/mesh/default_product.hpp"

using namespace oer;
using Json = nlohmann::json;

namespace {

Json with_hotspots(const Json& hotspots) {
    return {
        {"environment", "default"}, {"objects", {{{"mesh", "default"}}}}, {"hotspots", hotspots}};
}

const Json kSurface = {
    {"name", "collar"}, {"object", 0}, {"triangle", 4}, {"barycentric", {0.2, 0.3, 0.5}}};
const Json kPoint = {{"name", "hem"}, {"position", {0, 1, 0.5}}, {"normal", {0, 0, 2}}};

// The member a hotspots body is rejected for ("" when accepted).
std::string rejected(const Json& body) {
    try {
        api::parse_hotspot_json(body.dump());
    } catch (const api::InvalidParameter& error) {
        return error.parameter();
    }
    return "";
}

std::string rejected_query(const std::multimap<std::string, std::string>& query) {
    try {
        api::parse_hotspot_query(query);
    } catch (const api::InvalidParameter& error) {
        return error.parameter();
    }
    return "";
}

}  // namespace

TEST(HotspotRequest, BothFormsReadTheSameHotspots) {
    const api::HotspotRequest body =
        api::parse_hotspot_json(with_hotspots(Json::array({kSurface, kPoint})).dump());
    const api::HotspotRequest query =
        api::parse_hotspot_query({{"environment", "default"},
                                  {"mesh", "default"},
                                  {"hotspot", "collar:surface:0,0,4,0.2,0.3,0.5"},
                                  {"hotspot", "hem:point:0,1,0.5,0,0,2"}});
    ASSERT_EQ(body.hotspots.size(), 2u);
    ASSERT_EQ(query.hotspots.size(), 2u);
    EXPECT_EQ(api::normalised_render_json(body.render), api::normalised_render_json(query.render));
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(body.hotspots[i].name, query.hotspots[i].name);
    }
    const auto& surface = std::get<api::SurfaceSpot>(body.hotspots[0].place);
    EXPECT_EQ(surface.triangle, 4u);
    EXPECT_EQ(surface.primitive, 0u);
    EXPECT_EQ(surface.barycentric, glm::dvec3(0.2, 0.3, 0.5));
    const auto& point = std::get<api::PointSpot>(query.hotspots[1].place);
    EXPECT_EQ(point.normal, glm::dvec3(0, 0, 1)) << "normalised";
}

TEST(HotspotRequest, EachBadMemberIsNamed) {
    const auto changed = [](Json hotspot, const std::string& member, const Json& value) {
        hotspot[member] = value;
        return with_hotspots(Json::array({hotspot}));
    };
    EXPECT_EQ(rejected(changed(kSurface, "object", 1)), "hotspots/0/object");
    EXPECT_EQ(rejected(changed(kSurface, "object", -1)), "hotspots/0/object");
    EXPECT_EQ(rejected(changed(kSurface, "object", 0.5)), "hotspots/0/object");
    EXPECT_EQ(rejected(changed(kSurface, "triangle", "4")), "hotspots/0/triangle");
    EXPECT_EQ(rejected(changed(kSurface, "primitive", 1e300)), "hotspots/0/primitive");
    EXPECT_EQ(rejected(changed(kSurface, "barycentric", {0.2, 0.3})), "hotspots/0/barycentric");
    EXPECT_EQ(rejected(changed(kSurface, "barycentric", {0.9, 0.9, 0.1})),
              "hotspots/0/barycentric");
    EXPECT_EQ(rejected(changed(kSurface, "barycentric", {-0.1, 0.6, 0.5})),
              "hotspots/0/barycentric/0");
    EXPECT_EQ(rejected(changed(kSurface, "name", "")), "hotspots/0/name");
    EXPECT_EQ(rejected(changed(kSurface, "name", std::string(65, 'a'))), "hotspots/0/name");
    EXPECT_EQ(rejected(changed(kSurface, "name", "a\"b")), "hotspots/0/name");
    EXPECT_EQ(rejected(changed(kSurface, "name", 7)), "hotspots/0/name");
    EXPECT_EQ(rejected(changed(kSurface, "position", {0, 0, 0})), "hotspots/0");
    EXPECT_EQ(rejected(changed(kSurface, "colour", "red")), "hotspots/0/colour");
    EXPECT_EQ(rejected(changed(kPoint, "normal", {0, 0, 0})), "hotspots/0/normal");
    EXPECT_EQ(rejected(changed(kPoint, "position", {0, 1e7, 0})), "hotspots/0/position/1");
    EXPECT_EQ(rejected(changed(kPoint, "position", {0, "1", 0})), "hotspots/0/position/1");
    EXPECT_EQ(rejected(with_hotspots(Json::array({kSurface, kSurface}))), "hotspots/1/name");
    EXPECT_EQ(rejected(with_hotspots(Json::array({1}))), "hotspots/0");
    EXPECT_EQ(rejected(with_hotspots(Json::object())), "hotspots");
    Json without = with_hotspots(Json::array());
    without.erase("hotspots");
    EXPECT_EQ(rejected(without), "hotspots");
    Json typo = with_hotspots(Json::array({kSurface}));
    typo["hotspot"] = Json::array();
    EXPECT_EQ(rejected(typo), "hotspot") << "an unknown member beside the render's";
    EXPECT_EQ(rejected(with_hotspots(Json::array())), "") << "no hotspot is a valid, empty request";

    const std::multimap<std::string, std::string> base = {{"environment", "default"},
                                                          {"mesh", "default"}};
    for (const std::string bad :
         {"collar", "collar:surface", "collar:surface:0,0,4,0.2,0.3", "collar:cone:0,0,4,1,0,0",
          "col lar:surface:0,0,4,1,0,0", "collar:surface:0,0,-4,1,0,0",
          "collar:surface:1,0,4,1,0,0", "collar:point:0,0,0,0,0,0", "collar:point:0,0,0,0,0,x",
          "collar:surface:0,0,4,0.5,0.5,0.5,"}) {
        auto query = base;
        query.insert({"hotspot", bad});
        EXPECT_EQ(rejected_query(query), "hotspot") << bad;
    }
    auto unknown = base;
    unknown.insert({"hotspots", "collar:point:0,0,0,0,0,1"});
    EXPECT_EQ(rejected_query(unknown), "hotspots");
}

TEST(HotspotRequest, MoreHotspotsThanTheLimitAreALimitNotAnInvalidValue) {
    api::RenderLimits limits;
    limits.max_hotspots = 3;
    Json hotspots = Json::array();
    for (int i = 0; i < 4; ++i) {
        Json hotspot = kPoint;
        hotspot["name"] = "h" + std::to_string(i);
        hotspots.push_back(hotspot);
    }
    try {
        api::parse_hotspot_json(with_hotspots(hotspots).dump(), limits);
        FAIL() << "accepted";
    } catch (const api::InvalidParameter& error) {
        EXPECT_EQ(error.parameter(), "hotspots");
        EXPECT_EQ(error.kind(), ErrorKind::LimitExceeded);
    }
    // Far more small values than any valid body holds: refused while parsing.
    std::string flood = R"({"environment": "default", "hotspots": [)";
    for (int i = 0; i < 20000; ++i) {
        flood += (i ? "," : "") + std::string("[0,0,0,0]");
    }
    flood += "]}";
    try {
        api::parse_hotspot_json(flood);
        FAIL() << "accepted";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::LimitExceeded);
    }
    EXPECT_THROW(api::parse_hotspot_json(R"({"hotspots": [)"), api::MalformedRequest);
}

TEST(HotspotRequest, APickPixelMustLieInTheFrame) {
    const Json base = {{"environment", "default"}, {"width", 200}, {"height", 100}};
    const auto pixel_error = [&](const Json& pixel) -> std::string {
        Json body = base;
        body["pixel"] = pixel;
        try {
            api::parse_pick_json(body.dump());
        } catch (const api::InvalidParameter& error) {
            return error.parameter();
        }
        return "";
    };
    EXPECT_EQ(pixel_error({199.5, 99.5}), "");
    EXPECT_EQ(pixel_error({200, 50}), "pixel");
    EXPECT_EQ(pixel_error({-1, 50}), "pixel/0");
    EXPECT_EQ(pixel_error({10, 1e9}), "pixel/1");
    EXPECT_EQ(pixel_error({10}), "pixel");
    EXPECT_EQ(pixel_error("10,10"), "pixel");
    EXPECT_EQ(pixel_error(nullptr), "pixel");
    const api::PickRequest query = api::parse_pick_query(
        {{"environment", "default"}, {"width", "200"}, {"height", "100"}, {"pixel", "12.5,7"}});
    EXPECT_EQ(query.pixel, glm::dvec2(12.5, 7.0));
    for (const std::string bad : {"12.5", "12.5,", "a,b", "300,7", "12,100"}) {
        try {
            api::parse_pick_query(
                {{"environment", "default"}, {"width", "200"}, {"height", "100"}, {"pixel", bad}});
            ADD_FAILURE() << bad << " accepted";
        } catch (const api::InvalidParameter& error) {
            EXPECT_EQ(error.parameter(), "pixel") << bad;
        }
    }
}

// The point of a triangle is its corners weighted, placed by the object's transform, and its
// normal the triangle's front, turned around by a mirroring transform as the winding is.
TEST(HotspotRequest, ASurfaceHotspotIsItsTrianglesPointAndFront) {
    const Mesh mesh = make_default_product();
    const Primitive& primitive = mesh.primitives.at(0);
    const api::SurfaceSpot spot{0, 0, 3, {0.25, 0.25, 0.5}};
    glm::vec3 corners[3];
    for (int k = 0; k < 3; ++k) {
        corners[k] = primitive.positions[primitive.indices[9 + k]];
    }
    const glm::dvec3 point = 0.25 * glm::dvec3(corners[0]) + 0.25 * glm::dvec3(corners[1]) +
                             0.5 * glm::dvec3(corners[2]);
    const glm::dvec3 front = glm::normalize(
        glm::cross(glm::dvec3(corners[1] - corners[0]), glm::dvec3(corners[2] - corners[0])));
    const ScenePoint plain = api::surface_point(mesh, glm::mat4(1.0f), spot);
    EXPECT_LT(glm::length(plain.position - point), 1e-6);
    EXPECT_LT(glm::length(plain.normal - front), 1e-6);
    EXPECT_GT(glm::dot(plain.normal, glm::dvec3(primitive.normals[primitive.indices[9]])), 0.0)
        << "the winding's front is the side the vertex normals point to";

    const glm::mat4 mirror = glm::scale(glm::translate(glm::mat4(1.0f), {1, 2, 3}), {-1, 1, 1});
    const ScenePoint mirrored = api::surface_point(mesh, mirror, spot);
    EXPECT_LT(glm::length(mirrored.position - glm::dvec3(-point.x + 1, point.y + 2, point.z + 3)),
              1e-5);
    EXPECT_LT(glm::length(mirrored.normal - glm::dvec3(-front.x, front.y, front.z)), 1e-6);

    api::HotspotRequest request =
        api::parse_hotspot_json(with_hotspots(Json::array({kSurface, kPoint})).dump());
    const std::vector<std::shared_ptr<const Mesh>> meshes = {std::make_shared<const Mesh>(mesh)};
    EXPECT_EQ(api::hotspot_points(request, meshes, false).size(), 2u);
    std::get<api::SurfaceSpot>(request.hotspots[0].place).triangle = 1u << 30;
    try {
        api::hotspot_points(request, meshes, false);
        ADD_FAILURE() << "accepted";
    } catch (const api::InvalidParameter& error) {
        EXPECT_EQ(error.parameter(), "hotspots/0/triangle");
    }
    std::get<api::SurfaceSpot>(request.hotspots[0].place).primitive = 1000;
    try {
        api::hotspot_points(request, meshes, true);
        ADD_FAILURE() << "accepted";
    } catch (const api::InvalidParameter& error) {
        EXPECT_EQ(error.parameter(), "hotspot");
    }
}
