// bench/frame_sweep --quick as a process (the bunny under two Blender worlds, the four
// pipelines and the transfer rule's check, compared with the reference renderer at 64x64):
// its JSON and CSV agree, every comparison is complete and well formed, the frames with
// occlusion carry the bake of their own bounce mode, the images it names exist at the compare
// size, and its figures say what shadows and occlusion must: our default is nearer the reference
// than plain SH irradiance (the same map, no shadows) on the product, the ground and the ground
// near the product, in both bounce modes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>

#include "oer/scene/scene_transfer.hpp"
#include "sweep_process.hpp"
#include "sweep_support.hpp"

namespace {

const char* const kBunny = "/usr/share/glmark2/models/bunny.obj";

// (world, config, state, bounce, surface)
using FrameRowKey = std::tuple<std::string, std::string, std::string, std::string, std::string>;

class FrameSweepQuick : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        if (!std::filesystem::exists(std::filesystem::path(oer::bench::kBlenderWorldDirectory) /
                                     "studio.exr") ||
            !std::filesystem::exists(kBunny)) {
            return;
        }
        const std::filesystem::path dir = fresh_sweep_folder(FRAME_SWEEP_PATH);
        images_ = new std::map<std::string, std::uintmax_t>;
        output_ = new SweepOutput(run_sweep_command(
            std::string(FRAME_SWEEP_PATH) + " --quick --out " + dir.string(), dir,
            dir / "frame_sweep.json", dir / "frame_sweep.csv",
            [](const std::filesystem::path& folder) {
                for (const auto& entry : std::filesystem::directory_iterator(folder / "images")) {
                    (*images_)["images/" + entry.path().filename().string()] = entry.file_size();
                }
            }));
    }
    static void TearDownTestSuite() {
        delete output_;
        delete images_;
        output_ = nullptr;
        images_ = nullptr;
    }
    void SetUp() override {
        if (output_ == nullptr) {
            GTEST_SKIP() << "needs the Blender worlds and the bunny: install blender-data and "
                            "glmark2-data (scripts/setup-debian.sh --with-test-data)";
        }
        ASSERT_EQ(output_->status, 0) << output_->stderr_text;
        for (const auto& row : output_->json.at("rows")) {
            rows_[{row.at("world"), row.at("config"), row.at("state"), row.at("bounce"),
                   row.at("surface")}] = row;
        }
    }
    double error(const std::string& world, const std::string& config, const std::string& bounce,
                 const std::string& surface) const {
        return rows_.at({world, config, "all on", bounce, surface}).at("relative_rms");
    }

    static SweepOutput* output_;
    static std::map<std::string, std::uintmax_t>* images_;
    std::map<FrameRowKey, nlohmann::json> rows_;
};
SweepOutput* FrameSweepQuick::output_ = nullptr;
std::map<std::string, std::uintmax_t>* FrameSweepQuick::images_ = nullptr;

TEST_F(FrameSweepQuick, JsonAndCsvHoldTheSameRows) {
    const auto& rows = output_->json.at("rows");
    ASSERT_EQ(output_->csv.size(), rows.size() + 1);
    EXPECT_EQ(output_->csv[0][0], "mesh");
    EXPECT_EQ(rows_.size(), rows.size()) << "a (world, config, state, bounce, surface) twice";
}

const char* const kPipelines[] = {"default", "OER, no occlusion", "plain SH", "thesis"};
const char* const kRuleCheck[] = {"occlusion, 64 rays", "occlusion, order 3", "occlusion, order 5"};
const char* const kSurfaces[] = {"object", "ground", "ground near"};

TEST_F(FrameSweepQuick, EveryPipelineIsComparedInEveryStateOnEverySurface) {
    for (const std::string world : {"forest", "studio"}) {
        for (const std::string surface : kSurfaces) {
            for (const std::string config : kPipelines) {
                EXPECT_TRUE(rows_.contains({world, config, "all on", "none", surface}));
                EXPECT_TRUE(rows_.contains({world, config, "all on", "one", surface}));
                EXPECT_TRUE(rows_.contains({world, config, "light 1 off", "none", surface}));
                EXPECT_TRUE(rows_.contains({world, config, "light 1 at 0.5", "none", surface}));
            }
            // The rule's check: all lights on, both modes.
            for (const std::string config : kRuleCheck) {
                EXPECT_TRUE(rows_.contains({world, config, "all on", "none", surface}));
                EXPECT_TRUE(rows_.contains({world, config, "all on", "one", surface}));
            }
        }
    }
    EXPECT_EQ(rows_.size(), 2u * 3u * (4u * 4u + 3u * 2u));
}

TEST_F(FrameSweepQuick, OcclusionFramesCarryTheBakeOfTheirMode) {
    std::map<std::string, const nlohmann::json*> scenes;
    for (const auto& scene : output_->json.at("scenes")) {
        scenes[scene.at("world")] = &scene;
    }
    for (const auto& [key, row] : rows_) {
        const auto& [world, config, state, bounce, surface] = key;
        const bool occlusion = config == "default" || config.starts_with("occlusion");
        EXPECT_EQ(row.at("occlusion").get<bool>(), occlusion) << row.dump();
        if (!occlusion) {
            EXPECT_EQ(row.at("bake_ms").get<double>(), 0.0) << row.dump();
            EXPECT_EQ(row.at("transfer_rays").get<int>(), 0) << row.dump();
            continue;
        }
        EXPECT_EQ(row.at("transfer_rays").get<int>(), config == "occlusion, 64 rays" ? 64 : 144)
            << row.dump();
        if (row.at("transfer_rays").get<int>() == 144) {
            // The rule's transfer, baked once in each mode and recorded with the scene.
            const auto& baked = scenes.at(world)->at("transfer").at(bounce);
            EXPECT_EQ(baked.at("rays").get<int>(), 144);
            EXPECT_EQ(row.at("bake_ms").get<double>(), baked.at("bake_ms").get<double>())
                << row.dump();
        }
        EXPECT_GT(row.at("bake_ms").get<double>(), 0.0) << row.dump();
    }
    // The two modes are two bakes, each recorded with its scene. Their times are not compared:
    // on a loaded machine the one-bounce bake (which traces the blocked rays again) came out
    // faster than the other (1.9 s against 2.7 s), and speed is measured, not asserted.
    for (const auto& [world, scene] : scenes) {
        const auto& transfer = scene->at("transfer");
        EXPECT_TRUE(transfer.contains("one") && transfer.contains("none")) << world;
    }
}

TEST_F(FrameSweepQuick, FiguresAreFiniteAndConsistent) {
    for (const auto& [key, row] : rows_) {
        const double error = row.at("relative_rms"), noise = row.at("reference_noise");
        EXPECT_TRUE(error > 0.0 && error < 1.0) << row.dump();
        EXPECT_TRUE(std::isfinite(row.at("fidelity_db").get<double>()) &&
                    row.at("fidelity_db").get<double>() < 0.0)
            << row.dump();
        EXPECT_TRUE(noise > 0.0 && noise < 0.2) << row.dump();
        EXPECT_NEAR(row.at("noise_ratio").get<double>(), noise / error, 1e-12);
        EXPECT_GT(row.at("frame_ms").get<double>(), 0.0);
        EXPECT_GT(row.at("pixels").get<int>(), 100) << row.dump();
        const std::string& config = std::get<1>(key);
        EXPECT_EQ(row.at("scale_fitted").get<bool>(), config == "thesis");
        EXPECT_EQ(row.at("shadow_filter").get<std::string>(), config == "plain SH" ? "off"
                                                              : config == "thesis" ? "hard"
                                                                                   : "pcf");
        // The thesis's, plain SH's and the order check's orders are set; the others choose
        // their own.
        if (config == "plain SH" || config == "thesis" || config == "occlusion, order 3") {
            EXPECT_EQ(row.at("order").get<int>(), 3);
        } else if (config == "occlusion, order 5") {
            EXPECT_EQ(row.at("order").get<int>(), 5);
        }
        if (row.at("occlusion").get<bool>()) {
            EXPECT_EQ(row.at("transfer_order").get<int>(),
                      std::min(row.at("order").get<int>(), oer::kTransferBakeOrder));
        }
    }
}

TEST_F(FrameSweepQuick, TheGroundNearTheProductIsPartOfTheGround) {
    for (const auto& [key, row] : rows_) {
        const auto& [world, config, state, bounce, surface] = key;
        if (surface == "ground near") {
            EXPECT_LT(row.at("pixels").get<int>(),
                      rows_.at({world, config, state, bounce, "ground"}).at("pixels").get<int>());
        }
    }
}

TEST_F(FrameSweepQuick, TheDefaultIsNearerTheReferenceThanPlainShInBothModes) {
    for (const std::string world : {"forest", "studio"}) {
        for (const std::string bounce : {"none", "one"}) {
            for (const std::string surface : kSurfaces) {
                EXPECT_LT(error(world, "default", bounce, surface),
                          error(world, "plain SH", bounce, surface))
                    << world << ", " << bounce << ", " << surface;
            }
        }
    }
}

TEST_F(FrameSweepQuick, TheImagesItNamesExist) {
    const auto& scenes = output_->json.at("scenes");
    ASSERT_EQ(scenes.size(), 2u);
    for (const auto& scene : scenes) {
        for (const std::string key :
             {"reference", "reference_one_bounce", "default", "default_one_bounce",
              "oer_no_occlusion", "plain_sh", "thesis", "error_default", "error_default_one_bounce",
              "error_oer_no_occlusion", "error_plain_sh"}) {
            ASSERT_TRUE(scene.at("images").contains(key)) << scene.dump();
            const std::string path = scene.at("images").at(key);
            ASSERT_TRUE(images_->contains(path)) << path;
            // A 64x64 RGBA PNG of a rendered frame: more than its headers.
            EXPECT_GT(images_->at(path), 1000u) << path;
        }
    }
}

}  // namespace
