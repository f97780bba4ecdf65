// The transfer bake against answers known without it: a convex object's transfer is plain SH
// irradiance; an open box's floor sees the sky through the opening by the rectangle's view
// factor; a point under a bright ceiling gets the ceiling's reflected light by that view factor;
// a sphere resting on the ground darkens it by the sphere's view factor; and the bake is the
// same on any number of threads. Visible fractions are compared within three standard
// deviations of a binomial count of the bake's rays (stratified rays do better; the figures
// measured are printed).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "oer/core/error.hpp"
#include "oer/lighting/sh.hpp"
#include "oer/lighting/sh_projection.hpp"
#include "oer/transfer/transfer_bake.hpp"
#include "oer/transfer/transfer_lighting.hpp"
#include "synthetic_maps.hpp"
#include "test_meshes.hpp"

using namespace oer;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kCoefficients = sh_count(kTransferBakeOrder);
const double kY00 = 0.5 / std::sqrt(kPi);

using Coefficients = std::array<double, kCoefficients>;

// A_l Y_i(n): the transfer of a point nothing occludes.
Coefficients cosine_transfer(const glm::dvec3& n) {
    Coefficients transfer{};
    sh_evaluate(kTransferBakeOrder, n, transfer);
    for (int l = 0; l < kTransferBakeOrder; ++l) {
        for (int m = -l; m <= l; ++m) {
            transfer[std::size_t(sh_index(l, m))] *= lambertian_band_factor(l);
        }
    }
    return transfer;
}

// The share of the cosine-weighted hemisphere from which the sky reaches a point: its band-0
// transfer over the unoccluded A_0 Y_0 = pi Y_0 (under a constant sky of radiance L,
// L_00 = 4 pi Y_0 L and E = direct_0 L_00 = that share times pi L).
double visible_fraction(const float* direct) {
    return double(direct[0]) / (kPi * kY00);
}

// Three standard deviations of the share of `rays` independent rays that hit something of
// probability p: a bound for stratified rays, whose error is smaller.
double binomial_tolerance(double p, int rays) {
    return 3.0 * std::sqrt(p * (1.0 - p) / rays);
}

SceneObject object_of(Mesh mesh, glm::mat4 transform = glm::mat4(1.0f),
                      std::optional<glm::vec3> base_color = std::nullopt) {
    return {std::make_shared<const Mesh>(std::move(mesh)), transform, base_color};
}

FrameRequest request_of(std::vector<SceneObject> objects, bool ground) {
    FrameRequest request;
    request.objects = std::move(objects);
    request.ground = ground;
    return request;
}

// The vertex of `primitive` nearest `position` among those whose normal is `normal`.
std::size_t vertex_at(const Primitive& primitive, glm::vec3 position, glm::vec3 normal) {
    std::size_t best = primitive.positions.size();
    float best_distance = 1e30f;
    for (std::size_t v = 0; v < primitive.positions.size(); ++v) {
        const float distance = glm::length(primitive.positions[v] - position);
        if (glm::dot(primitive.normals[v], normal) > 0.999f && distance < best_distance) {
            best = v;
            best_distance = distance;
        }
    }
    EXPECT_LT(best_distance, 1e-4f) << "no vertex at the point the test needs";
    return best;
}

// The cosine-weighted view factor from a point, facing +Y, to the rectangle [x0, x1] x [z0, z1]
// at height h above it (x0 < 0 < x1, z0 < 0 < z1 in the point's frame), as four rectangles
// with a corner above the point, each (J. R. Howell, "A Catalog of Radiation Heat Transfer
// Configuration Factors": differential planar element to a parallel rectangle, the element's
// normal through a corner; sides a and b at distance c, A = a / c, B = b / c)
//   F = 1 / (2 pi) (A / sqrt(1 + A^2) atan(B / sqrt(1 + A^2))
//                   + B / sqrt(1 + B^2) atan(A / sqrt(1 + B^2))).
double rectangle_view_factor(double x0, double x1, double z0, double z1, double h) {
    const auto corner = [h](double a, double b) {
        const double A = a / h, B = b / h;
        const double sa = std::sqrt(1.0 + A * A), sb = std::sqrt(1.0 + B * B);
        return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2.0 * kPi);
    };
    return corner(-x0, -z0) + corner(-x0, z1) + corner(x1, -z0) + corner(x1, z1);
}

// The cosine-weighted view factor of a sphere of radius r resting on a plane, from a point of
// the plane at horizontal distance d from where it touches. The whole sphere is above the
// point's horizon, so by Nusselt's analogue (the solid angle projected onto the base of the unit
// hemisphere, over pi) its cap of half-angle alpha, sin alpha = r / D, whose axis makes the angle
// beta with the normal projects to an ellipse of area pi sin^2 alpha cos beta: with
// D = sqrt(d^2 + r^2) and cos beta = r / D, F = (r / D)^2 (r / D) (Howell's catalogue likewise:
// differential element to a sphere wholly above its plane).
double sphere_view_factor(double r, double d) {
    const double ratio = r / std::sqrt(d * d + r * r);
    return ratio * ratio * ratio;
}

const float* direct_of(const TransferPoints& points, std::size_t point) {
    return &points.direct[point * kCoefficients];
}

// What a point reflects in one colour channel in a frame of `request`: its bounce vectors
// weighed as that frame weighs them (bounce_weights).
Coefficients bounce_of(const SceneTransfer& transfer, const FrameRequest& request,
                       const TransferPoints& points, std::size_t point, int channel) {
    const std::vector<glm::vec3> weights = bounce_weights(transfer, request);
    Coefficients bounce{};
    for (std::size_t v = 0; v < weights.size(); ++v) {
        const float* vector = &points.bounce[(point * weights.size() + v) * kCoefficients];
        for (int i = 0; i < kCoefficients; ++i) {
            bounce[std::size_t(i)] += double(weights[v][channel]) * double(vector[i]);
        }
    }
    return bounce;
}

double max_abs(const std::vector<float>& values) {
    double largest = 0.0;
    for (const float value : values) {
        largest = std::max(largest, double(std::abs(value)));
    }
    return largest;
}

}  // namespace

TEST(TransferBakeConvex, SphereAloneIsPlainIrradiance) {
    const Mesh sphere = oer::testing::uv_sphere({0.0f, 0.5f, 0.0f}, 1.0f, 64, 32, glm::vec3(0.7f));
    TransferBakeOptions options;  // the rule's rays, one bounce
    const SceneTransfer transfer = bake_transfer(request_of({object_of(sphere)}, false), options);
    EXPECT_EQ(transfer.order, kTransferBakeOrder);
    EXPECT_EQ(transfer.rays, transfer_ray_count({object_of(sphere)}));
    EXPECT_FALSE(transfer.ground.has_value());
    ASSERT_EQ(transfer.objects.size(), 1u);
    ASSERT_EQ(transfer.objects[0].size(), 1u);
    const TransferPoints& points = transfer.objects[0][0];
    ASSERT_EQ(points.count, sphere.primitives[0].positions.size());

    // A sky with a broad bright patch, order 5 radiance through the lighting library.
    const HdrImage map = oer::testing::disc_map(256, 128, {0.2f, 0.3f, 0.5f},
                                                {{{0.3, 0.8, 0.2}, 0.6, {3.0f, 2.5f, 2.0f}}});
    const ShRgb radiance = project_environment(map, {}, kTransferBakeOrder).all;

    double worst_irradiance = 0.0, worst_coefficient = 0.0;
    for (std::size_t v = 0; v < points.count; ++v) {
        const glm::dvec3 n = glm::normalize(glm::dvec3(sphere.primitives[0].normals[v]));
        const Coefficients expected = cosine_transfer(n);
        const float* direct = direct_of(points, v);
        glm::dvec3 baked(0.0), plain(0.0);
        for (int i = 0; i < kCoefficients; ++i) {
            baked += double(direct[i]) * radiance.coefficients[std::size_t(i)];
            plain += expected[std::size_t(i)] * radiance.coefficients[std::size_t(i)];
            worst_coefficient =
                std::max(worst_coefficient, std::abs(double(direct[i]) - expected[std::size_t(i)]));
        }
        for (int c = 0; c < 3; ++c) {
            ASSERT_GT(plain[c], 0.0);
            worst_irradiance = std::max(worst_irradiance, std::abs(baked[c] / plain[c] - 1.0));
        }
    }
    std::printf(
        "convex sphere, %zu vertices, %d rays: worst relative irradiance error %.3g, "
        "worst coefficient error %.3g (of A_0 Y_0 = %.3f)\n",
        points.count, transfer.rays, worst_irradiance, worst_coefficient, kPi * kY00);
    EXPECT_LT(worst_irradiance, 0.01);
    // Nothing occludes: the bake's control variate leaves A_l Y_i(n) itself, to float rounding.
    EXPECT_LT(worst_coefficient, 1e-5);
    // Nothing to reflect: no bounce at all.
    ASSERT_EQ(points.bounce.size(),
              points.count * bounce_vectors(transfer.reflectors) * kCoefficients);
    EXPECT_EQ(max_abs(points.bounce), 0.0);
}

TEST(TransferBakeConcave, OpenBoxFloorSeesTheSkyThroughTheOpening) {
    const float half_size = 1.0f, height = 1.0f;
    const Mesh box = oer::testing::open_box(half_size, height, 0.02f, 8, glm::vec3(0.5f));
    TransferBakeOptions options;
    options.bounce = Bounce::None;
    options.rays = 4096;
    const SceneTransfer transfer = bake_transfer(request_of({object_of(box)}, false), options);
    ASSERT_EQ(transfer.rays, 4096);
    EXPECT_TRUE(transfer.objects[0][0].bounce.empty());

    const std::size_t floor_centre = vertex_at(box.primitives[0], {0, 0, 0}, {0, 1, 0});
    const double visible = visible_fraction(direct_of(transfer.objects[0][0], floor_centre));
    const double expected =
        rectangle_view_factor(-half_size, half_size, -half_size, half_size, height);
    const double tolerance = binomial_tolerance(expected, transfer.rays);
    std::printf(
        "open box floor centre: visible %.5f, view factor of the opening %.5f, "
        "difference %.2g (tolerance %.3g)\n",
        visible, expected, visible - expected, tolerance);
    EXPECT_NEAR(visible, expected, tolerance);

    // A vertex at the middle of an outer wall faces away from the box: its whole hemisphere is
    // open, so it holds the unoccluded transfer.
    const glm::vec3 outer(half_size + 0.02f, 0.5f * (height - 0.02f), 0.0f);
    const std::size_t wall = vertex_at(box.primitives[1], outer, {1, 0, 0});
    const Coefficients open = cosine_transfer({1.0, 0.0, 0.0});
    const float* direct = direct_of(transfer.objects[0][1], wall);
    EXPECT_NEAR(visible_fraction(direct), 1.0, 1e-6);
    for (int i = 0; i < kCoefficients; ++i) {
        EXPECT_NEAR(direct[i], open[std::size_t(i)], 1e-6) << "coefficient " << i;
    }
}

TEST(TransferBakeBounce, PointUnderABrightCeilingGetsItsReflectedLight) {
    // A tiny square facing up at the origin under a 2 x 2 square facing down at height 1: the
    // ceiling's own transfer is (nearly: the tiny square hides almost nothing) the unoccluded
    // A_l Y_i(-Y), so the light it reflects onto the point is rho F A_l Y_i(-Y) with F the
    // rectangle view factor: bounce_c,i = (pi / N) (rho_c / pi) D_i over the share F of the rays.
    const glm::vec3 albedo(0.2f, 0.5f, 0.8f);
    const glm::mat4 face_up = glm::rotate(glm::mat4(1.0f), -0.5f * float(kPi), {1, 0, 0});
    const glm::mat4 face_down = glm::translate(glm::mat4(1.0f), {0, 1, 0}) *
                                glm::rotate(glm::mat4(1.0f), 0.5f * float(kPi), {1, 0, 0});
    const Mesh receiver = oer::testing::quad({0, 0, 0}, 1e-3f, glm::vec3(0.5f));
    const Mesh ceiling = oer::testing::quad({0, 0, 0}, 1.0f, glm::vec3(1.0f));
    TransferBakeOptions options;
    options.rays = 4096;
    const FrameRequest request =
        request_of({object_of(receiver, face_up), object_of(ceiling, face_down, albedo)}, false);
    const SceneTransfer transfer = bake_transfer(request, options);

    const glm::vec3 point = glm::vec3(face_up * glm::vec4(receiver.primitives[0].positions[0], 1));
    ASSERT_NEAR(point.y, 0.0f, 1e-6f);
    const double view_factor =
        rectangle_view_factor(-1.0 - point.x, 1.0 - point.x, -1.0 - point.z, 1.0 - point.z, 1.0);
    const double tolerance = binomial_tolerance(view_factor, transfer.rays);
    const TransferPoints& points = transfer.objects[0][0];
    const double visible = visible_fraction(direct_of(points, 0));
    std::printf("point under a ceiling: visible %.5f, 1 - view factor %.5f\n", visible,
                1.0 - view_factor);
    EXPECT_NEAR(visible, 1.0 - view_factor, tolerance);

    const Coefficients ceiling_transfer = cosine_transfer({0.0, -1.0, 0.0});
    for (int c = 0; c < 3; ++c) {
        const Coefficients bounce = bounce_of(transfer, request, points, 0, c);
        const double share = double(bounce[0]) / (albedo[c] * ceiling_transfer[0]);
        std::printf("  channel %d: bounce_0 / (rho A_0 Y_0(-Y)) %.5f, view factor %.5f\n", c, share,
                    view_factor);
        for (int i = 0; i < kCoefficients; ++i) {
            const double expected = albedo[c] * view_factor * ceiling_transfer[std::size_t(i)];
            EXPECT_NEAR(bounce[std::size_t(i)], expected,
                        tolerance * albedo[c] * std::abs(ceiling_transfer[std::size_t(i)]) + 1e-6)
                << "channel " << c << ", coefficient " << i;
        }
    }

    // The bake does not depend on the colours, which only weigh its slots: a black ceiling has
    // the same vectors, and reflects nothing.
    const FrameRequest black_request = request_of(
        {object_of(receiver, face_up), object_of(ceiling, face_down, glm::vec3(0.0f))}, false);
    const SceneTransfer black = bake_transfer(black_request, options);
    EXPECT_EQ(black.objects[0][0].bounce, points.bounce);
    EXPECT_EQ(black.objects[0][0].direct, points.direct);
    for (int c = 0; c < 3; ++c) {
        for (const double value : bounce_of(black, black_request, points, 0, c)) {
            EXPECT_EQ(value, 0.0);
        }
    }
}

TEST(TransferBakeBounce, ReflectedTransferIsInterpolatedAcrossTheHitTriangle) {
    // A 2 x 2 ceiling at height 1 whose four corners have their normals tilted differently, so
    // their (unoccluded) transfers differ: a point under it gets the integral over the ceiling
    // of rho / pi D(q) cos, D(q) the barycentric mix of its triangle's corners, here summed
    // over a 400 x 400 grid of the ceiling with barycentrics from the positions.
    Mesh ceiling;
    Primitive square;
    const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};  // (x, z)
    for (const glm::vec2& corner : corners) {
        square.positions.emplace_back(corner.x, 1.0f, corner.y);
        square.normals.push_back(
            glm::normalize(glm::vec3(0.6f * corner.x, -1.0f, 0.2f * corner.y)));
    }
    square.indices = {0, 1, 2, 0, 2, 3};
    ceiling.primitives.push_back(square);
    ceiling.materials.push_back(oer::testing::lambertian(glm::vec3(0.5f)));
    oer::testing::finish(ceiling);
    const glm::mat4 face_up = glm::rotate(glm::mat4(1.0f), -0.5f * float(kPi), {1, 0, 0});
    const Mesh receiver = oer::testing::quad({0, 0, 0}, 1e-3f, glm::vec3(0.5f));
    TransferBakeOptions options;
    options.rays = 4096;
    const FrameRequest request =
        request_of({object_of(receiver, face_up), object_of(ceiling)}, false);
    const SceneTransfer transfer = bake_transfer(request, options);

    std::array<Coefficients, 4> corner_transfer;
    for (int k = 0; k < 4; ++k) {
        corner_transfer[std::size_t(k)] =
            cosine_transfer(glm::dvec3(square.normals[std::size_t(k)]));
    }
    const glm::dvec3 point(face_up * glm::vec4(receiver.primitives[0].positions[0], 1.0f));
    constexpr int kSteps = 400;
    const double step = 2.0 / kSteps, albedo = 0.5;
    Coefficients expected{};
    for (int j = 0; j < kSteps; ++j) {
        for (int i = 0; i < kSteps; ++i) {
            const double x = -1.0 + (i + 0.5) * step, z = -1.0 + (j + 0.5) * step;
            // Triangle (0, 1, 2) where x >= z, (0, 2, 3) where z > x; barycentrics of (x, z).
            const double s = 0.5 * (x + 1.0), t = 0.5 * (z + 1.0);
            const std::array<std::pair<int, double>, 3> weights =
                x >= z ? std::array<std::pair<int, double>, 3>{{{0, 1.0 - s}, {1, s - t}, {2, t}}}
                       : std::array<std::pair<int, double>, 3>{{{0, 1.0 - t}, {2, s}, {3, t - s}}};
            // cos at the point times cos at the ceiling over r^2, both cosines h / r (h = 1).
            const glm::dvec3 to_q = glm::dvec3(x, 1.0, z) - point;
            const double r2 = glm::dot(to_q, to_q);
            const double kernel = albedo / kPi * step * step / (r2 * r2);
            for (const auto& [corner, weight] : weights) {
                for (int c = 0; c < kCoefficients; ++c) {
                    expected[std::size_t(c)] +=
                        kernel * weight * corner_transfer[std::size_t(corner)][std::size_t(c)];
                }
            }
        }
    }
    const double view_factor =
        rectangle_view_factor(-1.0 - point.x, 1.0 - point.x, -1.0 - point.z, 1.0 - point.z, 1.0);
    const double tolerance = binomial_tolerance(view_factor, transfer.rays);
    const Coefficients bounce = bounce_of(transfer, request, transfer.objects[0][0], 0, 0);
    for (int c = 0; c < kCoefficients; ++c) {
        double largest = 0.0;
        for (const Coefficients& corner : corner_transfer) {
            largest = std::max(largest, std::abs(corner[std::size_t(c)]));
        }
        EXPECT_NEAR(bounce[std::size_t(c)], expected[std::size_t(c)],
                    tolerance * albedo * largest + 1e-6)
            << "coefficient " << c;
    }
    std::printf("interpolated bounce: bounce_0 %.5f, integral %.5f; bounce_3 %.5f, integral %.5f\n",
                bounce[0], expected[0], bounce[3], expected[3]);
}

TEST(TransferBakeGround, SphereRestingOnTheGroundCastsItsViewFactor) {
    const float radius = 1.0f;
    const Mesh sphere =
        oer::testing::uv_sphere({0.0f, radius, 0.0f}, radius, 48, 24, glm::vec3(0.5f));
    TransferBakeOptions options;
    options.rays = 2304;
    const FrameRequest request = request_of({object_of(sphere)}, true);
    const SceneTransfer transfer = bake_transfer(request, options);
    ASSERT_TRUE(transfer.ground.has_value());
    const GroundTransfer& ground = *transfer.ground;
    EXPECT_EQ(ground.height, 0.0f);
    EXPECT_EQ(ground.centre, glm::vec2(0.0f));
    EXPECT_EQ(ground.resolution, 64);
    ASSERT_EQ(ground.points.count, 64u * 64u);
    // Far enough for the sphere's shadow: 2 scene radii (half the box's diagonal) each side.
    EXPECT_NEAR(ground.half_size, 2.0f * std::sqrt(3.0f) * radius, 1e-5f);

    // Every texel within 3 radii of the contact point against the sphere's view factor.
    const double texel = 2.0 * ground.half_size / ground.resolution;
    double worst = 0.0, sum = 0.0, sum_squares = 0.0;
    int compared = 0;
    for (int row = 0; row < ground.resolution; ++row) {
        for (int column = 0; column < ground.resolution; ++column) {
            const double x = -ground.half_size + (column + 0.5) * texel;
            const double z = -ground.half_size + (row + 0.5) * texel;
            const double d = std::sqrt(x * x + z * z);
            if (d > 3.0 * radius) {
                continue;
            }
            const double expected = 1.0 - sphere_view_factor(radius, d);
            const std::size_t index =
                std::size_t(row) * std::size_t(ground.resolution) + std::size_t(column);
            const double error = visible_fraction(direct_of(ground.points, index)) - expected;
            EXPECT_NEAR(error, 0.0, binomial_tolerance(expected, transfer.rays))
                << "texel at distance " << d;
            worst = std::max(worst, std::abs(error));
            sum += error;
            sum_squares += error * error;
            ++compared;
        }
    }
    const double mean = sum / compared, rms = std::sqrt(sum_squares / compared);
    std::printf(
        "ground under a sphere, %d texels, %d rays: visible fraction error worst %.4f, "
        "mean %.2g, rms %.4f\n",
        compared, transfer.rays, worst, mean, rms);
    // Independent texel errors: their mean is unbiased within the tolerance over sqrt(count),
    // and their RMS within the largest one-sigma binomial error (p = 1/2).
    EXPECT_LT(std::abs(mean), binomial_tolerance(0.5, transfer.rays) / std::sqrt(compared));
    EXPECT_LT(rms, binomial_tolerance(0.5, transfer.rays) / 3.0);

    // The corner texel, 4.9 radii out, is nearly open: the sphere covers 0.8 % of its
    // hemisphere, and it reflects at most that share of its brightest transfer. Each blocked
    // ray takes (pi / N) Y_i(w) from the open transfer, and |Y_lm| <= sqrt((2l + 1) / (4 pi))
    // (the addition theorem: the squares of band l sum to that everywhere).
    const double corner = std::sqrt(2.0) * (ground.half_size - 0.5 * texel);
    const double covered = sphere_view_factor(radius, corner);
    const double covered_bound = covered + binomial_tolerance(covered, transfer.rays);
    const Coefficients open = cosine_transfer({0.0, 1.0, 0.0});
    const float* direct = direct_of(ground.points, 0);
    for (int l = 0; l < kTransferBakeOrder; ++l) {
        const double largest_basis_value = std::sqrt((2.0 * l + 1.0) / (4.0 * kPi));
        for (int m = -l; m <= l; ++m) {
            const auto i = std::size_t(sh_index(l, m));
            EXPECT_NEAR(direct[i], open[i], covered_bound * kPi * largest_basis_value)
                << "coefficient " << i;
        }
    }
    for (int c = 0; c < 3; ++c) {
        const double bounce = bounce_of(transfer, request, ground.points, 0, c)[0];
        EXPECT_GE(bounce, 0.0f);
        EXPECT_LE(bounce, 0.5 * covered_bound * kPi * kY00);
    }

    // The sphere's top sees only the sky: the unoccluded transfer, and nothing reflected.
    const TransferPoints& points = transfer.objects[0][0];
    const Coefficients up = cosine_transfer({0.0, 1.0, 0.0});
    for (int i = 0; i < kCoefficients; ++i) {
        EXPECT_NEAR(direct_of(points, 0)[i], up[std::size_t(i)], 1e-6) << "coefficient " << i;
        EXPECT_EQ(bounce_of(transfer, request, points, 0, 0)[std::size_t(i)], 0.0);
    }
}

TEST(TransferBakeGround, BounceFollowsTheReflectorsAlbedo) {
    // A black sphere reflects nothing onto the ground. The ground's light is the lighting's below
    // the horizon (transfer_lighting.hpp): a ray from the sphere that meets it is not blocked,
    // so the convex sphere's equator has the unoccluded transfer, and what the ground reflects
    // beyond that is its departure from the open ground, darker in the sphere's shadow: less
    // than nothing, equally in every channel (albedo 0.8).
    const Mesh sphere = oer::testing::uv_sphere({0.0f, 1.0f, 0.0f}, 1.0f, 24, 12, glm::vec3(0.5f));
    TransferBakeOptions options;
    options.rays = 256;
    const FrameRequest request =
        request_of({object_of(sphere, glm::mat4(1.0f), glm::vec3(0.0f))}, true);
    const SceneTransfer transfer = bake_transfer(request, options);
    for (std::size_t p = 0; p < transfer.ground->points.count; ++p) {
        EXPECT_EQ(bounce_of(transfer, request, transfer.ground->points, p, 1)[0], 0.0);
    }
    const std::size_t equator = vertex_at(sphere.primitives[0], {1, 1, 0}, {1, 0, 0});
    const TransferPoints& points = transfer.objects[0][0];
    const Coefficients open = cosine_transfer({1.0, 0.0, 0.0});
    for (int i = 0; i < kCoefficients; ++i) {
        EXPECT_NEAR(direct_of(points, equator)[i], open[std::size_t(i)], 1e-6) << i;
    }
    const double red = bounce_of(transfer, request, points, equator, 0)[0];
    EXPECT_LT(red, 0.0);
    EXPECT_EQ(bounce_of(transfer, request, points, equator, 1)[0], red);
    EXPECT_EQ(bounce_of(transfer, request, points, equator, 2)[0], red);
}

// The bake traces the ground as the plane alone, behind every object: a face lying on the plane,
// or a ray that starts on it (the vertices where a product stands), meets the object, so the
// objects block exactly the rays they block without the ground, and the direct vectors are
// those of a bake without it. (Before, the drawn square stopped rays leaving a vertex on the
// plane at t = 0, and hid the open box's bottom face, coplanar with it, from rays inside.)
TEST(TransferBakeGround, TheGroundBlocksNothingThatObjectsBlock) {
    const Mesh box = oer::testing::open_box(0.5f, 0.4f, 0.02f, 4, glm::vec3(0.6f, 0.4f, 0.2f));
    const Mesh sphere = oer::testing::uv_sphere({0.9f, 0.3f, 0.0f}, 0.3f, 16, 8, glm::vec3(0.9f));
    const std::vector<SceneObject> objects = {object_of(box), object_of(sphere)};
    TransferBakeOptions options;
    options.rays = 64;
    options.bounce = Bounce::None;
    const SceneTransfer with_ground = bake_transfer(request_of(objects, true), options);
    const SceneTransfer without_ground = bake_transfer(request_of(objects, false), options);
    for (std::size_t o = 0; o < objects.size(); ++o) {
        for (std::size_t p = 0; p < with_ground.objects[o].size(); ++p) {
            EXPECT_EQ(with_ground.objects[o][p].direct, without_ground.objects[o][p].direct)
                << "object " << o << ", primitive " << p;
        }
    }
}

// Each object its own slots, weighed by the frame's colours: a Material slot per untextured
// material, else Native and Unit; past kMaxSeparateReflectors objects, one group per mesh and
// colour.
TEST(TransferBakeReflectors, SlotsPerObjectWeighedByItsColourMergedPastTheirLimit) {
    using Kind = ReflectorSlot::Kind;
    auto sphere = std::make_shared<const Mesh>(
        oer::testing::uv_sphere({0.0f, 0.5f, 0.0f}, 0.5f, 8, 4, glm::vec3(0.25f, 0.5f, 1.0f)));
    Mesh many = oer::testing::open_box(0.5f, 0.4f, 0.02f, 2, glm::vec3(0.5f));
    for (std::size_t p = 0; p < many.primitives.size(); ++p) {
        many.materials.push_back(oer::testing::lambertian(glm::vec3(0.1f * float(p + 1))));
        many.primitives[p].material = int(many.materials.size()) - 1;
    }
    many.materials.push_back(oer::testing::lambertian(glm::vec3(0.3f)));
    many.materials.push_back(oer::testing::lambertian(glm::vec3(0.7f)));
    many.primitives.push_back(many.primitives[0]);
    many.primitives.back().material = int(many.materials.size()) - 1;
    many.primitives.push_back(many.primitives[1]);
    many.primitives.back().material = int(many.materials.size()) - 2;
    FrameRequest request = request_of({{sphere, glm::mat4(1.0f), std::nullopt},
                                       {sphere, glm::mat4(1.0f), glm::vec3(1.0f, 0.0f, 0.0f)},
                                       object_of(many)},
                                      true);
    EXPECT_FALSE(reflectors_follow_colours(request));
    const std::vector<ReflectorSlot> slots = reflector_slots(request);
    ASSERT_EQ(slots.size(), 1u + 1u + 1u + 2u);
    EXPECT_EQ(slots[0].kind, Kind::Ground);
    EXPECT_EQ(slots[1].kind, Kind::Material);
    EXPECT_EQ(slots[1].objects, std::vector<std::uint32_t>{0});
    EXPECT_EQ(slots[2].objects, std::vector<std::uint32_t>{1});
    EXPECT_EQ(slots[3].kind, Kind::Native);  // 4 materials: past kMaxMaterialSlots
    EXPECT_EQ(slots[4].kind, Kind::Unit);
    EXPECT_EQ(bounce_vectors(slots), 1u + 1u + 1u + 3u + 1u);
    SceneTransfer transfer;
    transfer.reflectors = slots;
    std::vector<glm::vec3> weights = bounce_weights(transfer, request);
    EXPECT_EQ(weights[1], glm::vec3(0.25f, 0.5f, 1.0f));  // the material's own
    EXPECT_EQ(weights[2], glm::vec3(1.0f, 0.0f, 0.0f));   // the request's colour
    EXPECT_EQ(weights[3], glm::vec3(1.0f, 0.0f, 0.0f));   // Native, red: as baked
    EXPECT_EQ(weights[5], glm::vec3(0.0f, 0.0f, 1.0f));   // Native, blue
    EXPECT_EQ(weights[6], glm::vec3(0.0f));               // Unit: no colour of its own
    request.objects[2].base_color = glm::vec3(0.5f, 0.25f, 0.0f);
    weights = bounce_weights(transfer, request);
    EXPECT_EQ(weights[3], glm::vec3(0.0f));
    EXPECT_EQ(weights[6], glm::vec3(0.5f, 0.25f, 0.0f));
    EXPECT_EQ(object_bounce_vectors(*sphere), 1u);
    EXPECT_EQ(object_bounce_vectors(many), 4u);

    request.objects.clear();
    for (std::size_t i = 0; i <= kMaxSeparateReflectors; ++i) {
        const std::optional<glm::vec3> colour =
            i % 2 == 0 ? std::nullopt : std::optional<glm::vec3>(glm::vec3(0.5f));
        request.objects.push_back({sphere, glm::mat4(1.0f), colour});
    }
    EXPECT_TRUE(reflectors_follow_colours(request));
    const std::vector<ReflectorSlot> merged = reflector_slots(request);
    ASSERT_EQ(merged.size(), 1u + 2u);  // the ground; the uncoloured and the grey spheres
    EXPECT_EQ(merged[1].objects.size(), kMaxSeparateReflectors / 2 + 1);
    EXPECT_EQ(merged[2].objects.size(), kMaxSeparateReflectors / 2);
}

// A variant only re-weighs the slots: where it draws one material in place of each default one,
// a Material slot takes the albedo it draws; where it draws two in place of one, the object gets
// Native and Unit slots, and under that variant the Unit slot carries the mean albedo it draws.
TEST(TransferBakeReflectors, AVariantWeighsTheSlotsByTheMaterialsItDraws) {
    using Kind = ReflectorSlot::Kind;
    Mesh box = oer::testing::open_box(0.5f, 0.4f, 0.02f, 1, glm::vec3(0.5f));
    ASSERT_EQ(box.primitives.size(), 2u);
    box.materials.push_back(oer::testing::lambertian(glm::vec3(0.9f, 0.1f, 0.1f)));
    box.materials.push_back(oer::testing::lambertian(glm::vec3(0.1f, 0.1f, 0.9f)));
    box.variants = {"Red", "Blue"};
    for (Primitive& primitive : box.primitives) {
        primitive.variant_materials = {1, 2};
    }
    SceneObject object = object_of(box);
    object.variant = 0;
    FrameRequest request = request_of({object}, true);
    SceneTransfer transfer;
    transfer.reflectors = reflector_slots(request);
    ASSERT_EQ(transfer.reflectors.size(), 2u);
    EXPECT_EQ(transfer.reflectors[1].kind, Kind::Material);
    EXPECT_EQ(object_bounce_vectors(box), 1u);
    EXPECT_EQ(bounce_weights(transfer, request)[1], glm::vec3(0.9f, 0.1f, 0.1f));
    request.objects[0].variant = 1;
    EXPECT_EQ(bounce_weights(transfer, request)[1], glm::vec3(0.1f, 0.1f, 0.9f));
    request.objects[0].variant.reset();
    EXPECT_EQ(bounce_weights(transfer, request)[1], glm::vec3(0.5f));

    // Blue draws the second wall in red: two materials where the default draws one.
    Mesh split = box;
    split.primitives[1].variant_materials = {1, 1};
    request.objects[0] = object_of(split);
    request.objects[0].variant = 1;
    transfer.reflectors = reflector_slots(request);
    ASSERT_EQ(transfer.reflectors.size(), 3u);
    EXPECT_EQ(transfer.reflectors[1].kind, Kind::Native);
    EXPECT_EQ(transfer.reflectors[2].kind, Kind::Unit);
    EXPECT_EQ(object_bounce_vectors(split), 4u);
    const std::vector<glm::vec3> weights = bounce_weights(transfer, request);
    const float first = float(split.primitives[0].positions.size());
    const float second = float(split.primitives[1].positions.size());
    const glm::vec3 mean =
        (first * glm::vec3(0.1f, 0.1f, 0.9f) + second * glm::vec3(0.9f, 0.1f, 0.1f)) /
        (first + second);
    EXPECT_EQ(weights[1], glm::vec3(0.0f));  // Native: the default's albedos, not drawn
    EXPECT_NEAR(weights[4].r, mean.r, 1e-6f);
    EXPECT_NEAR(weights[4].b, mean.b, 1e-6f);
    request.objects[0].variant.reset();
    EXPECT_EQ(bounce_weights(transfer, request)[1], glm::vec3(1.0f, 0.0f, 0.0f));  // as filed
}

TEST(TransferBakeDeterminism, SameVectorsOnOneAndTwoThreads) {
    // The box's two primitives in four materials: its slots are Native and Unit.
    Mesh box = oer::testing::open_box(0.5f, 0.4f, 0.02f, 4, glm::vec3(0.6f, 0.4f, 0.2f));
    for (int m = 1; m <= 3; ++m) {
        box.materials.push_back(oer::testing::lambertian(glm::vec3(0.2f * float(m))));
    }
    // A second box beside the first, not coincident with it: which of two coincident
    // triangles a ray meets is Embree's choice, and may differ with its threads.
    for (std::size_t p = 0; p < 2; ++p) {
        Primitive copy = box.primitives[p];
        for (glm::vec3& position : copy.positions) {
            position.x += 1.2f;
        }
        copy.material = int(p) + 2;
        box.primitives.push_back(std::move(copy));
    }
    box.primitives[1].material = 1;
    const FrameRequest request =
        request_of({object_of(box, glm::translate(glm::mat4(1.0f), {0, 0.02f, 0}))}, true);
    ASSERT_EQ(reflector_slots(request).back().kind, ReflectorSlot::Kind::Unit);
    TransferBakeOptions options;
    options.rays = 100;
    options.threads = 1;
    const SceneTransfer one = bake_transfer(request, options);
    options.threads = 2;
    const SceneTransfer two = bake_transfer(request, options);
    ASSERT_EQ(one.objects.size(), two.objects.size());
    for (std::size_t p = 0; p < one.objects[0].size(); ++p) {
        EXPECT_EQ(one.objects[0][p].direct, two.objects[0][p].direct) << "primitive " << p;
        EXPECT_EQ(one.objects[0][p].bounce, two.objects[0][p].bounce) << "primitive " << p;
    }
    EXPECT_EQ(one.ground->points.direct, two.ground->points.direct);
    EXPECT_EQ(one.ground->points.bounce, two.ground->points.bounce);
    // Not an empty comparison: the box reflects light onto the ground.
    EXPECT_GT(max_abs(one.ground->points.bounce), 0.0);

    // The transfer's id leaves colours and variants out, so the bake draws the file's
    // materials whichever the frame that asked for it drew: the Native slot holds their albedos.
    FrameRequest recoloured = request;
    recoloured.objects[0].base_color = glm::vec3(0.9f, 0.0f, 0.0f);
    Mesh with_variant = *request.objects[0].mesh;
    with_variant.variants = {"Grey"};
    for (Primitive& primitive : with_variant.primitives) {
        primitive.variant_materials = {1};
    }
    FrameRequest varied = request;
    varied.objects[0].mesh = std::make_shared<const Mesh>(std::move(with_variant));
    varied.objects[0].variant = 0;
    for (const FrameRequest* other : {&recoloured, &varied}) {
        const SceneTransfer asked = bake_transfer(*other, options);
        for (std::size_t p = 0; p < one.objects[0].size(); ++p) {
            EXPECT_EQ(one.objects[0][p].bounce, asked.objects[0][p].bounce) << "primitive " << p;
        }
        EXPECT_EQ(one.ground->points.bounce, asked.ground->points.bounce);
    }
}

TEST(TransferBakeRules, RaysFollowTheReceiverCount) {
    const Mesh small = oer::testing::uv_sphere({0, 0, 0}, 1.0f, 16, 8, glm::vec3(0.5f));
    EXPECT_EQ(transfer_ray_count({object_of(small)}), 1024);
    Mesh huge;
    huge.primitives.resize(1);
    huge.primitives[0].positions.resize(2'000'000);
    EXPECT_EQ(transfer_ray_count({object_of(huge)}), 64);
    int previous = 1 << 20;
    for (const std::size_t vertices : {1000u, 10000u, 35947u, 100000u, 300000u}) {
        Mesh mesh;
        mesh.primitives.resize(1);
        mesh.primitives[0].positions.resize(vertices);
        const int rays = transfer_ray_count({object_of(std::move(mesh))});
        const int strata = int(std::lround(std::sqrt(rays)));
        EXPECT_EQ(strata * strata, rays) << vertices << " vertices";
        EXPECT_LE(rays, previous) << vertices << " vertices";
        previous = rays;
    }
}

TEST(TransferBakeRules, RequestedRaysRoundDownToASquare) {
    const Mesh sphere = oer::testing::uv_sphere({0, 0, 0}, 1.0f, 8, 4, glm::vec3(0.5f));
    TransferBakeOptions options;
    options.bounce = Bounce::None;
    options.rays = 70;
    EXPECT_EQ(bake_transfer(request_of({object_of(sphere)}, false), options).rays, 64);
}

TEST(TransferBakeRules, OrderIsTheRigsAtMostTheBakes) {
    Rig rig;
    rig.sh.all = ShRgb(3);
    EXPECT_EQ(transfer_order(rig), 3);
    rig.sh.all = ShRgb(9);
    EXPECT_EQ(transfer_order(rig), kTransferBakeOrder);
    rig.sh.all = ShRgb(1);
    EXPECT_EQ(transfer_order(rig), 1);
}

TEST(TransferBakeRules, RequestWithoutObjectsIsInvalid) {
    try {
        bake_transfer(FrameRequest{}, {});
        FAIL() << "baked a request without objects";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
    }
}
