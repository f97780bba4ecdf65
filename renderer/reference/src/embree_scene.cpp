#include "oer/reference/embree_scene.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "oer/core/error.hpp"
#include "oer/reference/pixel_random.hpp"

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

// A texel coordinate wrapped as the sampler says (glTF 2.0 section 5.26).
long long wrap(long long t, long long size, TextureWrap mode) {
    switch (mode) {
        case TextureWrap::ClampToEdge:
            return std::clamp(t, 0LL, size - 1);
        case TextureWrap::MirroredRepeat: {
            const long long period = 2 * size, m = (t % period + period) % period;
            return m < size ? m : period - 1 - m;
        }
        case TextureWrap::Repeat:
            break;
    }
    return (t % size + size) % size;
}

// Bilinear (the renderer's filtering at its finest level) under the sampler's wrap modes, the
// texels decoded as the texture's encoding says (sRGB for colour, linear for data).
glm::dvec4 sample_texture(const Texture& texture, const TextureSampler& sampler, glm::dvec2 uv) {
    const double x = uv.x * texture.width - 0.5, y = uv.y * texture.height - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const auto texel = [&](long long tx, long long ty) {
        const std::size_t i = std::size_t(wrap(ty, texture.height, sampler.wrap_t) * texture.width +
                                          wrap(tx, texture.width, sampler.wrap_s)) *
                              4;
        const auto channel = [&](std::size_t c) {
            return texture.encoding == TextureEncoding::Srgb ? srgb_decode(texture.rgba[i + c])
                                                             : texture.rgba[i + c] / 255.0;
        };
        return glm::dvec4(channel(0), channel(1), channel(2), texture.rgba[i + 3] / 255.0);
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

struct EmbreeScene::Corners {
    const std::uint32_t* index;  // the triangle's three vertex indices
    double weight[3];            // 1 - u - v, u, v

    Corners(const Geometry& geometry, unsigned triangle, double u, double v)
        : index(&geometry.indices[3 * std::size_t(triangle)]), weight{1.0 - u - v, u, v} {}

    template <typename Vector>
    auto interpolate(const std::vector<Vector>& values) const {
        using Double = glm::vec<Vector::length(), double>;
        return weight[0] * Double(values[index[0]]) + weight[1] * Double(values[index[1]]) +
               weight[2] * Double(values[index[2]]);
    }
};

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
        const glm::mat3 linear(object.transform);
        const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
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
            geometry.texcoords[0] = primitive.texcoords;
            geometry.texcoords[1] = primitive.texcoords1;
            geometry.colors = primitive.colors;
            const auto lookup = [&mesh](const TextureReference& reference) {
                TextureLookup result;
                if (reference.present()) {
                    result.texture = &mesh.textures.at(std::size_t(reference.texture));
                    result.set = reference.texcoord;
                    result.uv_transform = reference.uv_transform();
                    result.sampler = reference.sampler;
                }
                return result;
            };
            // The geometry pass's base colour: the request's colour replaces the material's
            // factor and the RGB of its texture and vertex colours, whose alpha stays.
            geometry.base_color = glm::dvec4(material.base_color);
            if (const std::optional<glm::vec3> colour = base_color_override(object, material)) {
                geometry.base_color = glm::dvec4(glm::dvec3(*colour), material.base_color.a);
                geometry.keep_texture_color = false;
            }
            geometry.base_texture = lookup(material.base_color_texture);
            geometry.glossy = material.glossy();
            geometry.unlit = material.model == ShadingModel::Unlit;
            geometry.metallic = material.metallic;
            geometry.roughness = material.roughness;
            if (geometry.glossy) {
                geometry.metallic_roughness_texture = lookup(material.metallic_roughness_texture);
            }
            geometry.normal_texture = lookup(material.normal_texture);
            geometry.normal_scale = material.normal_scale;
            if (geometry.normal_texture.texture != nullptr) {
                for (const glm::vec4& tangent : primitive.tangents) {
                    geometry.tangents.emplace_back(glm::normalize(linear * glm::vec3(tangent)),
                                                   tangent.w);
                }
            }
            geometry.emissive = glm::dvec3(material.emissive) * double(material.emissive_strength);
            geometry.emissive_texture = lookup(material.emissive_texture);
            geometry.alpha_mode = material.alpha_mode;
            geometry.alpha_cutoff = material.alpha_cutoff;
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
        ground.base_color = glm::dvec4(glm::dvec3(kGroundAlbedo), 1.0);
        ground.ground = true;
        add(std::move(ground));
    }
    // The filters read their geometry through its user pointer: set once every geometry has
    // its final place in geometries_.
    for (std::size_t id = 0; id < geometries_.size(); ++id) {
        if (geometries_[id].alpha_mode == AlphaMode::Opaque) {
            continue;
        }
        RTCGeometry geometry = rtcGetGeometry(scene_, unsigned(id));
        rtcSetGeometryUserData(geometry, this);
        rtcSetGeometryIntersectFilterFunction(geometry, &EmbreeScene::filter_alpha);
        rtcSetGeometryOccludedFilterFunction(geometry, &EmbreeScene::filter_alpha);
        rtcCommitGeometry(geometry);
    }
    check_embree(device_, "rtcSetGeometryIntersectFilterFunction");
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

glm::dvec2 EmbreeScene::uv_at(const Geometry& geometry, const TextureLookup& lookup,
                              const Corners& corners) const {
    const std::vector<glm::vec2>& texcoords = geometry.texcoords[lookup.set];
    if (texcoords.empty()) {
        return glm::dvec2(0.0);
    }
    return glm::dvec2(glm::dmat3(lookup.uv_transform) *
                      glm::dvec3(corners.interpolate(texcoords), 1.0));
}

glm::dvec4 EmbreeScene::sample(const Geometry& geometry, const TextureLookup& lookup,
                               const Corners& corners) const {
    return sample_texture(*lookup.texture, lookup.sampler, uv_at(geometry, lookup, corners));
}

glm::dvec4 EmbreeScene::base_color_at(const Geometry& geometry, const Corners& corners) const {
    glm::dvec4 base = geometry.base_color;
    const double keep = geometry.keep_texture_color ? 1.0 : 0.0;
    if (geometry.base_texture.texture != nullptr) {
        const glm::dvec4 texel = sample(geometry, geometry.base_texture, corners);
        base *= glm::dvec4(glm::mix(glm::dvec3(1.0), glm::dvec3(texel), keep), texel.a);
    }
    if (!geometry.colors.empty()) {
        const glm::dvec4 color = corners.interpolate(geometry.colors);
        base *= glm::dvec4(glm::mix(glm::dvec3(1.0), glm::dvec3(color), keep), color.a);
    }
    return base;
}

void EmbreeScene::filter_alpha(const RTCFilterFunctionNArguments* arguments) {
    const auto& scene = *static_cast<const EmbreeScene*>(arguments->geometryUserPtr);
    for (unsigned i = 0; i < arguments->N; ++i) {
        if (arguments->valid[i] == 0) {
            continue;
        }
        const unsigned geometry_id = RTCHitN_geomID(arguments->hit, arguments->N, i);
        const Geometry& geometry = scene.geometries_[geometry_id];
        const unsigned triangle = RTCHitN_primID(arguments->hit, arguments->N, i);
        const float u = RTCHitN_u(arguments->hit, arguments->N, i);
        const float v = RTCHitN_v(arguments->hit, arguments->N, i);
        const double alpha = scene.base_color_at(geometry, Corners(geometry, triangle, u, v)).a;
        bool through = false;
        if (geometry.alpha_mode == AlphaMode::Mask) {
            through = alpha < geometry.alpha_cutoff;
        } else {
            // The coin: the ray's origin and direction and the hit's place, hashed.
            std::uint64_t key = splitmix64(std::uint64_t(geometry_id) << 32 | triangle);
            for (const float value : {u, v, RTCRayN_org_x(arguments->ray, arguments->N, i),
                                      RTCRayN_org_y(arguments->ray, arguments->N, i),
                                      RTCRayN_org_z(arguments->ray, arguments->N, i),
                                      RTCRayN_dir_x(arguments->ray, arguments->N, i),
                                      RTCRayN_dir_y(arguments->ray, arguments->N, i),
                                      RTCRayN_dir_z(arguments->ray, arguments->N, i)}) {
                key = splitmix64(key ^ std::bit_cast<std::uint32_t>(value));
            }
            through = double(key >> 11) * 0x1p-53 >= alpha;
        }
        if (through) {
            arguments->valid[i] = 0;
        }
    }
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
        hit.material.base_color = glm::dvec3(kGroundAlbedo);
        hit.ground = true;
        return hit;
    }
    const Geometry& geometry = geometries_[ray_hit.hit.geomID];
    const unsigned triangle = ray_hit.hit.primID;
    const double u = ray_hit.hit.u, v = ray_hit.hit.v;
    const Corners corners(geometry, triangle, u, v);
    SurfaceHit hit;
    hit.position = origin + double(ray_hit.ray.tfar) * direction;
    const glm::dvec3 p0(geometry.positions[corners.index[0]]),
        p1(geometry.positions[corners.index[1]]), p2(geometry.positions[corners.index[2]]);
    hit.geometric_normal = glm::normalize(glm::cross(p1 - p0, p2 - p0));
    // Interpolated as the rasteriser interpolates its vertex normals (Embree's u and v are the
    // weights of the second and third vertex), on the side of the surface the ray came from,
    // the normal texture applied in the tangent frame (glTF 2.0 section 3.7.2.1, as
    // material.glsl: t made orthogonal to n, b = w cross(n, t), the map's xy times its scale).
    glm::dvec3 n = glm::normalize(corners.interpolate(geometry.normals));
    const bool flip = glm::dot(n, direction) > 0.0;
    if (geometry.normal_texture.texture != nullptr && !geometry.tangents.empty()) {
        const glm::dvec4 tangent = corners.interpolate(geometry.tangents);
        glm::dvec3 t = glm::dvec3(tangent) - n * glm::dot(n, glm::dvec3(tangent));
        if (glm::dot(t, t) > 1e-12) {
            t = glm::normalize(t);
            const glm::dvec3 b = (tangent.w < 0.0 ? -1.0 : 1.0) * glm::cross(n, t);
            glm::dvec3 mapped =
                glm::dvec3(sample(geometry, geometry.normal_texture, corners)) * 2.0 - 1.0;
            mapped.x *= geometry.normal_scale;
            mapped.y *= geometry.normal_scale;
            n = glm::normalize(t * mapped.x + b * mapped.y + n * mapped.z);
        }
    }
    hit.shading_normal = flip ? -n : n;
    hit.material.base_color = glm::dvec3(base_color_at(geometry, corners));
    hit.material.glossy = geometry.glossy;
    hit.material.metallic = geometry.metallic;
    hit.material.roughness = geometry.roughness;
    if (geometry.metallic_roughness_texture.texture != nullptr) {
        const glm::dvec4 texel = sample(geometry, geometry.metallic_roughness_texture, corners);
        hit.material.roughness *= texel.g;
        hit.material.metallic *= texel.b;
    }
    hit.emissive = geometry.emissive;
    if (geometry.emissive_texture.texture != nullptr) {
        hit.emissive *= glm::dvec3(sample(geometry, geometry.emissive_texture, corners));
    }
    hit.unlit = geometry.unlit;
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
