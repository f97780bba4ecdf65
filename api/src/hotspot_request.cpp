#include "oer/api/hotspot_request.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/parameter_text.hpp"
#include "render_members.hpp"
#include "request_values.hpp"

namespace oer::api {

using namespace request_values;

namespace {

constexpr std::string_view kHotspotMembers[] = {"name",        "object",   "primitive", "triangle",
                                                "barycentric", "position", "normal"};
constexpr std::size_t kMaxNameLength = 64;
// JSON values a hotspot holds at most: its object, its name and two vectors of four values.
constexpr std::size_t kValuesPerHotspot = 10;
// How far the weights' sum may be from 1: six digits of each weight, as a viewer saves them.
constexpr double kBarycentricSumTolerance = 1e-3;
// Indices beyond these are nonsense, not a mesh's.
constexpr long long kLargestIndex = 1LL << 40;

std::string checked_hotspot_name(const std::string& parameter, const std::string& name) {
    const bool allowed = !name.empty() && name.size() <= kMaxNameLength &&
                         std::all_of(name.begin(), name.end(), [](char c) {
                             return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                                    (c >= '0' && c <= '9') || c == '-' || c == '_';
                         });
    if (!allowed) {
        throw InvalidParameter(parameter,
                               "a hotspot's name is 1 to " + std::to_string(kMaxNameLength) +
                                   " letters, digits, '-' or '_', got '" + excerpt(name) + "'");
    }
    return name;
}

glm::dvec3 checked_barycentric(const std::string& parameter, const glm::dvec3& weights) {
    const double sum = weights.x + weights.y + weights.z;
    if (std::abs(sum - 1.0) > kBarycentricSumTolerance) {
        throw InvalidParameter(parameter,
                               "the three weights must sum to 1, got " + number_text(sum));
    }
    return weights / sum;
}

glm::dvec3 checked_normal(const std::string& parameter, const glm::dvec3& normal) {
    const double length = glm::length(normal);
    if (!(length > 1e-12)) {
        throw InvalidParameter(parameter, "a normal must not be of length 0");
    }
    return normal / length;
}

std::size_t json_index(const Json& value, const std::string& path) {
    return std::size_t(json_integer(value, path, 0, kLargestIndex));
}

HotspotSpec json_hotspot(const Json& value, const std::string& path) {
    require_object(value, path, kHotspotMembers);
    HotspotSpec hotspot;
    hotspot.name = checked_hotspot_name(
        child(path, "name"),
        json_string(reader().member(value, path, "name"), child(path, "name")));
    const bool surface = find(value, "object") || find(value, "triangle") ||
                         find(value, "barycentric") || find(value, "primitive");
    const bool point = find(value, "position") || find(value, "normal");
    if (surface == point) {
        reader().fail(path, surface ? "either a surface point (object, triangle, barycentric) or "
                                      "a position and normal, not both"
                                    : "needs a surface point (object, triangle, barycentric) or "
                                      "a position and normal");
    }
    if (surface) {
        SurfaceSpot spot;
        spot.object = json_index(reader().member(value, path, "object"), child(path, "object"));
        if (const Json* primitive = find(value, "primitive")) {
            spot.primitive = json_index(*primitive, child(path, "primitive"));
        }
        spot.triangle =
            json_index(reader().member(value, path, "triangle"), child(path, "triangle"));
        const std::string weights = child(path, "barycentric");
        spot.barycentric = checked_barycentric(
            weights, json_vector3(reader().member(value, path, "barycentric"), weights, kColor));
        hotspot.place = spot;
    } else {
        PointSpot spot;
        spot.position = json_vector3(reader().member(value, path, "position"),
                                     child(path, "position"), kCoordinate);
        const std::string normal = child(path, "normal");
        spot.normal = checked_normal(
            normal, json_vector3(reader().member(value, path, "normal"), normal, kCoordinate));
        hotspot.place = spot;
    }
    return hotspot;
}

// NAME:surface:OBJECT,PRIMITIVE,TRIANGLE,A,B,C or NAME:point:X,Y,Z,NX,NY,NZ
HotspotSpec query_hotspot(const std::string& text) {
    const std::string parameter = "hotspot";
    const std::size_t first = text.find(':');
    const std::size_t second = first == std::string::npos ? first : text.find(':', first + 1);
    if (second == std::string::npos) {
        throw InvalidParameter(parameter,
                               "expected NAME:surface:OBJECT,PRIMITIVE,TRIANGLE,A,B,C or "
                               "NAME:point:X,Y,Z,NX,NY,NZ, got '" +
                                   excerpt(text) + "'");
    }
    HotspotSpec hotspot;
    hotspot.name = checked_hotspot_name(parameter, text.substr(0, first));
    const std::string form = text.substr(first + 1, second - first - 1);
    const std::string numbers = text.substr(second + 1);
    std::vector<std::string> fields;
    for (std::size_t start = 0;;) {
        const std::size_t comma = numbers.find(',', start);
        fields.push_back(numbers.substr(start, comma - start));
        if (comma == std::string::npos) {
            break;
        }
        start = comma + 1;
    }
    if ((form != "surface" && form != "point") || fields.size() != 6) {
        throw InvalidParameter(parameter,
                               "expected NAME:surface: and six numbers, or NAME:point: and six "
                               "numbers, got '" +
                                   excerpt(text) + "'");
    }
    const auto number = [&](std::size_t i, Range range) {
        return parse_number(parameter, fields[i], range.low, range.high);
    };
    if (form == "surface") {
        SurfaceSpot spot;
        const auto index = [&](std::size_t i) {
            return std::size_t(parse_integer(parameter, fields[i], 0, kLargestIndex));
        };
        spot.object = index(0);
        spot.primitive = index(1);
        spot.triangle = index(2);
        spot.barycentric = checked_barycentric(
            parameter, {number(3, kColor), number(4, kColor), number(5, kColor)});
        hotspot.place = spot;
    } else {
        PointSpot spot;
        spot.position = {number(0, kCoordinate), number(1, kCoordinate), number(2, kCoordinate)};
        spot.normal = checked_normal(
            parameter, {number(3, kCoordinate), number(4, kCoordinate), number(5, kCoordinate)});
        hotspot.place = spot;
    }
    return hotspot;
}

// Names unique, and surface hotspots on the request's objects.
void check_hotspots(const HotspotRequest& request, bool query_form) {
    std::set<std::string> names;
    for (std::size_t i = 0; i < request.hotspots.size(); ++i) {
        const HotspotSpec& hotspot = request.hotspots[i];
        const std::string path = "hotspots/" + std::to_string(i);
        if (!names.insert(hotspot.name).second) {
            throw InvalidParameter(query_form ? "hotspot" : path + "/name",
                                   "the name '" + hotspot.name + "' is given twice");
        }
        if (const auto* spot = std::get_if<SurfaceSpot>(&hotspot.place);
            spot && spot->object >= request.render.objects.size()) {
            throw InvalidParameter(query_form ? "hotspot" : path + "/object",
                                   "object " + std::to_string(spot->object) + " of a request of " +
                                       std::to_string(request.render.objects.size()) + " objects");
        }
    }
}

void check_hotspot_count(const std::string& parameter, std::size_t count,
                         const RenderLimits& limits) {
    if (count > limits.max_hotspots) {
        throw InvalidParameter(parameter,
                               "at most " + std::to_string(limits.max_hotspots) +
                                   " hotspots a request, got " + std::to_string(count),
                               ErrorKind::LimitExceeded);
    }
}

// The body's own required member `name` taken out of it, so that the render's members are
// left for the render request's reader.
Json take_member(Json& body, const char* name) {
    reader().object(body, "body");
    reader().member(body, "", name);
    const auto it = body.find(name);
    Json member = std::move(*it);
    body.erase(it);
    return member;
}

// The render request of a query that carries its own parameter `own` beside the render's.
RenderSpec render_query_beside(const RenderQuery& query, const char* own,
                               const RenderLimits& limits) {
    RenderQuery render_query = query;
    render_query.erase(own);
    return parse_render_query(render_query, limits);
}

// "x,y" inside the frame: the pick's pixel, in either form, named `parameter`.
glm::dvec2 checked_pixel(const std::string& parameter, const glm::dvec2& pixel,
                         const RenderSpec& render) {
    if (pixel.x >= render.width || pixel.y >= render.height) {
        throw InvalidParameter(parameter, "must lie inside the " + std::to_string(render.width) +
                                              "x" + std::to_string(render.height) + " frame");
    }
    return pixel;
}

}  // namespace

HotspotRequest parse_hotspot_json(std::string_view body, const RenderLimits& limits) {
    Json document =
        render_members::read_render_body(body, limits, 2 + kValuesPerHotspot * limits.max_hotspots);
    const Json hotspots = take_member(document, "hotspots");
    HotspotRequest request;
    render_members::read_body_members(request.render, document, limits);
    reader().array(hotspots, "hotspots");
    check_hotspot_count("hotspots", hotspots.size(), limits);
    for (std::size_t i = 0; i < hotspots.size(); ++i) {
        request.hotspots.push_back(json_hotspot(hotspots[i], child("hotspots", i)));
    }
    check_hotspots(request, false);
    return request;
}

HotspotRequest parse_hotspot_query(const RenderQuery& query, const RenderLimits& limits) {
    HotspotRequest request;
    request.render = render_query_beside(query, "hotspot", limits);
    const auto [first, last] = query.equal_range("hotspot");
    check_hotspot_count("hotspot", std::size_t(std::distance(first, last)), limits);
    for (auto it = first; it != last; ++it) {
        request.hotspots.push_back(query_hotspot(it->second));
    }
    check_hotspots(request, true);
    return request;
}

PickRequest parse_pick_json(std::string_view body, const RenderLimits& limits) {
    Json document = render_members::read_render_body(body, limits, 3);
    const Json pixel = take_member(document, "pixel");
    PickRequest request;
    render_members::read_body_members(request.render, document, limits);
    if (!pixel.is_array() || pixel.size() != 2) {
        reader().fail("pixel", "expected [x, y], the image position in pixels");
    }
    request.pixel =
        checked_pixel("pixel",
                      {json_number(pixel[0], "pixel/0", {0.0, double(request.render.width)}),
                       json_number(pixel[1], "pixel/1", {0.0, double(request.render.height)})},
                      request.render);
    return request;
}

PickRequest parse_pick_query(const RenderQuery& query, const RenderLimits& limits) {
    PickRequest request;
    request.render = render_query_beside(query, "pixel", limits);
    const auto [first, last] = query.equal_range("pixel");
    if (first == last) {
        throw InvalidParameter("pixel", "required");
    }
    if (std::next(first) != last) {
        throw InvalidParameter("pixel", "given more than once");
    }
    const std::size_t comma = first->second.find(',');
    if (comma == std::string::npos) {
        throw InvalidParameter("pixel", "expected x,y, the image position in pixels, got '" +
                                            excerpt(first->second) + "'");
    }
    request.pixel = checked_pixel(
        "pixel",
        {parse_number("pixel", first->second.substr(0, comma), 0.0, request.render.width),
         parse_number("pixel", first->second.substr(comma + 1), 0.0, request.render.height)},
        request.render);
    return request;
}

ScenePoint surface_point(const Mesh& mesh, const glm::mat4& transform, const SurfaceSpot& spot) {
    const Primitive& primitive = mesh.primitives.at(spot.primitive);
    const glm::dmat4 model(transform);
    glm::dvec3 corners[3];
    glm::dvec3 vertex_normal{0.0};
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t vertex = primitive.indices.at(3 * spot.triangle + std::size_t(k));
        corners[k] =
            glm::dvec3(model * glm::dvec4(glm::dvec3(primitive.positions.at(vertex)), 1.0));
        if (vertex < primitive.normals.size()) {
            vertex_normal += spot.barycentric[k] * glm::dvec3(primitive.normals[vertex]);
        }
    }
    ScenePoint point;
    point.position = spot.barycentric.x * corners[0] + spot.barycentric.y * corners[1] +
                     spot.barycentric.z * corners[2];
    // A mirroring transform turns the winding around, as the renderer's front faces do.
    const double side = glm::determinant(glm::dmat3(model)) < 0.0 ? -1.0 : 1.0;
    glm::dvec3 normal = side * glm::cross(corners[1] - corners[0], corners[2] - corners[0]);
    if (!(glm::length(normal) > 0.0)) {
        normal = glm::transpose(glm::inverse(glm::dmat3(model))) * vertex_normal;
    }
    const double length = glm::length(normal);
    point.normal = length > 0.0 ? normal / length : glm::dvec3(0.0);
    return point;
}

std::vector<ScenePoint> hotspot_points(const HotspotRequest& request,
                                       const std::vector<std::shared_ptr<const Mesh>>& meshes,
                                       bool query_form) {
    std::vector<ScenePoint> points;
    for (std::size_t i = 0; i < request.hotspots.size(); ++i) {
        const HotspotSpec& hotspot = request.hotspots[i];
        if (const auto* point = std::get_if<PointSpot>(&hotspot.place)) {
            points.push_back({point->position, point->normal});
            continue;
        }
        const SurfaceSpot& spot = std::get<SurfaceSpot>(hotspot.place);
        const Mesh& mesh = *meshes.at(spot.object);
        const auto named = [&](const char* member) {
            return query_form ? std::string("hotspot")
                              : "hotspots/" + std::to_string(i) + "/" + member;
        };
        if (spot.primitive >= mesh.primitives.size()) {
            throw InvalidParameter(named("primitive"),
                                   "primitive " + std::to_string(spot.primitive) +
                                       " of a mesh of " + std::to_string(mesh.primitives.size()) +
                                       " primitives");
        }
        const std::size_t triangles = mesh.primitives[spot.primitive].indices.size() / 3;
        if (spot.triangle >= triangles) {
            throw InvalidParameter(named("triangle"), "triangle " + std::to_string(spot.triangle) +
                                                          " of a primitive of " +
                                                          std::to_string(triangles) + " triangles");
        }
        points.push_back(
            surface_point(mesh, glm::mat4(request.render.objects.at(spot.object).transform), spot));
    }
    return points;
}

}  // namespace oer::api
