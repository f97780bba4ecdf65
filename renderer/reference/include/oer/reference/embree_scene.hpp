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
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "oer/mesh/camera.hpp"
#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_bounds.hpp"

namespace oer::reference {

struct SurfaceHit {
    glm::dvec3 position{0.0};
    glm::dvec3 geometric_normal{0.0};  // unit, either side
    glm::dvec3 shading_normal{0.0};    // unit, on the side the ray came from
    glm::dvec3 albedo{0.0};
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
    struct Geometry {
        std::vector<glm::vec3> positions;  // world space
        std::vector<glm::vec3> normals;    // world space, unit
        std::vector<glm::vec2> texcoords;  // empty without a texture
        // COLOR_0, multiplying the albedo; empty without vertex colours or with the object's
        // base colour (which replaces them, as it does the texture).
        std::vector<glm::vec4> colors;
        std::vector<std::uint32_t> indices;
        glm::dvec3 base_color{1.0};
        const Texture* texture = nullptr;  // the base-color texture, sRGB
        bool ground = false;
        std::size_t object = 0;     // index in request.objects (not for the ground)
        std::size_t primitive = 0;  // index in that object's mesh's primitives
    };
    void add(Geometry geometry);
    glm::dvec3 albedo_at(const Geometry& geometry, unsigned triangle, double u, double v) const;

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
