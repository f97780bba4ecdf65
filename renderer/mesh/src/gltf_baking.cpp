// A glTF node's world transform baked into vertices (see gltf_baking.hpp).
#include "gltf_baking.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>

#include "mesh_finishing.hpp"

namespace oer::mesh_detail {

namespace {

bool flattening(double determinant) {
    return determinant == 0.0 || !std::isfinite(determinant);
}

void transform_normals(std::vector<glm::vec3>& normals, const glm::dmat3& linear,
                       double determinant) {
    if (flattening(determinant)) {
        std::fill(normals.begin(), normals.end(), glm::vec3(0.0f));
        return;
    }
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
    for (glm::vec3& normal : normals) {
        if (normal == glm::vec3(0.0f)) {
            continue;  // bad in the file: computed later
        }
        const glm::dvec3 turned = normal_matrix * glm::dvec3(normal);
        const double length = glm::length(turned);
        normal =
            length > 0.0 && std::isfinite(length) ? glm::vec3(turned / length) : glm::vec3(0.0f);
    }
}

}  // namespace

std::uint64_t bake_transform(Primitive& primitive, const glm::dmat4& world) {
    for (glm::vec3& p : primitive.positions) {
        p = glm::vec3(world * glm::dvec4(glm::dvec3(p), 1.0));
    }
    const glm::dmat3 linear(world);
    const double determinant = glm::determinant(linear);
    std::uint64_t renormalised = 0;
    if (!primitive.normals.empty()) {
        renormalised = normalise_file_normals(primitive.normals);
        transform_normals(primitive.normals, linear, determinant);
    }
    if (determinant < 0.0) {
        for (std::size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
            std::swap(primitive.indices[t + 1], primitive.indices[t + 2]);
        }
    }
    return renormalised;
}

void bake_tangents(std::vector<glm::vec4>& tangents, const glm::dmat4& world) {
    const glm::dmat3 linear(world);
    const double determinant = glm::determinant(linear);
    if (flattening(determinant)) {
        tangents.clear();
        return;
    }
    const float sign = determinant < 0.0 ? -1.0f : 1.0f;
    for (glm::vec4& tangent : tangents) {
        const glm::dvec3 turned = linear * glm::dvec3(glm::vec3(tangent));
        const double length = glm::length(turned);
        if (!(length > 0.0) || !std::isfinite(length)) {
            tangents.clear();
            return;
        }
        tangent = glm::vec4(glm::vec3(turned / length), sign * tangent.w);
    }
}

}  // namespace oer::mesh_detail
