#include "oer/reference/embree_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "oer/core/error.hpp"

namespace oer::reference {

namespace {

void check_embree(RTCDevice device, const char* what) {
    const RTCError error = rtcGetDeviceError(device);
    if (error != RTC_ERROR_NONE) {
        throw Error(ErrorKind::Internal, std::string("reference: Embree failed in ") + what +
                                             " (RTCError " + std::to_string(int(error)) + ")");
    }
}

// sRGB to linear (IEC 61966-2-1), as GL_SRGB8_ALPHA8 decodes the renderer's textures.
double srgb_decode(std::uint8_t value) {
    const double c = value / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// Bilinear, repeating at the edges (glTF's default sampler), of linear texels: the renderer's
// filtering at its finest level.
glm::dvec3 sample_texture(const Texture& texture, glm::dvec2 uv) {
    const double x = uv.x * texture.width - 0.5, y = uv.y * texture.height - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const auto texel = [&texture](long long tx, long long ty) {
        const long long w = texture.width, h = texture.height;
        const std::size_t i = std::size_t(((ty % h + h) % h) * w + ((tx % w + w) % w)) * 4;
        return glm::dvec3(srgb_decode(texture.rgba[i]), srgb_decode(texture.rgba[i + 1]),
                          srgb_decode(texture.rgba[i + 2]));
    };
    const long long ix = (long long)x0, iy = (long long)y0;
    return (1 - fy) * ((1 - fx) * texel(ix, iy) + fx * texel(ix + 1, iy)) +
           fy * ((1 - fx) * texel(ix, iy + 1) + fx * texel(ix + 1, iy + 1));
}

RTCRay make_ray(const glm::dvec3& origin, const glm::dvec3& direction, double t_near) {
    RTCRay ray{};
    ray.org_x = float(origin.x);
    ray.org_y = float(origin.y);
    ray.org_z = float(origin.z);
    ray.dir_x = float(direction.x);
    ray.dir_y = float(direction.y);
    ray.dir_z = float(direction.z);
    ray.tnear = float(t_near);
    ray.tfar = std::numeric_limits<float>::infinity();
    ray.mask = std::numeric_limits<unsigned>::max();
    ray.flags = 0;
    return ray;
}

}  // namespace

EmbreeScene::EmbreeScene(const FrameRequest& request, const SceneBounds& frame,
                         GroundTracing ground_tracing) {
    device_ = rtcNewDevice(nullptr);
    if (device_ == nullptr) {
        throw Error(ErrorKind::Internal, "reference: rtcNewDevice failed (RTCError " +
                                             std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    }
    scene_ = rtcNewScene(device_);
    check_embree(device_, "rtcNewScene");
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    for (std::size_t o = 0; o < request.objects.size(); ++o) {
        const SceneObject& object = request.objects[o];
        const Mesh& mesh = *object.mesh;
        const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(object.transform)));
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            const Primitive& primitive = mesh.primitives[p];
            const Material& material =
                mesh.materials.at(std::size_t(primitive.material_under(object.variant)));
            Geometry geometry;
            geometry.object = o;
            geometry.primitive = p;
            for (std::size_t i = 0; i < primitive.positions.size(); ++i) {
                geometry.positions.push_back(
                    glm::vec3(object.transform * glm::vec4(primitive.positions[i], 1.0f)));
                geometry.normals.push_back(glm::normalize(normal_matrix * primitive.normals[i]));
            }
            geometry.indices = primitive.indices;
            // The geometry pass's albedo: the request's base colour replaces the material's
            // factor, texture and vertex colours; otherwise the factor times the texture (sRGB
            // decoded) times the vertex colour (COLOR_0).
            if (const std::optional<glm::vec3> colour = base_color_override(object, material)) {
                geometry.base_color = glm::dvec3(*colour);
            } else {
                geometry.base_color = glm::dvec3(glm::vec3(material.base_color));
                if (material.base_color_texture.present()) {
                    geometry.texture =
                        &mesh.textures.at(std::size_t(material.base_color_texture.texture));
                    geometry.texcoords = material.base_color_texture.texcoord == 1
                                             ? primitive.texcoords1
                                             : primitive.texcoords;
                }
                geometry.colors = primitive.colors;
            }
            add(std::move(geometry));
        }
    }
    if (request.ground) {
        ground_height_ = double(frame.box.min.y);
    }
    if (request.ground && ground_tracing == GroundTracing::SquareAndPlane) {
        // The renderer's unit ground (renderer_state.cpp), albedo 0.8 (docs/design.md section 7).
        Geometry ground;
        const float h = frame.ground_half_size(), y = frame.box.min.y;
        const glm::vec3 c = frame.centre;
        ground.positions = {{c.x - h, y, c.z + h},
                            {c.x + h, y, c.z + h},
                            {c.x + h, y, c.z - h},
                            {c.x - h, y, c.z - h}};
        ground.normals.assign(4, {0.0f, 1.0f, 0.0f});
        ground.indices = {0, 1, 2, 0, 2, 3};
        ground.base_color = glm::dvec3(kGroundAlbedo);
        ground.ground = true;
        add(std::move(ground));
    }
    rtcCommitScene(scene_);
    check_embree(device_, "rtcCommitScene");
}

EmbreeScene::~EmbreeScene() {
    if (scene_ != nullptr) {
        rtcReleaseScene(scene_);
    }
    rtcReleaseDevice(device_);
}

void EmbreeScene::add(Geometry geometry) {
    RTCGeometry triangles = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    check_embree(device_, "rtcNewGeometry");
    // Embree reads vertices with 16-byte loads: the buffer it allocates carries the padding.
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(triangles, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), geometry.positions.size()));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(triangles, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), geometry.indices.size() / 3));
    check_embree(device_, "rtcSetNewGeometryBuffer");
    for (std::size_t i = 0; i < geometry.positions.size(); ++i) {
        vertices[3 * i] = geometry.positions[i].x;
        vertices[3 * i + 1] = geometry.positions[i].y;
        vertices[3 * i + 2] = geometry.positions[i].z;
    }
    std::copy(geometry.indices.begin(), geometry.indices.end(), indices);
    rtcCommitGeometry(triangles);
    const unsigned id = rtcAttachGeometry(scene_, triangles);
    rtcReleaseGeometry(triangles);
    check_embree(device_, "rtcAttachGeometry");
    if (id != geometries_.size()) {
        throw Error(ErrorKind::Internal, "reference: Embree gave geometry id " +
                                             std::to_string(id) + ", expected " +
                                             std::to_string(geometries_.size()));
    }
    geometries_.push_back(std::move(geometry));
}

glm::dvec3 EmbreeScene::albedo_at(const Geometry& geometry, unsigned triangle, double u,
                                  double v) const {
    if (geometry.texture == nullptr && geometry.colors.empty()) {
        return geometry.base_color;
    }
    const std::uint32_t* corner = &geometry.indices[3 * std::size_t(triangle)];
    glm::dvec3 albedo = geometry.base_color;
    if (geometry.texture != nullptr) {
        const glm::dvec2 uv = (1.0 - u - v) * glm::dvec2(geometry.texcoords[corner[0]]) +
                              u * glm::dvec2(geometry.texcoords[corner[1]]) +
                              v * glm::dvec2(geometry.texcoords[corner[2]]);
        albedo *= sample_texture(*geometry.texture, uv);
    }
    if (!geometry.colors.empty()) {
        const glm::dvec3 color = (1.0 - u - v) * glm::dvec3(geometry.colors[corner[0]]) +
                                 u * glm::dvec3(geometry.colors[corner[1]]) +
                                 v * glm::dvec3(geometry.colors[corner[2]]);
        albedo *= color;
    }
    return albedo;
}

bool EmbreeScene::reaches_infinite_ground(const glm::dvec3& origin, const glm::dvec3& direction,
                                          GroundReach reach) const {
    return reach == GroundReach::Infinite && ground_height_ && direction.y < 0.0 &&
           origin.y > *ground_height_;
}

std::optional<SurfaceHit> EmbreeScene::intersect(const glm::dvec3& origin,
                                                 const glm::dvec3& direction, double t_near,
                                                 GroundReach reach) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit ray_hit{};
    ray_hit.ray = make_ray(origin, direction, t_near);
    ray_hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    ray_hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &ray_hit);
    if (ray_hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        if (!reaches_infinite_ground(origin, direction, reach)) {
            return std::nullopt;
        }
        // Beyond the drawn square, the plane it belongs to.
        SurfaceHit hit;
        hit.position = origin + (*ground_height_ - origin.y) / direction.y * direction;
        hit.geometric_normal = hit.shading_normal = {0.0, 1.0, 0.0};
        hit.albedo = glm::dvec3(kGroundAlbedo);
        hit.ground = true;
        return hit;
    }
    const Geometry& geometry = geometries_[ray_hit.hit.geomID];
    const unsigned triangle = ray_hit.hit.primID;
    const double u = ray_hit.hit.u, v = ray_hit.hit.v;
    const std::uint32_t* corner = &geometry.indices[3 * std::size_t(triangle)];
    SurfaceHit hit;
    hit.position = origin + double(ray_hit.ray.tfar) * direction;
    const glm::dvec3 p0(geometry.positions[corner[0]]), p1(geometry.positions[corner[1]]),
        p2(geometry.positions[corner[2]]);
    hit.geometric_normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    // Interpolated as the rasteriser interpolates its vertex normals (Embree's u and v are the
    // weights of the second and third vertex), on the side of the surface the ray came from.
    glm::dvec3 n = (1.0 - u - v) * glm::dvec3(geometry.normals[corner[0]]) +
                   u * glm::dvec3(geometry.normals[corner[1]]) +
                   v * glm::dvec3(geometry.normals[corner[2]]);
    n = glm::normalize(n);
    if (glm::dot(n, direction) > 0.0) {
        n = -n;
    }
    hit.shading_normal = n;
    hit.albedo = albedo_at(geometry, triangle, u, v);
    hit.ground = geometry.ground;
    hit.object = geometry.object;
    hit.primitive = geometry.primitive;
    hit.triangle = triangle;
    hit.u = u;
    hit.v = v;
    return hit;
}

bool EmbreeScene::occluded(const glm::dvec3& origin, const glm::dvec3& direction, double t_near,
                           GroundReach reach) const {
    if (reaches_infinite_ground(origin, direction, reach)) {
        return true;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray = make_ray(origin, direction, t_near);
    rtcOccluded1(scene_, &context, &ray);
    // rtcOccluded1 sets tfar to -infinity when it finds a hit.
    return ray.tfar < 0.0f;
}

}  // namespace oer::reference
