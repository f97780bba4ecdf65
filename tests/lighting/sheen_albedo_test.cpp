// The sheen lobe's directional albedo table (sheen_albedo.hpp) against the same integral done
// another way: KHR_materials_sheen's BRDF written out here (Estevez and Kulla's Charlie D and
// the extension's fitted visibility) and integrated by a fine midpoint rule over the hemisphere
// of light directions, with no importance sampling; and the bounds every entry keeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "directions.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/sheen_albedo.hpp"

using namespace oer;
using std::numbers::pi;

namespace {

// The extension's "Sheen visibility": lambda(x) = exp(L(x)) below 0.5, exp(2 L(0.5) - L(1 - x))
// above, L(x) = a / (1 + b x^c) + d x + e interpolated in (1 - alpha)^2.
double lambda(double x, double alpha) {
    const double t = (1.0 - alpha) * (1.0 - alpha);
    const auto fit = [&](double y) {
        const double a = 21.5473 + (25.3245 - 21.5473) * t;
        const double b = 3.82987 + (3.32435 - 3.82987) * t;
        const double c = 0.19823 + (0.16801 - 0.19823) * t;
        const double d = -1.97760 + (-1.27393 + 1.97760) * t;
        const double e = -4.32054 + (-4.85967 + 4.32054) * t;
        return a / (1.0 + b * std::pow(y, c)) + d * y + e;
    };
    return x < 0.5 ? std::exp(fit(x)) : std::exp(2.0 * fit(0.5) - fit(1.0 - x));
}

double sheen_integral(double n_dot_v, double roughness, int rows, int columns) {
    const double alpha = roughness * roughness;
    const glm::dvec3 v(std::sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    return oer::testing::hemisphere_integral<double>(rows, columns, [&](const glm::dvec3& l) {
        const glm::dvec3 h = glm::normalize(l + v);
        const double sin2_h = 1.0 - h.z * h.z;
        const double d = (2.0 + 1.0 / alpha) * std::pow(sin2_h, 0.5 / alpha) / (2.0 * pi);
        const double visibility =
            1.0 / ((1.0 + lambda(n_dot_v, alpha) + lambda(l.z, alpha)) * 4.0 * n_dot_v * l.z);
        return d * visibility * l.z;
    });
}

}  // namespace

// Within 2 % (and 0.002) of the quadrature at the table's texel centres, for roughness from 0.2
// (below it the lobe narrows to grazing half vectors that the midpoint rule's cells miss).
TEST(SheenAlbedo, EveryEntryAgreesWithABruteForceQuadrature) {
    const int size = 16;
    const SheenAlbedoTable table = sheen_albedo_table(size, 1024);
    double worst = 0.0;
    for (int j = 3; j < size; j += 3) {
        for (int i = 0; i < size; i += 3) {
            const double n_dot_v = (i + 0.5) / size, roughness = (j + 0.5) / size;
            // The table holds at most 1 (sheen_albedo.hpp).
            const double want = std::min(1.0, sheen_integral(n_dot_v, roughness, 512, 256));
            const double got = table.albedo[std::size_t(j * size + i)];
            worst = std::max(worst, std::abs(got - want) / std::max(want, 0.1));
            EXPECT_NEAR(got, want, 0.02 * want + 0.002)
                << "n.v " << n_dot_v << " roughness " << roughness;
        }
    }
    std::printf("[ measured ] sheen albedo table against the quadrature: worst %.4f relative\n",
                worst);
}

// An albedo: positive and at most 1 everywhere (a white sheen never reflects more than arrives;
// the fit's excess at grazing view is clamped), largest at grazing view, as a sheen's rim is;
// sample_sheen_albedo reads the texel centres.
TEST(SheenAlbedo, AlbedosStayWithinOneAndRiseTowardsGrazing) {
    const SheenAlbedoTable table = sheen_albedo_table(32, 1024);
    for (float value : table.albedo) {
        EXPECT_GT(value, 0.0f);
        EXPECT_LE(value, 1.0f);
    }
    for (double roughness : {0.25, 0.5, 1.0}) {
        EXPECT_GT(sample_sheen_albedo(table, 0.1, roughness),
                  sample_sheen_albedo(table, 0.9, roughness))
            << roughness;
    }
    EXPECT_EQ(sample_sheen_albedo(table, 0.5 / 32, 0.5 / 32), double(table.albedo[0]));
    EXPECT_THROW(sheen_albedo_table(1, 16), Error);
    EXPECT_THROW(sheen_albedo_table(32, 0), Error);
}
