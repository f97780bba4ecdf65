// The default exposure over HTTP ("well exposed"): on the built-in default scene and on
// the Stanford bunny under each Blender world, a frame asked for with no exposure, tone map or
// format (the API's defaults: 0 EV, neutral tone mapping, JPEG quality 85) has under 2.5 % of
// the product's pixels at 255 in any channel. The fixed default suffices, with no automatic
// exposure: the Khronos PBR Neutral shoulder, 1 - 0.24^2 / (peak - 0.52), approaches 1 only
// asymptotically, so a pixel reaches 255 (linear 0.9955 before sRGB) only for exposed radiance
// over 13.5, and no world lights the bunny that brightly. What reaches 255 here is JPEG's
// quantisation error over near-white surfaces (city and sunrise put half the bunny at 248 or more);
// the lossless PNG of the same frames has none. At +3 EV the same check fails on the default scene
// and on every world but night and studio (8.4 % and 32 to 52 %; night 0.01 %, studio 1.1 %), so
// it can.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

// A modest frame, framed as the default 512 x 512 is (the framing depends on the aspect ratio
// alone); without anti-aliasing its edges are sharper, so JPEG's error is larger, not smaller
// (sunrise: 1.42 % here, 0.35 % at the default size and samples, under the bounding sphere's
// framing; 2.01 % here since the framing fills the frame with the product and soft shadows
// sample Vogel spirals).
const std::string kFrameSize = "&width=256&height=256&samples=1";

// The share allowed: under 2.5 % of the product's pixels at 255 (JPEG's error over the
// brightest world, sunrise, is 2.01 %).
constexpr double kMaxClippedShare = 0.025;

struct ClippedPixels {
    long product = 0;  // pixels fully covered by the product
    long clipped = 0;  // of those, the ones with a channel at 255
    double share() const { return product == 0 ? 0.0 : double(clipped) / double(product); }
};

// The pixels of the default frame of the scene (with `extra` parameters) fully covered by the
// product, found by its silhouette: the same request with a transparent background and no ground
// (the framing does not depend on either), whose alpha is the product's coverage. Only fully
// covered pixels count: the edges' colour is the background's in part.
std::vector<std::array<std::uint8_t, 3>> product_pixels(httplib::Client& client,
                                                        const std::string& environment,
                                                        const std::string& mesh,
                                                        const std::string& extra = "") {
    const std::string scene = "/v1/render?environment=" + environment + "&mesh=" + mesh;
    const Rgba8Image frame = get_frame(client, scene + kFrameSize + extra);
    const Rgba8Image silhouette =
        get_frame(client, scene + kFrameSize + "&background=transparent&ground=off&format=png");
    std::vector<std::array<std::uint8_t, 3>> pixels;
    if (frame.width != silhouette.width || frame.height != silhouette.height) {
        ADD_FAILURE() << scene << ": the frame is " << frame.width << "x" << frame.height
                      << ", its silhouette " << silhouette.width << "x" << silhouette.height;
        return pixels;
    }
    for (std::size_t i = 0; i < frame.pixels.size(); i += 4) {
        if (silhouette.pixels[i + 3] == 255) {
            pixels.push_back({frame.pixels[i], frame.pixels[i + 1], frame.pixels[i + 2]});
        }
    }
    return pixels;
}

ClippedPixels clipped_product_pixels(httplib::Client& client, const std::string& environment,
                                     const std::string& mesh) {
    ClippedPixels pixels;
    for (const auto& rgb : product_pixels(client, environment, mesh)) {
        ++pixels.product;
        pixels.clipped += std::max({rgb[0], rgb[1], rgb[2]}) == 255 ? 1 : 0;
    }
    return pixels;
}

// The check of one scene, with its figure printed.
void expect_well_exposed(httplib::Client& client, const std::string& name,
                         const std::string& environment, const std::string& mesh) {
    const ClippedPixels pixels = clipped_product_pixels(client, environment, mesh);
    std::printf("%-14s %5.2f %% of %ld product pixels at 255\n", name.c_str(),
                100.0 * pixels.share(), pixels.product);
    // The product is in the frame, large enough for the share to mean something (the bunny
    // covers about 18 % of it, the dress form about 8 %).
    EXPECT_GT(pixels.product, 256L * 256L / 50L) << name;
    EXPECT_LT(pixels.share(), kMaxClippedShare)
        << name << ": " << pixels.clipped << " of " << pixels.product
        << " product pixels have a channel at 255";
}

std::string file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(DefaultExposure, TheDefaultSceneClipsUnderTwoAndAHalfPercentOfTheProduct) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    expect_well_exposed(*client, "default scene", "default", "default");
}

TEST(DefaultExposure, TheBunnyUnderEachBlenderWorldClipsUnderTwoAndAHalfPercentOfItself) {
    const std::filesystem::path worlds = "/usr/share/blender/datafiles/studiolights/world";
    const std::filesystem::path bunny = "/usr/share/glmark2/models/bunny.obj";
    std::vector<std::filesystem::path> maps;
    if (std::filesystem::is_directory(worlds)) {
        for (const auto& entry : std::filesystem::directory_iterator(worlds)) {
            if (entry.path().extension() == ".exr") {
                maps.push_back(entry.path());
            }
        }
    }
    if (maps.empty() || !std::filesystem::exists(bunny)) {
        GTEST_SKIP() << "*** NO BLENDER WORLDS in " << worlds << " or NO BUNNY at " << bunny
                     << ": install the Debian packages blender-data and glmark2-data; the "
                        "default exposure on real worlds is NOT tested ***";
    }
    std::sort(maps.begin(), maps.end());
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Json mesh = upload_mesh(*client, file_bytes(bunny), "model/obj");
    ASSERT_FALSE(mesh.is_null());
    for (const std::filesystem::path& map : maps) {
        // Preprocessed with the default options, as a shop's upload is.
        const Json rig = upload_environment(*client, file_bytes(map), "image/x-exr");
        ASSERT_FALSE(rig.is_null()) << map;
        expect_well_exposed(*client, map.stem().string(), rig.at("id"), mesh.at("id"));
    }
}

// "A white product is white" (issue 29): on the built-in studio at the defaults (0 EV, neutral),
// a white Lambertian product (base_color 1,1,1; the bunny's OBJ has no specular term, the dress
// form's stand keeps its gloss) has the 90th and 99th percentiles of its pixels' luma (Rec. 709
// weights over the 8-bit sRGB values) within [215, 246]: white, not grey, and short of the
// tone map's shoulder, with no pixel at 255 in the lossless PNG. Measured: the dress form 242
// and 243, the bunny 243 and 243, the glTF sample 2CylinderEngine 242 and 242 (the old studio:
// 238 and 239 for all three, half of each product at 234 or more). At -1 EV the dress form's
// are 197 and 203, at +0.5 EV 247 and 247: the band fails on either side.
TEST(DefaultExposure, TheStudioShowsAWhiteProductWhiteAndUnclipped) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    // The dress form alone, to keep the test short (the bunny's figures are above).
    const std::vector<std::pair<std::string, std::string>> products = {{"dress form", "default"}};
    for (const auto& [name, mesh] : products) {
        const auto pixels =
            product_pixels(*client, "default", mesh, "&base_color=1,1,1&format=png");
        ASSERT_GT(pixels.size(), 256u * 256u / 50u) << name;
        std::vector<double> luma;
        long clipped = 0;
        for (const auto& rgb : pixels) {
            luma.push_back(0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]);
            clipped += std::max({rgb[0], rgb[1], rgb[2]}) == 255 ? 1 : 0;
        }
        std::sort(luma.begin(), luma.end());
        const auto percentile = [&luma](double p) {
            return luma[std::size_t(p * double(luma.size() - 1))];
        };
        std::printf("%-10s luma p50 %.0f p90 %.0f p99 %.0f, %ld of %zu pixels at 255\n",
                    name.c_str(), percentile(0.5), percentile(0.9), percentile(0.99), clipped,
                    pixels.size());
        for (const double p : {0.9, 0.99}) {
            EXPECT_GE(percentile(p), 215.0) << name << ": percentile " << p << " is grey";
            EXPECT_LE(percentile(p), 246.0) << name << ": percentile " << p << " is washed out";
        }
        EXPECT_EQ(clipped, 0) << name;
    }
}
