// `oer render` reads its flags with the service's parser: one table of values, good and bad, run
// through `oer render` as a process and through api::parse_render_query, must be accepted or
// rejected alike, and rejected with the same message (the flag's name for the parameter's).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <cstdio>
#include <fstream>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "base64.hpp"
#include "cli_process.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/render_request.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/lighting/default_environment.hpp"

namespace {

class RenderFlags : public OerProcessTest {};

struct Case {
    std::string flags;                              // added to `oer render`'s command line
    std::multimap<std::string, std::string> query;  // the same values as GET parameters
    std::string flag;                               // the flag an error must name
};

// The parser's verdict: empty when it accepts, else its message with the parameter's name
// replaced by the flag's.
std::string parser_verdict(const Case& row) {
    std::multimap<std::string, std::string> query = row.query;
    query.emplace("environment", "default");
    query.emplace("mesh", "default");
    query.emplace("format", "png");
    try {
        oer::api::parse_render_query(query);
    } catch (const oer::api::InvalidParameter& error) {
        return "--" + row.flag + std::string(error.what()).substr(error.parameter().size());
    }
    return {};
}

std::vector<Case> cases() {
    const std::string every_light_on = [count = oer::default_environment_lights().size()] {
        std::string text = "1";
        for (std::size_t i = 1; i < count; ++i) {
            text += ",1";
        }
        return text;
    }();
    return {
        {"--samples 3", {{"samples", "3"}}, "samples"},
        {"--samples 8", {{"samples", "8"}}, "samples"},
        {"--samples 16", {{"samples", "16"}}, "samples"},
        {"--samples 0", {{"samples", "0"}}, "samples"},
        {"--samples many", {{"samples", "many"}}, "samples"},
        {"--shadow-resolution 64", {{"shadow_resolution", "64"}}, "shadow-resolution"},
        {"--shadow-resolution 100", {{"shadow_resolution", "100"}}, "shadow-resolution"},
        {"--shadow-resolution 32", {{"shadow_resolution", "32"}}, "shadow-resolution"},
        {"--shadow-resolution 16384", {{"shadow_resolution", "16384"}}, "shadow-resolution"},
        {"--size 5000x10", {{"width", "5000"}, {"height", "10"}}, "size"},
        {"--size 10x5000", {{"width", "10"}, {"height", "5000"}}, "size"},
        {"--size 0x10", {{"width", "0"}, {"height", "10"}}, "size"},
        {"--size 24x-1", {{"width", "24"}, {"height", "-1"}}, "size"},
        {"--size 32x24", {{"width", "32"}, {"height", "24"}}, "size"},
        {"--quality 0", {{"quality", "0"}}, "quality"},
        {"--quality 101", {{"quality", "101"}}, "quality"},
        {"--quality 1", {{"quality", "1"}}, "quality"},
        {"--tonemap bogus", {{"tonemap", "bogus"}}, "tonemap"},
        {"--tonemap aces", {{"tonemap", "aces"}}, "tonemap"},
        {"--lights 1,x", {{"lights", "1,x"}}, "lights"},
        {"--lights " + every_light_on, {{"lights", every_light_on}}, "lights"},
        {"--exposure 1e9", {{"exposure", "1e9"}}, "exposure"},
        {"--exposure -1.5", {{"exposure", "-1.5"}}, "exposure"},
        {"--yaw 361", {{"environment_yaw", "361"}}, "yaw"},
        {"--yaw -90", {{"environment_yaw", "-90"}}, "yaw"},
        {"--ground maybe", {{"ground", "maybe"}}, "ground"},
        {"--shadows yes", {{"shadows", "yes"}}, "shadows"},
        {"--occlusion yes", {{"occlusion", "yes"}}, "occlusion"},
        {"--occlusion true", {{"occlusion", "true"}}, "occlusion"},
        {"--occlusion on", {{"occlusion", "on"}}, "occlusion"},
        {"--bounce two", {{"bounce", "two"}}, "bounce"},
        {"--bounce none", {{"bounce", "none"}}, "bounce"},
        {"--base-color 0.8,0.1", {{"base_color", "0.8,0.1"}}, "base-color"},
        {"--base-color 0.8,0.1,1.2", {{"base_color", "0.8,0.1,1.2"}}, "base-color"},
        {"--base-color 0.8,0.1,x", {{"base_color", "0.8,0.1,x"}}, "base-color"},
        {"--base-color 0.8,0.1,0.1", {{"base_color", "0.8,0.1,0.1"}}, "base-color"},
        {"--shadow-filter soft", {{"shadow_filter", "soft"}}, "shadow-filter"},
        {"--shadow-filter hard", {{"shadow_filter", "hard"}}, "shadow-filter"},
        {"--background '#12345'", {{"background", "#12345"}}, "background"},
        {"--background transparent", {{"background", "transparent"}}, "background"},
        {"--eye 0,1,3 --target 0,0,0 --fov 0",
         {{"eye", "0,1,3"}, {"target", "0,0,0"}, {"fov_y", "0"}},
         "fov"},
        {"--eye 0,1,x --target 0,0,0", {{"eye", "0,1,x"}, {"target", "0,0,0"}}, "eye"},
        {"--eye 0,0,0 --target 0,0,0", {{"eye", "0,0,0"}, {"target", "0,0,0"}}, "eye"},
        {"--eye 0,1,3 --target 0,0.5,0 --up 0,0,1 --fov 30",
         {{"eye", "0,1,3"}, {"target", "0,0.5,0"}, {"up", "0,0,1"}, {"fov_y", "30"}},
         "eye"},
        {"--camera front", {{"camera", "front"}}, "camera"},
        {"--camera asset:0 --eye 0,1,3", {{"camera", "asset:0"}, {"eye", "0,1,3"}}, "eye"},
    };
}

}  // namespace

TEST_F(RenderFlags, TheCliAndTheQueryParserAgreeOnEveryValue) {
    // A triangle as OBJ, whose material is Lambertian: no specular cube to prefilter (the
    // default product's glossy stand costs each accepted case over half its CPU time).
    const std::filesystem::path triangle = dir_ / "triangle.obj";
    std::ofstream(triangle) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    int accepted = 0, rejected = 0;
    for (const Case& row : cases()) {
        const std::string expected = parser_verdict(row);
        const std::filesystem::path frame = dir_ / "frame.png";
        std::filesystem::remove(frame);
        // Small, unshadowed and unoccluded (no transfer to bake), so that the accepted cases
        // render quickly; the row's own flags come last and win. Run as `oer-render`, which
        // `oer render` becomes (execv, the same arguments; the tests below go through `oer`):
        // each row starts one process that loads the shared libraries, not two.
        const ProcessResult result = run_executable(OER_RENDER_PATH,
                                                    "--env default --mesh " + triangle.string() +
                                                        " --size 16x16 --shadows off "
                                                        "--occlusion off -o " +
                                                        frame.string() + " " + row.flags,
                                                    dir_);
        if (expected.empty()) {
            ++accepted;
            EXPECT_EQ(result.status, 0) << row.flags << ": " << result.err;
            EXPECT_TRUE(std::filesystem::exists(frame)) << row.flags;
        } else {
            ++rejected;
            EXPECT_EQ(result.status, 2) << row.flags;
            EXPECT_EQ(result.err, "oer render: " + expected + "\n") << row.flags;
        }
    }
    // The table holds both kinds, so that neither half of the comparison is vacuous.
    EXPECT_GE(accepted, 10);
    EXPECT_GE(rejected, 20);
}

TEST_F(RenderFlags, DefaultsAreTheServicesJpegQualityAndSamples) {
    const auto frame = [this](const std::string& flags) {
        const std::filesystem::path path = dir_ / "frame.jpg";
        const ProcessResult result =
            run("render --env default --mesh default --size 48x32 "
                "--shadows off --occlusion off -o " +
                path.string() + " " + flags);
        EXPECT_EQ(result.status, 0) << flags << ": " << result.err;
        return slurp(path);
    };
    const std::string by_default = frame("");
    EXPECT_FALSE(by_default.empty());
    EXPECT_EQ(by_default, frame("--quality 85 --samples 4"));
    EXPECT_NE(by_default, frame("--quality 90"));
    EXPECT_NE(by_default, frame("--samples 1"));
}

// --base-color is the query's base_color: every mesh takes it. Against a black background with
// no ground, a red variant turns most of the product's pixels red-dominant; the default
// product (fabric 0.85, 0.80, 0.75 and a dark stand) has next to none.
TEST_F(RenderFlags, BaseColorRecolorsTheProduct) {
    struct Counts {
        int product = 0;
        int red = 0;
    };
    const auto count = [this](const std::string& flags) {
        const std::filesystem::path path = dir_ / "frame.png";
        const ProcessResult result =
            run("render --env default --mesh default --size 64x64 --samples 1 --shadows off "
                "--occlusion off --ground off --background '#000000' -o " +
                path.string() + " " + flags);
        EXPECT_EQ(result.status, 0) << flags << ": " << result.err;
        const std::string bytes = slurp(path);
        const oer::Rgba8Image image = oer::decode_8bit({bytes.begin(), bytes.end()});
        Counts counts;
        for (std::size_t i = 0; i + 3 < image.pixels.size(); i += 4) {
            const int r = image.pixels[i], g = image.pixels[i + 1], b = image.pixels[i + 2];
            if (std::max({r, g, b}) < 16) {
                continue;  // the black background, and the darkest of the stand
            }
            ++counts.product;
            counts.red += r > 2 * std::max(g, b);
        }
        return counts;
    };
    const Counts plain = count(""), red = count("--base-color 0.8,0.05,0.05");
    ASSERT_GT(plain.product, 200);  // the dress form: about 8 % of the frame
    EXPECT_LT(plain.red, plain.product / 50);
    EXPECT_GT(red.red, red.product / 2);
}

// With occlusion on (the default) render bakes the scene's transfer before the frame and says
// so on stderr only; with it off there is nothing to bake.
TEST_F(RenderFlags, OcclusionBakesTheTransferAndSaysSoOnStderrOnly) {
    const auto render = [this](const std::string& flags) {
        const std::filesystem::path path = dir_ / "frame.png";
        const ProcessResult result =
            run("render --env default --mesh default --size 32x24 --samples 1 --shadows off -o " +
                path.string() + " " + flags);
        EXPECT_EQ(result.status, 0) << flags << ": " << result.err;
        EXPECT_EQ(result.out, "") << flags;
        return result.err;
    };
    EXPECT_NE(render("").find(", transfer "), std::string::npos);
    EXPECT_NE(render("--bounce none").find(", transfer "), std::string::npos);
    EXPECT_EQ(render("--occlusion off").find(", transfer "), std::string::npos);
}

namespace {

// A triangle (bounds centre (0.5, 0.5, 0)) as a .gltf, with camera 0 "Front" at (0, 0.5, 3)
// looking down -Z and camera 1 "Back" at (0, 0.5, -3) turned half about +Y (looking down +Z),
// both with a yfov of kBackYfov radians.
constexpr double kBackYfov = 0.6;

std::string triangle_with_cameras() {
    const std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(positions.data());
    const std::vector<std::uint8_t> data(bytes, bytes + positions.size() * sizeof(glm::vec3));
    const nlohmann::json camera = {{"type", "perspective"},
                                   {"perspective", {{"yfov", kBackYfov}, {"znear", 0.01}}}};
    nlohmann::json front = camera, back = camera;
    front["name"] = "Front";
    back["name"] = "Back";
    const nlohmann::json gltf = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0, 1, 2}}}}},
        {"nodes",
         {{{"mesh", 0}},
          {{"camera", 0}, {"translation", {0.0, 0.5, 3.0}}},
          {{"camera", 1}, {"translation", {0.0, 0.5, -3.0}}, {"rotation", {0.0, 1.0, 0.0, 0.0}}}}},
        {"cameras", {front, back}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
        {"accessors",
         {{{"bufferView", 0},
           {"componentType", 5126},
           {"count", 3},
           {"type", "VEC3"},
           {"min", {0, 0, 0}},
           {"max", {1, 1, 0}}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", data.size()}}}},
        {"buffers",
         {{{"byteLength", data.size()},
           {"uri", "data:application/octet-stream;base64," + oer::testing::base64(data)}}}}};
    return gltf.dump();
}

}  // namespace

// --camera asset:N is the query's camera: `oer render` draws the mesh's own camera, the same
// frame as that camera given by --eye, --target and --fov; one the mesh does not have is a
// usage error listing those it has.
TEST_F(RenderFlags, CameraDrawsTheMeshsOwnCamera) {
    std::ofstream(dir_ / "triangle.gltf") << triangle_with_cameras();
    const auto render = [this](const std::string& flags) {
        return run("render --env default --mesh " + (dir_ / "triangle.gltf").string() +
                   " --size 48x32 --samples 1 --occlusion off -o " + (dir_ / "frame.png").string() +
                   " " + flags);
    };
    const ProcessResult asset = render("--camera asset:1");
    ASSERT_EQ(asset.status, 0) << asset.err;
    const std::string from_asset = slurp(dir_ / "frame.png");
    // The loader's float of the yfov in degrees, to every digit.
    char fov[32];
    std::snprintf(fov, sizeof fov, "%.9g",
                  double(float(kBackYfov * 180.0 / 3.14159265358979323846)));
    const ProcessResult given = render(std::string("--eye 0,0.5,-3 --target 0,0.5,0 --fov ") + fov);
    ASSERT_EQ(given.status, 0) << given.err;
    EXPECT_EQ(slurp(dir_ / "frame.png"), from_asset) << "the explicit camera draws another frame";
    ASSERT_EQ(render("--camera asset:Front").status, 0);
    EXPECT_NE(slurp(dir_ / "frame.png"), from_asset) << "camera 0 draws camera 1's frame";

    const ProcessResult missing = render("--camera asset:Side");
    EXPECT_EQ(missing.status, 2);
    EXPECT_EQ(missing.err,
              "oer render: --camera: the first object's mesh has no camera named 'Side'; it has "
              "2: 0 'Front' (perspective), 1 'Back' (perspective)\n");
}
