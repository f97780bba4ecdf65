#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "oer/image/image_io.hpp"
#include "oer/lighting/irradiance.hpp"
#include "oer/lighting/reference_irradiance.hpp"
#include "oer/lighting/sh_projection.hpp"

using namespace oer;

namespace {

// Relative RMS error over the sphere of the order-N SH truncation of a point light's clamped
// cosine max(0, n.d): sqrt(1 - captured energy), with the energy of band l
// a_l^2 2 / (2l + 1), a_l = (2l + 1) A_l / (4 pi), against the total integral of
// max(0, t)^2 over [-1, 1], 1/3. For N = 3 this is
// sqrt(1 - 0.99219) = 8.84 % (Basri and Jacobs: 9 coefficients capture 99.2 % of the energy).
double point_light_error(int order) {
    double captured = 0.0;
    for (int l = 0; l < order; ++l) {
        const double a = (2.0 * l + 1.0) * lambertian_band_factor(l) / (4.0 * std::numbers::pi);
        captured += a * a * 2.0 / (2.0 * l + 1.0);
    }
    return std::sqrt(1.0 - captured / (1.0 / 3.0));
}

// Order-3 relative RMS error measured on each map (below), the map's own figure.
const std::map<std::string, double> kMeasuredOrder3Error = {
    {"city", 0.0347},  {"courtyard", 0.0375}, {"forest", 0.0245},  {"interior", 0.0299},
    {"night", 0.0356}, {"studio", 0.0750},    {"sunrise", 0.0675}, {"sunset", 0.0142},
};
// Each map is bounded near its own figure: a 25 % margin for the order-3 error.
constexpr double kOrder3Margin = 1.25;

}  // namespace

// Order-3 SH irradiance against the exact brute-force irradiance on Blender's HDR worlds
// (package blender-data, 1024x512 each), relative RMS error over 1024 Fibonacci normals.
// Measured (orders 3 / 5 / 9):
//   city 3.47 / 1.50 / 0.57 %     courtyard 3.75 / 0.95 / 0.19 %   forest 2.45 / 1.06 / 0.32 %
//   interior 2.99 / 1.59 / 0.72 % night 3.56 / 2.01 / 0.70 %       studio 7.50 / 3.11 / 1.12 %
//   sunrise 6.75 / 3.22 / 1.35 %  sunset 1.42 / 0.45 / 0.13 %
// Ramamoorthi and Hanrahan's "about 1 %" is a share of energy (the square of this figure:
// studio's 7.5 % RMS is 0.56 % of the energy); in RMS terms maps dominated by a small sun
// approach the point-light limit of 8.84 %, the bound every map must stay under; each map is
// also held to 1.25 times its own measured order-3 figure, and must converge with the order
// (which also checks that projection and reference agree).
TEST(RealHdrIrradiance, ShIrradianceAgainstExactOnBlenderWorldsSlow) {
    const std::filesystem::path directory = "/usr/share/blender/datafiles/studiolights/world";
    std::vector<std::filesystem::path> maps;
    if (std::filesystem::is_directory(directory)) {
        for (const auto& entry : std::filesystem::directory_iterator(directory)) {
            if (entry.path().extension() == ".exr") {
                maps.push_back(entry.path());
            }
        }
    }
    if (maps.empty()) {
        GTEST_SKIP() << "*** NO REAL HDR WORLDS in " << directory
                     << ": install the Debian package blender-data to run this test ***";
    }
    std::sort(maps.begin(), maps.end());
    const double bound = point_light_error(3);
    ASSERT_NEAR(bound, 0.0884, 1e-4);
    const std::vector<glm::dvec3> normals = fibonacci_sphere(1024);
    for (const std::filesystem::path& path : maps) {
        const HdrImage image = load_image_file(path.string()).image;
        const std::vector<glm::dvec3> exact = ReferenceIrradiance(image).at(normals);
        const ShProjection projection = project_environment(image, {}, 9);
        std::array<double, 3> errors{};
        const std::array<int, 3> orders = {3, 5, 9};
        for (std::size_t i = 0; i < orders.size(); ++i) {
            const ShRgb irradiance = irradiance_coefficients(projection.all.truncated(orders[i]));
            std::vector<glm::dvec3> sh;
            for (const glm::dvec3& n : normals) {
                sh.push_back(irradiance.evaluate(n));
            }
            errors[i] = relative_rms_error(sh, exact);
        }
        std::printf(
            "%-14s %dx%d: SH irradiance relative RMS error, order 3 %.2f %%, "
            "5 %.2f %%, 9 %.2f %%\n",
            path.filename().string().c_str(), image.width, image.height, 100.0 * errors[0],
            100.0 * errors[1], 100.0 * errors[2]);
        EXPECT_LT(errors[0], bound) << path;
        const auto measured = kMeasuredOrder3Error.find(path.stem().string());
        ASSERT_NE(measured, kMeasuredOrder3Error.end())
            << path << ": a world without a measured figure; add it to kMeasuredOrder3Error";
        EXPECT_LT(errors[0], kOrder3Margin * measured->second) << path;
        EXPECT_LT(errors[1], errors[0]) << path;
        EXPECT_LT(errors[2], errors[1]) << path;
        EXPECT_LT(errors[2], 0.02) << path;
    }
}
