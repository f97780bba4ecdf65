// `oer reference` as a process: from `oer render`'s flags it must path trace exactly the request
// the service's parser makes of them, write it as linear EXR and its noise as JSON.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_process.hpp"
#include "oer/api/render_request.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/mesh/default_product.hpp"
#include "oer/reference/reference_renderer.hpp"

using namespace oer;

namespace {

class ReferenceCommand : public OerProcessTest {};

TEST_F(ReferenceCommand, TracesTheRequestRendersFlagsMake) {
    const ProcessResult result =
        run("reference --env default --mesh default --size 40x30 --eye 0.4,1.4,2.6 "
            "--target 0,0.9,0 --yaw 35 --base-color 0.2,0.5,0.9 --samples 8 --sample-seed 5 "
            "--stats " +
            (dir_ / "stats.json").string() + " -o " + (dir_ / "frame.exr").string());
    ASSERT_EQ(result.status, 0) << result.err;
    EXPECT_NE(result.err.find("relative RMS noise"), std::string::npos) << result.err;

    // The same request in this process, through the service's parser.
    const api::RenderSpec spec = api::parse_render_query({{"environment", "default"},
                                                          {"mesh", "default"},
                                                          {"format", "exr"},
                                                          {"width", "40"},
                                                          {"height", "30"},
                                                          {"eye", "0.4,1.4,2.6"},
                                                          {"target", "0,0.9,0"},
                                                          {"environment_yaw", "35"},
                                                          {"base_color", "0.2,0.5,0.9"}});
    const HdrImage map = make_default_environment();
    const FrameRequest request =
        api::to_frame_request(spec, std::make_shared<const Rig>(build_rig(map, {}, RigOptions{})),
                              std::make_shared<const HdrImage>(map),
                              {std::make_shared<const Mesh>(make_default_product())});
    ReferenceOptions options;
    options.bounce = request.bounce;  // one: --bounce's default, as oer render's
    options.samples = 8;
    options.seed = 5;
    const ReferenceFrame expected = render_reference(request, options);

    const HdrImage written = load_image_file((dir_ / "frame.exr").string()).image;
    ASSERT_EQ(written.width, 40);
    ASSERT_EQ(written.height, 30);
    for (std::size_t i = 0; i < written.pixel_count(); ++i) {
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(written.pixels[i * 3 + c], expected.linear[i * 4 + c])
                << "pixel " << i << " channel " << c;
        }
    }
    const nlohmann::json stats = nlohmann::json::parse(slurp(dir_ / "stats.json"));
    ASSERT_GT(expected.noise.object_pixels, 0u);
    ASSERT_GT(expected.noise.ground_pixels, 0u);
    EXPECT_EQ(stats.at("noise").at("object").at("pixels"), expected.noise.object_pixels);
    EXPECT_DOUBLE_EQ(stats.at("noise").at("object").at("relative_rms").get<double>(),
                     expected.noise.object);
    EXPECT_DOUBLE_EQ(stats.at("noise").at("ground").at("relative_rms").get<double>(),
                     expected.noise.ground);
    EXPECT_EQ(stats.at("samples"), 8);
    EXPECT_EQ(stats.at("bounce"), "one");
}

TEST_F(ReferenceCommand, BounceNoneTracesTheEnvironmentsLightAlone) {
    const std::string stats = (dir_ / "stats.json").string();
    const ProcessResult result =
        run("reference --env default --mesh default --size 8x6 --samples 2 --bounce none "
            "--stats " +
            stats + " -o " + (dir_ / "frame.exr").string());
    ASSERT_EQ(result.status, 0) << result.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(stats)).at("bounce"), "none");
    EXPECT_NE(result.err.find("bounce none"), std::string::npos) << result.err;
}

TEST_F(ReferenceCommand, RejectsOddSamplesAndDisplayFormats) {
    const std::string out = " -o " + (dir_ / "frame.exr").string();
    ProcessResult result = run("reference --env default --mesh default --samples 7" + out);
    EXPECT_EQ(result.status, 2);
    EXPECT_NE(result.err.find("--samples"), std::string::npos) << result.err;
    result = run("reference --env default --mesh default -o " + (dir_ / "frame.png").string());
    EXPECT_EQ(result.status, 2);
    EXPECT_NE(result.err.find(".exr"), std::string::npos) << result.err;
    // --bounce is oer render's flag, read by the service's parser; --occlusion is the
    // rasteriser's alone.
    result = run("reference --env default --mesh default --bounce two" + out);
    EXPECT_EQ(result.status, 2);
    EXPECT_NE(result.err.find("--bounce: bounce 'two' is not one of none, one"), std::string::npos)
        << result.err;
    result = run("reference --env default --mesh default --occlusion off" + out);
    EXPECT_EQ(result.status, 2);
    EXPECT_NE(result.err.find("--occlusion"), std::string::npos) << result.err;
    result = run("reference --env default --mesh default --fov 0" + out);
    EXPECT_EQ(result.status, 2);
    EXPECT_NE(result.err.find("--fov"), std::string::npos) << result.err;
}

}  // namespace
