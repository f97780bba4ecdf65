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

// The room around the soft-boxes: a light, neutral grey, brighter towards the ceiling, after
// three.js's RoomEnvironment (examples/jsm/environments/RoomEnvironment.js, from model-viewer's
// EnvironmentScene), whose white room lit by a ceiling lamp surrounds its six area lights at
// about 1/50 of their radiance. An even surround lights every side of a product and shows as
// a grey backdrop (the old dim gradient, 0.02 to 0.08, showed near black); linear in the
// direction's y between these three. Brighter, it would flatten the product: the floor the
// renderer adds reflects the room and the soft-boxes back up at it.
constexpr glm::dvec3 kRoomFloor{0.18, 0.18, 0.18};    // straight down (-Y)
constexpr glm::dvec3 kRoomWalls{0.30, 0.30, 0.30};    // the horizon
constexpr glm::dvec3 kRoomCeiling{0.38, 0.38, 0.38};  // straight up (+Y)

glm::dvec3 room(double y) {
    return y < 0.0 ? kRoomWalls + (kRoomFloor - kRoomWalls) * -y
                   : kRoomWalls + (kRoomCeiling - kRoomWalls) * y;
}

}  // namespace

std::vector<DefaultStudioLight> default_environment_lights() {
    // Placed as a product photographer's three soft-boxes (and as RoomEnvironment's front, side
    // and back area lights): the key above and beside the default camera, a fill low on the
    // other side, a rim behind. The radiances make a white Lambertian product white but not
    // clipped at 0 EV under the neutral tone map (tests/integration/default_exposure_test.cpp);
    // the sizes keep the three discs within the top 1 % of the map's pixels, which light
    // location clusters (docs/design.md section 2), so that each is found as a light.
    return {
        // Key: large warm soft-box up and front-left, azimuth -40 deg, elevation 35 deg:
        // direction (-0.5265, 0.5736, 0.6275), angular radius 10 deg (20 deg wide),
        // radiance 28 * (1.0, 0.96, 0.9) = (28, 26.88, 25.2).
        {"key", from_angles(-40.0, 35.0), degrees(10.0), {28.0f, 26.88f, 25.2f}},
        // Fill: smaller cool soft-box low on the other side, azimuth 60 deg, elevation 15 deg:
        // direction (0.8365, 0.2588, 0.4830), angular radius 7 deg (14 deg wide),
        // radiance 8 * (0.9, 0.95, 1.0) = (7.2, 7.6, 8).
        {"fill", from_angles(60.0, 15.0), degrees(7.0), {7.2f, 7.6f, 8.0f}},
        // Rim: small bright neutral soft-box behind and above, azimuth 165 deg, elevation 50 deg:
        // direction (0.1664, 0.7660, -0.6209), angular radius 4 deg (8 deg wide),
        // radiance (40, 40, 40).
        {"rim", from_angles(165.0, 50.0), degrees(4.0), {40.0f, 40.0f, 40.0f}},
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
        const glm::dvec3 background = room(grid.row_cos_theta[y]);
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
