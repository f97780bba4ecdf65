// The built-in studio environment (see oer/default_environment.hpp), generated per pixel from
// directions so that the soft-boxes are round on the sphere and the map has no seam.
#include "oer/lighting/default_environment.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"

namespace oer {

namespace {

using std::numbers::pi;

constexpr int kMaxSize = 32768;

// Azimuth is measured from +Z (towards a default camera in front of the product) turning
// towards +X (the camera's right); elevation from the horizon towards +Y.
glm::dvec3 from_angles(double azimuth_degrees, double elevation_degrees) {
    const double a = azimuth_degrees * pi / 180.0, e = elevation_degrees * pi / 180.0;
    return {std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a)};
}

constexpr double degrees(double d) {
    return d * pi / 180.0;
}

// The edge of a soft-box: full radiance out to kInner * radius, none beyond kOuter * radius,
// smoothstep between (half radiance at the documented radius).
constexpr double kInner = 0.85;
constexpr double kOuter = 1.15;

// The dim gradient behind the soft-boxes: warm floor, cool ceiling.
constexpr glm::dvec3 kFloor{0.020, 0.018, 0.016};    // straight down (-Y)
constexpr glm::dvec3 kCeiling{0.064, 0.072, 0.080};  // straight up (+Y)

}  // namespace

std::vector<DefaultStudioLight> default_environment_lights() {
    return {
        // Key: large warm soft-box up and front-left, azimuth -45 deg, elevation 40 deg:
        // direction (-0.5417, 0.6428, 0.5417), angular radius 10 deg (20 deg wide),
        // radiance 50 * (1.0, 0.85, 0.7) = (50, 42.5, 35).
        {"key", from_angles(-45.0, 40.0), degrees(10.0), {50.0f, 42.5f, 35.0f}},
        // Fill: smaller cool soft-box low on the other side, azimuth 55 deg, elevation 10 deg:
        // direction (0.8067, 0.1736, 0.5649), angular radius 6 deg (12 deg wide),
        // radiance 18 * (0.7, 0.85, 1.0) = (12.6, 15.3, 18).
        {"fill", from_angles(55.0, 10.0), degrees(6.0), {12.6f, 15.3f, 18.0f}},
        // Rim: small bright neutral light behind and above, azimuth 165 deg, elevation 50 deg:
        // direction (0.1664, 0.7660, -0.6209), angular radius 3 deg (6 deg wide),
        // radiance (180, 180, 180).
        {"rim", from_angles(165.0, 50.0), degrees(3.0), {180.0f, 180.0f, 180.0f}},
    };
}

HdrImage make_default_environment(int width, int height) {
    if (width < 1 || height < 1 || width > kMaxSize || height > kMaxSize) {
        throw Error(ErrorKind::InvalidInput, "default environment: size " + std::to_string(width) +
                                                 "x" + std::to_string(height) + " is outside [1, " +
                                                 std::to_string(kMaxSize) + "]");
    }
    struct Box {
        glm::dvec3 direction;
        double cos_inner, cos_outer, inner, outer;
        glm::dvec3 radiance;
    };
    std::vector<Box> boxes;
    for (const DefaultStudioLight& light : default_environment_lights()) {
        const double inner = kInner * light.angular_radius, outer = kOuter * light.angular_radius;
        boxes.push_back({light.direction, std::cos(inner), std::cos(outer), inner, outer,
                         glm::dvec3(light.radiance)});
    }

    HdrImage image(width, height);
    const equirect::Grid grid(width, height);
    for (int y = 0; y < height; ++y) {
        const double t = 0.5 * (grid.row_cos_theta[y] + 1.0);  // 0 straight down, 1 up
        const glm::dvec3 background = kFloor + (kCeiling - kFloor) * t;
        for (int x = 0; x < width; ++x) {
            const glm::dvec3 d = grid.direction(x, y);
            glm::dvec3 value = background;
            for (const Box& box : boxes) {
                const double c = glm::dot(d, box.direction);
                if (c <= box.cos_outer) {
                    continue;
                }
                double weight = 1.0;
                if (c < box.cos_inner) {
                    const double angle = std::acos(std::min(c, 1.0));
                    const double s = (angle - box.inner) / (box.outer - box.inner);
                    weight = 1.0 - s * s * (3.0 - 2.0 * s);  // 1 - smoothstep
                }
                value += box.radiance * weight;
            }
            float* p = image.at(x, y);
            p[0] = float(value.x), p[1] = float(value.y), p[2] = float(value.z);
        }
    }
    return image;
}

}  // namespace oer
