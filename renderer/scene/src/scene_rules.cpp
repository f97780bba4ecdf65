#include "oer/scene/scene_rules.hpp"

#include <cstddef>
#include <vector>

namespace oer {

bool needs_specular(const FrameRequest& request) {
    if (!request.rig || request.rig->model != LightingModel::Hdr) {
        return false;
    }
    for (const SceneObject& object : request.objects) {
        for (const Primitive& primitive : object.mesh->primitives) {
            if (object.mesh->materials.at(std::size_t(primitive.material)).glossy()) {
                return true;
            }
        }
    }
    return false;
}

std::string transfer_misfit(const SceneTransfer& transfer, const FrameRequest& request) {
    if (transfer.bounce != request.bounce) {
        return std::string("it was baked with bounce ") +
               (transfer.bounce == Bounce::One ? "one" : "none") + ", the frame asks " +
               (request.bounce == Bounce::One ? "one" : "none");
    }
    if (transfer.ground.has_value() != request.ground) {
        return transfer.ground ? "it has a ground, the frame has none"
                               : "it has no ground, the frame has one";
    }
    if (transfer.objects.size() != request.objects.size()) {
        return "it has " + std::to_string(transfer.objects.size()) + " object(s), the frame " +
               std::to_string(request.objects.size());
    }
    for (std::size_t o = 0; o < transfer.objects.size(); ++o) {
        const std::vector<Primitive>& primitives = request.objects[o].mesh->primitives;
        if (transfer.objects[o].size() != primitives.size()) {
            return "object " + std::to_string(o) + " has " +
                   std::to_string(transfer.objects[o].size()) + " primitive(s), its mesh " +
                   std::to_string(primitives.size());
        }
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            if (transfer.objects[o][p].count != primitives[p].positions.size()) {
                return "object " + std::to_string(o) + ", primitive " + std::to_string(p) +
                       " has " + std::to_string(transfer.objects[o][p].count) + " point(s) for " +
                       std::to_string(primitives[p].positions.size()) + " vertices";
            }
        }
    }
    return {};
}

}  // namespace oer
