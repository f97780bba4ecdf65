#include "oer/transfer/transfer_lighting.hpp"

#include <algorithm>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/sh_projection.hpp"
#include "oer/lighting/sh_rotation.hpp"

namespace oer {

namespace {

[[noreturn]] void invalid_lighting(const std::string& message) {
    throw Error(ErrorKind::InvalidInput, "transfer lighting: " + message);
}

// The map turned by the yaw lights world direction d as the unturned map lights d turned back:
// g(d) = f(Q^T d) with Q the yaw's rotation (equirect::rotate_yaw), rotate_sh's convention.
ShRgb turned_by_yaw(const ShRgb& sh, double yaw_degrees) {
    if (yaw_degrees == 0.0) {
        return sh;
    }
    const glm::dmat3 yaw(equirect::rotate_yaw({1.0, 0.0, 0.0}, yaw_degrees),
                         equirect::rotate_yaw({0.0, 1.0, 0.0}, yaw_degrees),
                         equirect::rotate_yaw({0.0, 0.0, 1.0}, yaw_degrees));
    return rotate_sh(sh, yaw);
}

// P_n(0): 0 for odd n, (-1)^(n/2) n! / (2^n ((n/2)!)^2) for even n.
double legendre_at_zero(int n) {
    if (n % 2 != 0) {
        return 0.0;
    }
    double value = 1.0;
    for (int k = 1; k <= n / 2; ++k) {
        value *= -double(2 * k - 1) / double(2 * k);
    }
    return value;
}

}  // namespace

ShRgb below_horizon_indicator(int order) {
    std::vector<double> basis(std::size_t(sh_count(order)));
    sh_evaluate(order, {0.0, -1.0, 0.0}, basis);
    ShRgb indicator(order);
    for (int l = 0; l < order; ++l) {
        const double q =
            l == 0 ? 1.0 : (legendre_at_zero(l - 1) - legendre_at_zero(l + 1)) / double(2 * l + 1);
        for (int m = -l; m <= l; ++m) {
            indicator.coefficients[std::size_t(sh_index(l, m))] =
                glm::dvec3(2.0 * std::numbers::pi * q * basis[std::size_t(sh_index(l, m))]);
        }
    }
    return indicator;
}

int transfer_order(const Rig& rig) {
    return std::min(rig.sh.all.order, kTransferBakeOrder);
}

TransferLighting transfer_lighting(const Rig& rig, std::span<const float> weights,
                                   double yaw_degrees, int order, bool ground, Bounce bounce) {
    if (weights.size() != rig.lights.size()) {
        invalid_lighting(std::to_string(weights.size()) + " light weights for a rig of " +
                         std::to_string(rig.lights.size()) + " lights");
    }
    if (order < 1 || order > transfer_order(rig)) {
        invalid_lighting("order " + std::to_string(order) + " is outside 1.." +
                         std::to_string(transfer_order(rig)));
    }
    // The yaw turns about +Y: it keeps the horizon, so the ground's part needs no turning.
    ShRgb residual = ground ? residual_above_horizon(rig.sh, order) : rig.sh.all.truncated(order);
    if (!ground) {
        for (const ShRgb& light : rig.sh.per_light) {
            residual -= light.truncated(order);
        }
    }
    ShRgb whole = residual;
    for (std::size_t k = 0; k < rig.lights.size(); ++k) {
        if (weights[k] != 0.0f) {
            // With the ground, only the part of the light above the horizon lights anything.
            ShRgb light =
                (ground ? rig.sh.per_light_above_horizon[k] : rig.sh.per_light[k]).truncated(order);
            light *= double(weights[k]);
            whole += light;
        }
    }
    if (ground && bounce == Bounce::One) {
        // The open ground's radiance, albedo / pi times the irradiance of L above the horizon.
        const glm::dvec3 open_ground = irradiance_coefficients(whole).evaluate({0.0, 1.0, 0.0}) *
                                       (double(kGroundAlbedo) / std::numbers::pi);
        ShRgb below = below_horizon_indicator(order);
        for (glm::dvec3& c : below.coefficients) {
            c *= open_ground;
        }
        residual += below;
        whole += below;
    }
    return {turned_by_yaw(residual, yaw_degrees), turned_by_yaw(whole, yaw_degrees)};
}

namespace {

// The linear base colour of the material `object` draws where its file draws `material`
// (the first primitive that does; reflector_slots makes Material slots only where every one of
// them draws the same under each variant), its override included.
glm::vec3 albedo_drawn(const SceneObject& object, std::uint32_t material) {
    const Mesh& mesh = *object.mesh;
    std::size_t drawn = material;
    for (const Primitive& primitive : mesh.primitives) {
        if (std::uint32_t(primitive.material) == material) {
            drawn = std::size_t(primitive.material_under(object.variant));
            break;
        }
    }
    const Material& drawn_material = mesh.materials.at(drawn);
    return base_color_override(object, drawn_material)
        .value_or(glm::vec3(drawn_material.base_color));
}

// Whether the object draws some primitive with another albedo than its file's materials: under
// a variant that changes its materials, or with a base colour of its own.
bool draws_other_albedos(const SceneObject& object) {
    return object.base_color ||
           std::any_of(object.mesh->primitives.begin(), object.mesh->primitives.end(),
                       [&](const Primitive& primitive) {
                           return primitive.material_under(object.variant) != primitive.material;
                       });
}

// The vertex-weighted mean base colour of what `object` draws (its variant's materials and
// its override): a Unit slot's weight for a textured or many-material object drawn with other
// albedos than its file's, whose Native slot holds the file's (textures are left out of the
// mean: an approximation the design notes state). With one colour over every material, that
// colour.
glm::vec3 mean_albedo_drawn(const SceneObject& object) {
    glm::vec3 sum(0.0f);
    double vertices = 0.0;
    for (const Primitive& primitive : object.mesh->primitives) {
        const Material& material =
            object.mesh->materials.at(std::size_t(primitive.material_under(object.variant)));
        sum += float(primitive.positions.size()) *
               base_color_override(object, material).value_or(glm::vec3(material.base_color));
        vertices += double(primitive.positions.size());
    }
    return vertices > 0.0 ? sum / float(vertices) : sum;
}

}  // namespace

std::vector<glm::vec3> bounce_weights(const SceneTransfer& transfer, const FrameRequest& request) {
    std::vector<glm::vec3> weights;
    for (const ReflectorSlot& slot : transfer.reflectors) {
        if (slot.kind == ReflectorSlot::Kind::Ground) {
            weights.push_back(slot.albedo);
            continue;
        }
        const SceneObject& object = request.objects.at(slot.objects.front());
        switch (slot.kind) {
            case ReflectorSlot::Kind::Ground:
                break;
            case ReflectorSlot::Kind::Material:
                weights.push_back(albedo_drawn(object, slot.material));
                break;
            case ReflectorSlot::Kind::Native: {
                // The file's albedos, textures included, when the object draws them.
                const float native = draws_other_albedos(object) ? 0.0f : 1.0f;
                for (int c = 0; c < 3; ++c) {
                    glm::vec3 channel(0.0f);
                    channel[c] = native;
                    weights.push_back(channel);
                }
                break;
            }
            case ReflectorSlot::Kind::Unit:
                weights.push_back(draws_other_albedos(object) ? mean_albedo_drawn(object)
                                                              : glm::vec3(0.0f));
                break;
        }
    }
    return weights;
}

std::vector<glm::vec3> transferred_irradiance(const TransferPoints& points, int stored_order,
                                              const TransferLighting& lighting,
                                              std::span<const glm::vec3> weights) {
    const int order = lighting.residual.order;
    if (order > stored_order || lighting.whole.order != order) {
        invalid_lighting("lighting of order " + std::to_string(order) +
                         " for a transfer baked at order " + std::to_string(stored_order));
    }
    const std::size_t stored = std::size_t(stored_order) * std::size_t(stored_order);
    const std::size_t used = std::size_t(order) * std::size_t(order);
    const std::size_t vectors = points.bounce.empty() ? 0 : weights.size();
    if (points.direct.size() != points.count * stored ||
        points.bounce.size() != points.count * vectors * stored) {
        invalid_lighting("transfer vectors of " + std::to_string(points.direct.size()) +
                         " direct and " + std::to_string(points.bounce.size()) +
                         " bounce values for " + std::to_string(points.count) + " points and " +
                         std::to_string(weights.size()) + " bounce vectors' weights");
    }
    // Float copies, channel-major, so that each dot product below is a contiguous loop.
    std::vector<float> residual(3 * used), whole(3 * used);
    for (std::size_t i = 0; i < used; ++i) {
        for (int c = 0; c < 3; ++c) {
            residual[std::size_t(c) * used + i] = float(lighting.residual.coefficients[i][c]);
            whole[std::size_t(c) * used + i] = float(lighting.whole.coefficients[i][c]);
        }
    }
    const auto dot = [used](const float* a, const float* b) {
        float sum = 0.0f;
        for (std::size_t i = 0; i < used; ++i) {
            sum += a[i] * b[i];
        }
        return sum;
    };
    std::vector<glm::vec3> irradiance(points.count);
    for (std::size_t p = 0; p < points.count; ++p) {
        const float* direct = points.direct.data() + p * stored;
        glm::vec3 e(0.0f);
        for (int c = 0; c < 3; ++c) {
            e[c] = dot(direct, residual.data() + std::size_t(c) * used);
        }
        for (std::size_t v = 0; v < vectors; ++v) {
            const float* reflected = points.bounce.data() + (p * vectors + v) * stored;
            for (int c = 0; c < 3; ++c) {
                if (weights[v][c] != 0.0f) {
                    e[c] += weights[v][c] * dot(reflected, whole.data() + std::size_t(c) * used);
                }
            }
        }
        irradiance[p] = e;
    }
    return irradiance;
}

std::vector<double> unoccluded_transfer(int order, const glm::dvec3& n) {
    std::vector<double> transfer(std::size_t(sh_count(order)));
    sh_evaluate(order, n, transfer);
    for (int l = 0; l < order; ++l) {
        const double a_l = lambertian_band_factor(l);
        for (int m = -l; m <= l; ++m) {
            transfer[std::size_t(sh_index(l, m))] *= a_l;
        }
    }
    return transfer;
}

glm::vec3 open_ground_irradiance(int stored_order, const TransferLighting& lighting) {
    const std::vector<double> transfer = unoccluded_transfer(stored_order, {0.0, 1.0, 0.0});
    TransferPoints open;
    open.count = 1;
    // As floats, as the bake stores every receiver's vector.
    open.direct.assign(transfer.begin(), transfer.end());
    return transferred_irradiance(open, stored_order, lighting, {}).front();
}

}  // namespace oer
