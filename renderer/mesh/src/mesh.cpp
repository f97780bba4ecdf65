// What oer::Mesh computes of itself (see oer/mesh/mesh.hpp).
#include "oer/mesh/mesh.hpp"

#include <algorithm>
#include <cmath>

namespace oer {

glm::mat3 TextureReference::uv_transform() const {
    const float c = std::cos(rotation), s = std::sin(rotation);
    const glm::mat3 translation(1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, offset.x, offset.y, 1.0f);
    const glm::mat3 turn(c, s, 0.0f, -s, c, 0.0f, 0.0f, 0.0f, 1.0f);
    const glm::mat3 stretch(scale.x, 0.0f, 0.0f, 0.0f, scale.y, 0.0f, 0.0f, 0.0f, 1.0f);
    return translation * turn * stretch;
}

std::vector<int> Primitive::materials_drawn() const {
    std::vector<int> drawn{material};
    for (const int variant : variant_materials) {
        if (std::find(drawn.begin(), drawn.end(), variant) == drawn.end()) {
            drawn.push_back(variant);
        }
    }
    return drawn;
}

}  // namespace oer
