#pragma once
// A frame's lighting through a baked transfer (oer/scene/scene_transfer.hpp): the residual map R
// and the whole lighting L in the transfer's frame, and the irradiance E(x) = T(x) . R + B(x) . L
// that they give at every receiver point (P.-P. Sloan, J. Kautz and J. Snyder, "Precomputed
// Radiance Transfer for Real-Time Rendering in Dynamic, Low-Frequency Lighting Environments",
// SIGGRAPH 2002, section 5: a diffuse receiver's exit radiance is a dot product of its transfer
// vector with the lighting's coefficients). No GL and no ray tracing: the frame renderer calls it
// per frame, before its passes.
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "oer/lighting/rig.hpp"
#include "oer/lighting/sh.hpp"
#include "oer/scene/frame_request.hpp"
#include "oer/scene/scene_transfer.hpp"

namespace oer {

// The order a frame evaluates a transfer at for this rig: the rig's own SH order, at most
// kTransferBakeOrder. The rig's order is already the lowest whose irradiance error is under the
// tolerance for this map (rig.hpp, "model only what a scene needs"), and the first order^2
// coefficients of a transfer are exactly that order's transfer, so a lower order costs nothing
// in accuracy that the rig had not already given up.
int transfer_order(const Rig& rig);

struct TransferLighting {
    // R, the residual map (the rig's radiance minus every light's own pixels, Rig::sh), and L,
    // the whole lighting of the frame (R plus each light's pixels times its weight), both turned
    // by the environment's yaw into the world frame the transfer was baked in, unwindowed, at
    // the evaluation order.
    //
    // With the ground as lighting (docs/design.md section 2), a point above the infinite plane sees
    // the plane in every direction below its horizon, never the map: R and L are then the map's
    // above the horizon (the rig's above-horizon projection: the residual, and each light's part
    // above the horizon) plus, below it,
    // the open ground's radiance g = albedo / pi E_g, E_g the irradiance of L above the horizon
    // at +Y, under Bounce::One; nothing under Bounce::None (the ground reflects nothing). The
    // bake counts a ray that meets the plane as seeing this lighting, and adds the ground's
    // departure from g near the objects (their contact shadow) as reflected light.
    ShRgb residual;
    ShRgb whole;
};

// weights: one per rig light (0 off, 1 as captured); yaw_degrees about +Y (docs/design.md
// section 3); ground: the frame has the ground plane, which reflects as `bounce` says. Throws
// oer::Error (InvalidInput) when the weights do not match the rig's lights or order is outside
// 1 .. min(rig order, kTransferBakeOrder).
TransferLighting transfer_lighting(const Rig& rig, std::span<const float> weights,
                                   double yaw_degrees, int order, bool ground, Bounce bounce);

// The SH coefficients, at `order`, of the function that is 1 below the horizon (y < 0) and 0
// above: 2 pi q_l Y_lm(-Y), q_0 = 1, q_l = (P_(l-1)(0) - P_(l+1)(0)) / (2l + 1), the integral of
// the Legendre polynomial P_l over [0, 1] (a zonal function about -Y, turned there by the
// addition theorem).
ShRgb below_horizon_indicator(int order);

// The weight, per colour channel, of each of transfer's bounce vectors in request's frame, as
// ReflectorSlot::Kind says: the ground's albedo; a Material slot's
// objects' colour (SceneObject::base_color) or else its material's; a Native slot's vector c
// 1 in channel c when its objects have no colour of their own; a Unit slot's their colour.
// The transfer must fit the request (transfer_misfit, oer/scene/scene_rules.hpp).
std::vector<glm::vec3> bounce_weights(const SceneTransfer& transfer, const FrameRequest& request);

// The irradiance at every point of `points` (baked at stored_order) under `lighting`, its
// bounce vectors weighted by `weights` (one per vector, bounce_weights):
// E_c(p) = sum_i direct_i(p) R_c,i + sum_v weight_v,c sum_i bounce_v,i(p) L_c,i over the
// lighting's order^2 coefficients. Throws oer::Error (InvalidInput) when the lighting's order
// exceeds stored_order or the points' vectors do not have the sizes their count and the
// weights say.
std::vector<glm::vec3> transferred_irradiance(const TransferPoints& points, int stored_order,
                                              const TransferLighting& lighting,
                                              std::span<const glm::vec3> weights);

// The transfer of a point facing n that nothing occludes: the clamped cosine's, A_l Y_lm(n)
// (Ramamoorthi and Hanrahan 2001), order^2 coefficients. The bake starts every receiver from
// it and takes off what its rays find blocked.
std::vector<double> unoccluded_transfer(int order, const glm::dvec3& n);

// The irradiance of the open ground under `lighting`: a texel of the ground's grid that
// nothing occludes and nothing reflects onto, by the same sums as transferred_irradiance, so
// that such a texel of a transfer baked at stored_order has exactly this value (the
// shadow-catching floor's light without the objects, and where the grid ends).
glm::vec3 open_ground_irradiance(int stored_order, const TransferLighting& lighting);

}  // namespace oer
