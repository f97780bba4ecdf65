#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/environment_layouts.hpp"
#include "oer/lighting/environment_source.hpp"
#include "oer/lighting/equirect.hpp"

using namespace oer;
using std::numbers::pi;

namespace {

// A smooth known environment: each channel is an affine function of the direction.
glm::vec3 f(const glm::dvec3& d) {
    return glm::vec3(0.5 + 0.5 * d.x, 0.5 + 0.5 * d.y, 0.5 + 0.5 * d.z);
}

// Direction of texel (a, b) of cube face `face` (order +X, -X, +Y, -Y, +Z, -Z), from the
// OpenGL table (specification section 8.13), written out independently of the library:
// sc = 2 s - 1, tc = 2 t - 1 with s = (a + 0.5) / n, t = (b + 0.5) / n (t = 0 on the top row).
glm::dvec3 face_texel_direction(int face, double a, double b, int n) {
    const double sc = 2.0 * (a + 0.5) / n - 1.0;
    const double tc = 2.0 * (b + 0.5) / n - 1.0;
    glm::dvec3 d;
    switch (face) {
        case 0:
            d = {1.0, -tc, -sc};
            break;  // +X: sc = -z, tc = -y
        case 1:
            d = {-1.0, -tc, sc};
            break;  // -X: sc = +z, tc = -y
        case 2:
            d = {sc, 1.0, tc};
            break;  // +Y: sc = +x, tc = +z
        case 3:
            d = {sc, -1.0, -tc};
            break;  // -Y: sc = +x, tc = -z
        case 4:
            d = {sc, -tc, 1.0};
            break;  // +Z: sc = +x, tc = -y
        default:
            d = {-sc, -tc, -1.0};
            break;  // -Z: sc = -x, tc = -y
    }
    return glm::normalize(d);
}

std::array<HdrImage, 6> render_faces(int n, const std::function<glm::vec3(int, glm::dvec3)>& g) {
    std::array<HdrImage, 6> faces;
    for (int face = 0; face < 6; ++face) {
        faces[face] = HdrImage(n, n);
        for (int b = 0; b < n; ++b) {
            for (int a = 0; a < n; ++a) {
                const glm::vec3 v = g(face, face_texel_direction(face, a, b, n));
                float* p = faces[face].at(a, b);
                p[0] = v.x, p[1] = v.y, p[2] = v.z;
            }
        }
    }
    return faces;
}

std::array<const HdrImage*, 6> pointers(const std::array<HdrImage, 6>& faces) {
    std::array<const HdrImage*, 6> p{};
    for (int i = 0; i < 6; ++i) {
        p[i] = &faces[i];
    }
    return p;
}

// Pastes face into cell (cx, cy) of a cross, optionally rotated by 180 degrees.
void paste(HdrImage& cross, const HdrImage& face, int cx, int cy, bool rotate) {
    const int n = face.width;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const float* s = rotate ? face.at(n - 1 - x, n - 1 - y) : face.at(x, y);
            float* d = cross.at(cx * n + x, cy * n + y);
            d[0] = s[0], d[1] = s[1], d[2] = s[2];
        }
    }
}

struct ErrorStats {
    double max = 0.0;
    double mean = 0.0;
};

// Compares every output pixel with f at that pixel's direction, skipping the directions for
// which skip() holds.
ErrorStats compare_with_f(const HdrImage& out, const std::function<bool(glm::dvec3)>& skip = {}) {
    ErrorStats stats;
    std::size_t count = 0;
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            const glm::dvec3 d = equirect::pixel_direction(x, y, out.width, out.height);
            if (skip && skip(d)) {
                continue;
            }
            const glm::vec3 expected = f(d);
            const float* p = out.at(x, y);
            for (int c = 0; c < 3; ++c) {
                const double e = std::abs(double(p[c]) - expected[c]);
                stats.max = std::max(stats.max, e);
                stats.mean += e;
            }
            ++count;
        }
    }
    stats.mean /= double(3 * count);
    return stats;
}

void expect_invalid(const std::function<void()>& body, const std::string& needle) {
    try {
        body();
        ADD_FAILURE() << "no error for: " << needle;
    } catch (const Error& e) {
        EXPECT_EQ(int(e.kind()), int(ErrorKind::InvalidInput)) << e.what();
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

// Error bounds for n = 64 faces. Inside a face, bilinear interpolation of the smooth f (f is
// linear in the direction, the direction is smooth in the face coordinates) errs by about
// h^2 / 8 * |f''| with h = 2 / n: ~1e-4. Within half a texel of a face edge the lookup is
// clamped to the edge texel: an error of up to |grad f| * (half a texel's angle there)
// = 0.5 * (1 / n) / 2 ~ 4e-3 (measured: 2.8e-3). Those edge bands are thin, so the mean error
// is far smaller (measured: 4e-5).
constexpr int kFace = 64;
constexpr double kMaxError = 5e-3;
constexpr double kMeanError = 2e-4;

}  // namespace

TEST(EnvironmentLayouts, CubeFacesResampleToTheKnownFunction) {
    const auto faces = render_faces(kFace, [](int, glm::dvec3 d) { return f(d); });
    const HdrImage out = equirect_from_cube_faces(pointers(faces), 256);
    ASSERT_EQ(out.width, 256);
    ASSERT_EQ(out.height, 128);
    const ErrorStats e = compare_with_f(out);
    EXPECT_LT(e.max, kMaxError);
    EXPECT_LT(e.mean, kMeanError);
}

TEST(EnvironmentLayouts, PlusXFaceLandsAtTheImageCentreUnmirrored) {
    // Only +X is lit, and only its upper-right quadrant (s > 1/2, t < 1/2), which per the
    // table is z < 0 and y > 0: in the equirect that is up and left of the centre (+X).
    const int n = 32;
    const auto faces =
        render_faces(n, [](int face, glm::dvec3) { return glm::vec3(face == 0 ? 1.0f : 0.0f); });
    std::array<HdrImage, 6> quadrant = faces;
    for (int b = 0; b < n; ++b) {
        for (int a = 0; a < n; ++a) {
            if (!(a >= n / 2 && b < n / 2)) {
                quadrant[0].at(a, b)[0] = quadrant[0].at(a, b)[1] = quadrant[0].at(a, b)[2] = 0;
            }
        }
    }
    const int w = 512, h = 256;
    const HdrImage whole = equirect_from_cube_faces(pointers(faces), w);
    EXPECT_NEAR(whole.at(w / 2, h / 2)[0], 1.0f, 1e-6f);      // +X
    EXPECT_NEAR(whole.at(w / 4, h / 2)[0], 0.0f, 1e-6f);      // -Z
    EXPECT_NEAR(whole.at(3 * w / 4, h / 2)[0], 0.0f, 1e-6f);  // +Z
    EXPECT_NEAR(whole.at(0, h / 2)[0], 0.0f, 1e-6f);          // -X
    // Lit pixels are those within the +X cube's frustum, centred on the image centre.
    double sum = 0, sx = 0, sy = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const double v = whole.at(x, y)[0];
            sum += v, sx += v * (x + 0.5), sy += v * (y + 0.5);
        }
    }
    ASSERT_GT(sum, 0.0);
    EXPECT_NEAR(sx / sum, w / 2.0, 1.0);
    EXPECT_NEAR(sy / sum, h / 2.0, 1.0);

    const HdrImage part = equirect_from_cube_faces(pointers(quadrant), w);
    sum = sx = sy = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const double v = part.at(x, y)[0];
            sum += v, sx += v * (x + 0.5), sy += v * (y + 0.5);
        }
    }
    ASSERT_GT(sum, 0.0);
    EXPECT_LT(sx / sum, w / 2.0 - 10.0) << "the quadrant z < 0 must lie left of the centre";
    EXPECT_LT(sy / sum, h / 2.0 - 10.0) << "the quadrant y > 0 must lie above the centre";
    const glm::dvec3 centroid = equirect::direction_at(sx / sum, sy / sum, w, h);
    EXPECT_GT(centroid.x, 0.7);
    EXPECT_LT(centroid.z, -0.2);
    EXPECT_GT(centroid.y, 0.2);
}

TEST(EnvironmentLayouts, HorizontalCrossMatchesFacesAndFunction) {
    const auto faces = render_faces(kFace, [](int, glm::dvec3 d) { return f(d); });
    HdrImage cross(4 * kFace, 3 * kFace);
    std::fill(cross.pixels.begin(), cross.pixels.end(), -100.0f);  // empty cells: never read
    paste(cross, faces[2], 1, 0, false);                           // +Y
    paste(cross, faces[1], 0, 1, false);                           // -X
    paste(cross, faces[4], 1, 1, false);                           // +Z
    paste(cross, faces[0], 2, 1, false);                           // +X
    paste(cross, faces[5], 3, 1, false);                           // -Z
    paste(cross, faces[3], 1, 2, false);                           // -Y
    const HdrImage out = equirect_from_cross(cross, 256);
    EXPECT_EQ(out.pixels, equirect_from_cube_faces(pointers(faces), 256).pixels);
    const ErrorStats e = compare_with_f(out);
    EXPECT_LT(e.max, kMaxError);
    EXPECT_LT(e.mean, kMeanError);
}

TEST(EnvironmentLayouts, VerticalCrossMatchesFacesAndFunction) {
    const auto faces = render_faces(kFace, [](int, glm::dvec3 d) { return f(d); });
    HdrImage cross(3 * kFace, 4 * kFace);
    std::fill(cross.pixels.begin(), cross.pixels.end(), -100.0f);
    paste(cross, faces[2], 1, 0, false);  // +Y
    paste(cross, faces[1], 0, 1, false);  // -X
    paste(cross, faces[4], 1, 1, false);  // +Z
    paste(cross, faces[0], 2, 1, false);  // +X
    paste(cross, faces[3], 1, 2, false);  // -Y
    paste(cross, faces[5], 1, 3, true);   // -Z, upside down
    const HdrImage out = equirect_from_cross(cross, 256);
    EXPECT_EQ(out.pixels, equirect_from_cube_faces(pointers(faces), 256).pixels);
    const ErrorStats e = compare_with_f(out);
    EXPECT_LT(e.max, kMaxError);
    EXPECT_LT(e.mean, kMeanError);
}

TEST(EnvironmentLayouts, MirrorBallResamplesToTheKnownFunction) {
    // The probe as a camera looking down -Z sees it: image point (u, v), v up, normal
    // n = (u, v, sqrt(1 - u^2 - v^2)), reflected direction r = 2 (n . e) n - e, e = +Z.
    const int size = 512;
    HdrImage probe(size, size);
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            const double u = 2.0 * (i + 0.5) / size - 1.0;
            const double v = 1.0 - 2.0 * (j + 0.5) / size;
            const double rr = u * u + v * v;
            if (rr > 1.0) {
                continue;  // outside the ball: black
            }
            const glm::dvec3 n(u, v, std::sqrt(1.0 - rr));
            const glm::dvec3 r = 2.0 * n.z * n - glm::dvec3(0, 0, 1);
            const glm::vec3 value = f(r);
            float* p = probe.at(i, j);
            p[0] = value.x, p[1] = value.y, p[2] = value.z;
        }
    }
    const HdrImage out = equirect_from_mirror_ball(probe, 256);
    ASSERT_EQ(out.height, 128);
    // A direction at angle g from -Z is imaged at radius cos(g / 2): towards -Z the ball
    // compresses the sphere into its rim (singular at -Z itself, whose preimage is the whole
    // rim), and the texels there also mix with the black outside. Skip within 20 degrees of
    // -Z (radius > cos(10 deg) = 0.985, the outer 1.5 % of the radius); elsewhere a probe
    // texel spans at most ~0.02 rad and bilinear interpolation of f errs by ~1e-4 at worst
    // (measured: 3.5e-4 at the 20 degree ring, 4e-5 beyond 45 degrees).
    const double skip_cos = std::cos(20.0 * pi / 180.0);
    const ErrorStats e = compare_with_f(out, [&](glm::dvec3 d) {
        return glm::dot(d, {0.0, 0.0, -1.0}) > skip_cos;
    });
    EXPECT_LT(e.max, kMaxError);
    EXPECT_LT(e.mean, kMeanError);
    // The front (+Z) is the ball's centre, +X its right, +Y its top.
    const glm::dvec2 front = equirect::position_of({0, 0, 1}, 256, 128);
    EXPECT_NEAR(out.at(int(front.x), int(front.y))[2], 1.0f, 1e-2f);
}

TEST(EnvironmentLayouts, InvalidInputsAreRejected) {
    const auto faces = render_faces(8, [](int, glm::dvec3 d) { return f(d); });
    auto p = pointers(faces);
    expect_invalid([&] { equirect_from_cube_faces(p, 1); }, "width");
    auto missing = p;
    missing[3] = nullptr;
    expect_invalid([&] { equirect_from_cube_faces(missing, 64); }, "-Y is missing");
    HdrImage oblong(8, 9);
    auto not_square = p;
    not_square[4] = &oblong;
    expect_invalid([&] { equirect_from_cube_faces(not_square, 64); }, "+Z is not square");
    HdrImage small(4, 4);
    auto mixed = p;
    mixed[5] = &small;
    expect_invalid([&] { equirect_from_cube_faces(mixed, 64); }, "-Z is 4 pixels wide");

    expect_invalid([&] { equirect_from_cross(HdrImage(40, 40), 64); }, "4:3");
    expect_invalid([&] { equirect_from_cross(HdrImage(), 64); }, "empty");
    expect_invalid([&] { equirect_from_mirror_ball(HdrImage(20, 10), 64); }, "square");
    HdrImage inconsistent(4, 4);
    inconsistent.pixels.resize(3);
    expect_invalid([&] { equirect_from_mirror_ball(inconsistent, 64); }, "values");
}

TEST(EnvironmentLayoutsSource, DecodesSixEncodedFacesLikeTheFacesThemselves) {
    const int n = 16;
    const auto faces = render_faces(n, [](int, glm::dvec3 d) { return f(d); });
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("oer-source-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::array<std::vector<std::byte>, 6> bytes;
    std::vector<EncodedImage> encoded;
    for (int i = 0; i < 6; ++i) {
        const std::filesystem::path path = dir / ("face" + std::to_string(i) + ".exr");
        write_image_file(faces[i], path.string());
        std::ifstream in(path, std::ios::binary);
        const std::string content{std::istreambuf_iterator<char>(in), {}};
        bytes[i].resize(content.size());
        std::memcpy(bytes[i].data(), content.data(), content.size());
        encoded.push_back({path.filename().string(), bytes[i]});
    }
    std::filesystem::remove_all(dir);

    const LoadedImage decoded = decode_environment(encoded, EnvironmentLayout::CubeFaces, {});
    const HdrImage direct = equirect_from_cube_faces(pointers(faces), 4 * n);
    ASSERT_EQ(decoded.image.width, 4 * n);
    ASSERT_EQ(decoded.image.height, 2 * n);
    EXPECT_EQ(decoded.image.pixels, direct.pixels);

    // Six images for cube faces, one for the other layouts; a pixel limit on the output.
    EXPECT_THROW(decode_environment(std::span(encoded).first(5), EnvironmentLayout::CubeFaces, {}),
                 Error);
    EXPECT_THROW(decode_environment(encoded, EnvironmentLayout::Equirect, {}), Error);
    ImageLimits small;
    small.max_pixels = 4 * n * 2 * n - 1;
    try {
        decode_environment(encoded, EnvironmentLayout::CubeFaces, small);
        ADD_FAILURE() << "the resampled map exceeds the pixel limit";
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::LimitExceeded) << error.what();
    }
}

TEST(EnvironmentLayoutsSource, LayoutNamesRoundTrip) {
    for (const EnvironmentLayout layout :
         {EnvironmentLayout::Equirect, EnvironmentLayout::Cross, EnvironmentLayout::MirrorBall,
          EnvironmentLayout::CubeFaces}) {
        EXPECT_EQ(environment_layout_from_string(to_string(layout)), layout);
    }
    EXPECT_THROW(environment_layout_from_string("octahedral"), Error);
}
