// What oer::Mesh computes of itself (see oer/mesh/mesh.hpp).
#include "oer/mesh/mesh.hpp"

#include <algorithm>

namespace oer {

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
