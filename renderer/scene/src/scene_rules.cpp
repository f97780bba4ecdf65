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
            const int material = primitive.material_under(object.variant);
            if (object.mesh->materials.at(std::size_t(material)).glossy()) {
                return true;
            }
        }
    }
    return false;
}

namespace {

// Why transfer's reflector slots do not fit request's objects: an object or material the frame
// does not have, or one slot's objects of different meshes or drawn with different colours
// (their shared vectors could not be weighed apart).
std::string reflectors_misfit(const SceneTransfer& transfer, const FrameRequest& request) {
    if ((transfer.bounce == Bounce::One) != !transfer.reflectors.empty()) {
        return transfer.reflectors.empty() ? "it has bounce vectors but no reflector slots"
                                           : "it has reflector slots but no bounce";
    }
    for (std::size_t s = 0; s < transfer.reflectors.size(); ++s) {
        const ReflectorSlot& slot = transfer.reflectors[s];
        const std::string name = "its reflector slot " + std::to_string(s);
        if ((slot.kind == ReflectorSlot::Kind::Ground) != slot.objects.empty()) {
            return name +
                   (slot.objects.empty() ? " names no object" : " of the ground names objects");
        }
        for (const std::uint32_t o : slot.objects) {
            if (o >= request.objects.size()) {
                return name + " names object " + std::to_string(o) +
                       ", which the frame does not have";
            }
            const SceneObject& first = request.objects[slot.objects.front()];
            if (request.objects[o].mesh != first.mesh ||
                request.objects[o].base_color != first.base_color ||
                request.objects[o].base_color_material != first.base_color_material ||
                request.objects[o].variant != first.variant) {
                return name + " holds objects that the frame draws differently";
            }
        }
        if (slot.kind == ReflectorSlot::Kind::Material &&
            slot.material >= request.objects[slot.objects.front()].mesh->materials.size()) {
            return name + " names material " + std::to_string(slot.material) +
                   ", which its objects' mesh does not have";
        }
    }
    return {};
}

}  // namespace

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
    return reflectors_misfit(transfer, request);
}

}  // namespace oer
