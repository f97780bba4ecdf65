// Tangents by MikkTSpace, welded back into an indexed primitive (see tangent_generation.hpp).
// MikkTSpace's bitangent points along increasing t of the texture coordinates it is given;
// glTF's uv has v growing down the image (specification, section 3.7.2.1: its origin is the
// image's top-left corner) while a normal map's +Y points up it, so MikkTSpace is given
// t = 1 - v. That only flips the sign w: the tangent, along increasing u, is the same either
// way. three.js does the same by negating MikkTSpace's sign for glTF.
#include "tangent_generation.hpp"

#include <mikktspace.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "mesh_errors.hpp"
#include "oer/core/error.hpp"

namespace oer::mesh_detail {

namespace {

struct MikkInput {
    const Primitive& primitive;
    std::vector<glm::vec4> corner_tangents;  // 3 per triangle
};

MikkInput& input_of(const SMikkTSpaceContext* context) {
    return *static_cast<MikkInput*>(context->m_pUserData);
}

std::uint32_t vertex_of(const SMikkTSpaceContext* context, int face, int corner) {
    return input_of(context).primitive.indices[std::size_t(face) * 3 + std::size_t(corner)];
}

int face_count(const SMikkTSpaceContext* context) {
    return int(input_of(context).primitive.indices.size() / 3);
}

int corners_of_face(const SMikkTSpaceContext*, const int) {
    return 3;
}

void position(const SMikkTSpaceContext* context, float out[], const int face, const int corner) {
    const glm::vec3& p = input_of(context).primitive.positions[vertex_of(context, face, corner)];
    out[0] = p.x;
    out[1] = p.y;
    out[2] = p.z;
}

void normal(const SMikkTSpaceContext* context, float out[], const int face, const int corner) {
    const glm::vec3& n = input_of(context).primitive.normals[vertex_of(context, face, corner)];
    out[0] = n.x;
    out[1] = n.y;
    out[2] = n.z;
}

void texcoord(const SMikkTSpaceContext* context, float out[], const int face, const int corner) {
    const glm::vec2& uv = input_of(context).primitive.texcoords[vertex_of(context, face, corner)];
    out[0] = uv.x;
    out[1] = 1.0f - uv.y;  // glTF's v grows down the image; MikkTSpace's t up it
}

void store(const SMikkTSpaceContext* context, const float tangent[], const float sign,
           const int face, const int corner) {
    input_of(context).corner_tangents[std::size_t(face) * 3 + std::size_t(corner)] =
        glm::vec4(tangent[0], tangent[1], tangent[2], sign);
}

// A unit vector perpendicular to the unit `n` (Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 2017).
glm::vec3 perpendicular(const glm::vec3& n) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    return glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
}

// The corner's tangent made perpendicular to its normal (MikkTSpace's already is, except its
// default (1, 0, 0) for a corner whose triangles have no uv area), or a perpendicular to the
// normal when nothing of it is left.
glm::vec4 usable(const glm::vec4& tangent, const glm::vec3& normal) {
    const glm::vec3 xyz = glm::vec3(tangent) - glm::dot(glm::vec3(tangent), normal) * normal;
    const float length = glm::length(xyz);
    const float sign = tangent.w < 0.0f ? -1.0f : 1.0f;
    if (length > 1e-3f && std::isfinite(length)) {
        return glm::vec4(xyz / length, sign);
    }
    return glm::vec4(perpendicular(normal), sign);
}

// Whether MikkTSpace can weld the primitive's corners: it hashes each position on a grid over
// the widest extent of the corners' positions, int(2048 * (x - min) / (max - min))
// (mikktspace.c, FindGridCell), which is undefined behaviour, a NaN cast to int, when every
// position is one point (0 / 0) or the extent passes the largest float (inf / inf).
bool weldable(const Primitive& primitive) {
    glm::vec3 low(std::numeric_limits<float>::max());
    glm::vec3 high(std::numeric_limits<float>::lowest());
    for (const std::uint32_t vertex : primitive.indices) {
        low = glm::min(low, primitive.positions[vertex]);
        high = glm::max(high, primitive.positions[vertex]);
    }
    const glm::vec3 extent = high - low;
    const float widest = std::max({extent.x, extent.y, extent.z});
    return widest > 0.0f && widest <= std::numeric_limits<float>::max();
}

}  // namespace

std::size_t generate_tangents(Primitive& primitive, const std::string& asset) {
    const std::size_t corners = primitive.indices.size();
    if (corners > std::size_t(std::numeric_limits<int>::max())) {
        fail(ErrorKind::LimitExceeded, asset,
             primitive.name + ": too many triangles to generate tangents for");
    }
    MikkInput input{primitive, std::vector<glm::vec4>(corners, glm::vec4(0.0f))};
    SMikkTSpaceInterface callbacks{};
    callbacks.m_getNumFaces = &face_count;
    callbacks.m_getNumVerticesOfFace = &corners_of_face;
    callbacks.m_getPosition = &position;
    callbacks.m_getNormal = &normal;
    callbacks.m_getTexCoord = &texcoord;
    callbacks.m_setTSpaceBasic = &store;
    const SMikkTSpaceContext context{&callbacks, &input};
    // A primitive MikkTSpace cannot weld (a point, which has no surface to take tangents from,
    // or positions spanning past the float range, whose tangents float cannot compute) is not
    // given to it: its corners keep no tangent and get the perpendicular below.
    if (weldable(primitive) && genTangSpaceDefault(&context) == 0) {
        fail(ErrorKind::LimitExceeded, asset,
             primitive.name + ": out of memory while generating tangents");
    }

    // Welding: the first tangent met at a vertex stays with it; another one gets a copy of the
    // vertex (copies of one vertex are chained, the first in first_copy, the next in next_copy).
    constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    const std::size_t original = primitive.positions.size();
    std::vector<bool> assigned(original, false);
    std::vector<std::uint32_t> first_copy(original, none);
    std::vector<std::uint32_t> next_copy;
    primitive.tangents.assign(original, glm::vec4(0.0f));
    for (std::size_t c = 0; c < corners; ++c) {
        const std::uint32_t vertex = primitive.indices[c];
        const glm::vec4 tangent = usable(input.corner_tangents[c], primitive.normals[vertex]);
        if (!assigned[vertex]) {
            assigned[vertex] = true;
            primitive.tangents[vertex] = tangent;
            continue;
        }
        if (primitive.tangents[vertex] == tangent) {
            continue;
        }
        std::uint32_t* link = &first_copy[vertex];
        while (*link != none && primitive.tangents[*link] != tangent) {
            link = &next_copy[*link - original];
        }
        if (*link == none) {
            if (primitive.positions.size() >= std::size_t(none)) {
                fail(ErrorKind::LimitExceeded, asset,
                     primitive.name + ": too many vertices after splitting them for tangents");
            }
            *link = std::uint32_t(primitive.positions.size());
            primitive.positions.push_back(primitive.positions[vertex]);
            primitive.normals.push_back(primitive.normals[vertex]);
            primitive.texcoords.push_back(primitive.texcoords[vertex]);
            if (!primitive.texcoords1.empty()) {
                primitive.texcoords1.push_back(primitive.texcoords1[vertex]);
            }
            if (!primitive.colors.empty()) {
                primitive.colors.push_back(primitive.colors[vertex]);
            }
            primitive.tangents.push_back(tangent);
            const std::uint32_t copy = *link;
            next_copy.push_back(none);  // may move next_copy, where `link` may point
            primitive.indices[c] = copy;
            continue;
        }
        primitive.indices[c] = *link;
    }
    // Vertices on no triangle keep a valid tangent too.
    for (std::size_t v = 0; v < original; ++v) {
        if (!assigned[v]) {
            primitive.tangents[v] = glm::vec4(perpendicular(primitive.normals[v]), 1.0f);
        }
    }
    return primitive.positions.size() - original;
}

}  // namespace oer::mesh_detail
