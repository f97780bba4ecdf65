// Framing over HTTP: an orbit camera without target or distance frames the whole product (its
// projected bounds, computed here from the mesh's bounds and the camera the automatic framing
// should give, hold the rendered silhouette and sit in the frame), and the preview recipe
// (1 sample, a fifth of each side, hard shadows, a small shadow map) frames the product exactly
// as the full frame does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "http_support.hpp"
#include "oer/mesh/camera.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

// The default scene seen by an orbit with neither target nor distance; a transparent
// background and no ground, so that alpha is the product's silhouette.
const std::string kOrbitQuery =
    "/v1/render?environment=default&mesh=default&yaw=60&pitch=20&ground=off"
    "&background=transparent&format=png";

// Pixel-space bounding box of the pixels whose alpha is over half.
struct PixelBox {
    glm::dvec2 low{1e9};
    glm::dvec2 high{-1e9};
    long count = 0;
};

PixelBox silhouette_box(const Rgba8Image& image) {
    PixelBox box;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (image.pixels[(std::size_t(y) * image.width + x) * 4 + 3] > 127) {
                box.low = glm::min(box.low, glm::dvec2(x, y));
                box.high = glm::max(box.high, glm::dvec2(x + 1, y + 1));
                ++box.count;
            }
        }
    }
    return box;
}

// A pinhole camera looking from eye at target, +Y up, vertical field of view fov_y degrees:
// the pixel (x to the right, y down) a world point lands on.
glm::dvec2 project(glm::dvec3 eye, glm::dvec3 target, double fov_y, int width, int height,
                   glm::dvec3 point) {
    const glm::dvec3 forward = glm::normalize(target - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
    const glm::dvec3 up = glm::cross(right, forward);
    const glm::dvec3 d = point - eye;
    const double t = std::tan(glm::radians(fov_y) / 2.0);
    const double aspect = double(width) / double(height);
    const double nx = glm::dot(d, right) / glm::dot(d, forward) / (t * aspect);
    const double ny = glm::dot(d, up) / glm::dot(d, forward) / t;
    return {(nx + 1.0) * 0.5 * width, (1.0 - ny) * 0.5 * height};
}

}  // namespace

TEST(Framing, AnOrbitWithoutTargetOrDistanceFramesTheWholeProduct) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const auto mesh = client->Get("/v1/meshes/default");
    ASSERT_TRUE(mesh);
    ASSERT_EQ(mesh->status, 200) << mesh->body;
    const Json bounds = Json::parse(mesh->body).at("bounds");
    const glm::dvec3 low{bounds["min"][0], bounds["min"][1], bounds["min"][2]};
    const glm::dvec3 high{bounds["max"][0], bounds["max"][1], bounds["max"][2]};
    constexpr int width = 320, height = 240;
    // The pixel box of the bounds' eight corners seen by an orbit camera.
    const auto projected_bounds = [&](glm::dvec3 target, double distance) {
        const double yaw = glm::radians(60.0), pitch = glm::radians(20.0);
        const glm::dvec3 eye =
            target + distance * glm::dvec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                                           std::cos(pitch) * std::cos(yaw));
        PixelBox box;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec2 p =
                project(eye, target, 45.0, width, height,
                        {(corner & 1) ? high.x : low.x, (corner & 2) ? high.y : low.y,
                         (corner & 4) ? high.z : low.z});
            box.low = glm::min(box.low, p);
            box.high = glm::max(box.high, p);
        }
        return box;
    };
    // The product drawn lies inside the projected bounds (one pixel of rasterisation slack):
    // it was drawn through the camera expected.
    const auto expect_inside = [](const PixelBox& product, const PixelBox& projected) {
        ASSERT_GT(product.count, 0);
        EXPECT_GE(product.low.x, projected.low.x - 1.0);
        EXPECT_GE(product.low.y, projected.low.y - 1.0);
        EXPECT_LE(product.high.x, projected.high.x + 1.0);
        EXPECT_LE(product.high.y, projected.high.y + 1.0);
    };

    // The camera expected (camera.hpp, frame_orbit): about the bounds' centre, from the distance
    // at which the cylinder holding the bounds at every yaw fits both fields of view.
    const glm::dvec3 centre = 0.5 * (low + high);
    const Camera expected =
        frame_orbit(60.0f, 20.0f, std::nullopt, std::nullopt,
                    Bounds{glm::vec3(low), glm::vec3(high)}, 45.0f, float(width) / float(height));
    const PixelBox framed =
        projected_bounds(centre, glm::length(glm::dvec3(expected.eye - expected.target)));
    // The projected bounds are inside the frame ...
    EXPECT_GE(framed.low.x, 0.0);
    EXPECT_GE(framed.low.y, 0.0);
    EXPECT_LE(framed.high.x, width);
    EXPECT_LE(framed.high.y, height);
    // ... and hold the product drawn, whose centre is near the image centre (the dress form is
    // nearly symmetric about its bounds' centre) and which is not lost in the distance.
    const PixelBox product =
        silhouette_box(get_frame(*client, kOrbitQuery + "&width=320&height=240&samples=1"));
    expect_inside(product, framed);
    const glm::dvec2 product_centre = 0.5 * (product.low + product.high);
    EXPECT_NEAR(product_centre.x, width / 2.0, 0.05 * width);
    EXPECT_NEAR(product_centre.y, height / 2.0, 0.05 * height);
    EXPECT_GT(product.high.y - product.low.y, 0.5 * height);

    // An explicit target and distance still win: the floor's origin from 3 away (the old
    // defaults, which do not hold the product: its top leaves the frame).
    const PixelBox floor_bounds = projected_bounds(glm::dvec3(0.0), 3.0);
    EXPECT_LT(floor_bounds.low.y, 0.0);
    const PixelBox floor_view = silhouette_box(get_frame(
        *client, kOrbitQuery + "&target=0,0,0&distance=3&width=320&height=240&samples=1"));
    expect_inside(floor_view, floor_bounds);
    EXPECT_GT(glm::length(0.5 * (floor_view.low + floor_view.high) - product_centre), 0.1 * height);
}

// The preview recipe (api/README.md) at 160x120 against the full frame at 800x600: after a 5x5
// box filter of the full frame's alpha, the silhouettes (alpha over half) overlap with an
// intersection over union above 0.97. A framing that moved with the size in pixels would shift
// or scale the silhouette by whole preview pixels and fall well below.
TEST(Framing, APreviewFramesTheProductAsTheFullFrameDoes) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Rgba8Image preview =
        get_frame(*client, kOrbitQuery +
                               "&width=160&height=120&samples=1&shadow_resolution=256"
                               "&shadow_filter=hard");
    const Rgba8Image full = get_frame(*client, kOrbitQuery + "&width=800&height=600");
    ASSERT_EQ(preview.width, 160);
    ASSERT_EQ(preview.height, 120);
    ASSERT_EQ(full.width, 800);
    ASSERT_EQ(full.height, 600);
    constexpr int factor = 5;
    long both = 0, either = 0, preview_count = 0;
    for (int y = 0; y < preview.height; ++y) {
        for (int x = 0; x < preview.width; ++x) {
            double alpha = 0.0;
            for (int dy = 0; dy < factor; ++dy) {
                for (int dx = 0; dx < factor; ++dx) {
                    const std::size_t i =
                        (std::size_t(y * factor + dy) * full.width + (x * factor + dx)) * 4 + 3;
                    alpha += full.pixels[i];
                }
            }
            const bool in_full = alpha / (factor * factor) > 127.5;
            const bool in_preview =
                preview.pixels[(std::size_t(y) * preview.width + x) * 4 + 3] > 127;
            both += in_full && in_preview;
            either += in_full || in_preview;
            preview_count += in_preview;
        }
    }
    ASSERT_GT(preview_count, 160 * 120 / 20) << "the product covers too little to compare";
    const double iou = double(both) / double(either);
    RecordProperty("silhouette_iou", std::to_string(iou));
    EXPECT_GT(iou, 0.97) << both << " of " << either << " pixels";
}
