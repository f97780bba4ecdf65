#pragma once
// The request's surfaces in an Embree 3 scene (Intel's Embree:
// rtcNewDevice, rtcNewScene, one RTC_GEOMETRY_TYPE_TRIANGLE geometry per primitive, committed
// once, then rtcIntersect1 / rtcOccluded1 from any number of threads): every object's
// primitives in world space, and the renderer's ground plane. A hit is resolved to what
// shading needs (position, normals and the renderer's albedo there) and to where it lies on the
// request's meshes (object, primitive, triangle and barycentrics), so that per-vertex data baked
// for the request (renderer/transfer) can be interpolated there. Public for that bake: the
// reference renderer and the transfer bake trace the same surfaces and the same finite ground.
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "oer/mesh/camera.hpp"
#include "oer/reference/metallic_roughness_brdf.hpp"
#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_bounds.hpp"

namespace oer::reference {

struct SurfaceHit {
    glm::dvec3 position{0.0};
    glm::dvec3 geometric_normal{0.0};  // unit, either side
    // Unit, on the side the ray came from; the material's normal texture applied.
    glm::dvec3 shading_normal{0.0};
    // The material there (base colour: the factor times the texture, sRGB decoded, times
    // COLOR_0, or the request's base colour; metallic and roughness: the factors times the
    // texture), a Lambertian albedo of 0.8 on the ground (docs/design.md section 7).
    SurfaceMaterial material;
    glm::dvec3 emissive{0.0};  // factor times KHR_materials_emissive_strength times texture
    // KHR_materials_unlit: the base colour is the radiance it sends, whatever the light, as the
    // rasteriser's shade_object returns it (the transfer bake still reflects its base colour).
    bool unlit = false;
    bool ground = false;
    // Where on the request's meshes (not set on the ground): request.objects[object], its
    // mesh's primitives[primitive], the triangle's index in that primitive's index list
    // (corners indices[3 triangle + 0..2]) and Embree's barycentrics, u and v the weights of
    // the second and third corner (1 - u - v the first's).
    std::size_t object = 0;
    std::size_t primitive = 0;
    unsigned triangle = 0;
    double u = 0.0;
    double v = 0.0;
};

// How far the ground plane reaches for a ray: as drawn (the renderer's square, for the rays of
// the camera), or infinite (for rays that leave a surface towards a light or the map: above an
// infinite plane every direction below the horizon sees the plane, never the map, docs/design.md
// section 2, and the square's edge is only where the picture stops).
enum class GroundReach { Drawn, Infinite };

// How a scene with the ground traces it: the drawn square in the Embree scene and the infinite
// plane beyond it (both reaches), or the infinite plane alone (GroundReach::Infinite only), found
// only where a ray meets no object, so that a face of an object lying on the plane, or a ray
// that starts on it, meets the object and not the plane.
enum class GroundTracing { SquareAndPlane, PlaneOnly };

class EmbreeScene {
  public:
    // Throws oer::Error (Internal) when Embree fails, with its message.
    // frame: the scene's bounds as the GL renderer has them (oer/scene/scene_bounds.hpp), whose
    // ground plane (y = the box's lowest y, half side ground_half_size()) the reference traces too.
    EmbreeScene(const FrameRequest& request, const SceneBounds& frame,
                GroundTracing ground_tracing = GroundTracing::SquareAndPlane);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // The nearest surface along the ray beyond t_near, if any.
    std::optional<SurfaceHit> intersect(const glm::dvec3& origin, const glm::dvec3& direction,
                                        double t_near, GroundReach reach) const;
    // Whether anything lies along the ray beyond t_near (to infinity).
    bool occluded(const glm::dvec3& origin, const glm::dvec3& direction, double t_near,
                  GroundReach reach) const;

  private:
    // A material's use of a texture on one primitive (mesh.hpp's TextureReference).
    struct TextureLookup {
        const Texture* texture = nullptr;
        int set = 0;  // TEXCOORD_0 or TEXCOORD_1
        glm::mat3 uv_transform{1.0f};
        TextureSampler sampler;
    };
    struct Geometry {
        std::vector<glm::vec3> positions;  // world space
        std::vector<glm::vec3> normals;    // world space, unit
        std::vector<glm::vec4> tangents;   // world space, w the bitangent's sign; with a normal map
        std::vector<glm::vec2> texcoords[2];  // empty where no texture reads the set
        // COLOR_0, multiplying the base colour and alpha (only the alpha under the request's
        // base colour, which replaces the RGB, as it does the texture's); empty without them.
        std::vector<glm::vec4> colors;
        std::vector<std::uint32_t> indices;
        glm::dvec4 base_color{1.0};
        bool keep_texture_color = true;  // false under the request's base colour
        TextureLookup base_texture, metallic_roughness_texture, normal_texture, emissive_texture;
        bool glossy = false;
        bool unlit = false;  // KHR_materials_unlit
        double metallic = 0.0, roughness = 1.0, normal_scale = 1.0;
        glm::dvec3 emissive{0.0};
        AlphaMode alpha_mode = AlphaMode::Opaque;
        double alpha_cutoff = 0.5;
        bool ground = false;
        std::size_t object = 0;     // index in request.objects (not for the ground)
        std::size_t primitive = 0;  // index in that object's mesh's primitives
    };
    struct Corners;  // a triangle's vertex indices and barycentric weights
    glm::dvec2 uv_at(const Geometry& geometry, const TextureLookup& lookup,
                     const Corners& corners) const;
    glm::dvec4 sample(const Geometry& geometry, const TextureLookup& lookup,
                      const Corners& corners) const;
    glm::dvec4 base_color_at(const Geometry& geometry, const Corners& corners) const;
    // Whether a hit on a masked or blended surface lets the ray through (Embree's filters).
    static void filter_alpha(const RTCFilterFunctionNArguments* arguments);

    void add(Geometry geometry);

    // Whether a ray from origin along direction meets the infinite ground plane beyond the drawn
    // square: it goes down from above the plane.
    bool reaches_infinite_ground(const glm::dvec3& origin, const glm::dvec3& direction,
                                 GroundReach reach) const;

    std::optional<double> ground_height_;  // the plane's y, when the request has the ground
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<Geometry> geometries_;  // by Embree geometry id
};

}  // namespace oer::reference
