#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "oer/api/content_id.hpp"
#include "oer/api/rig_from_json.hpp"
#include "oer/api/rig_json.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/core/checked_json.hpp"
#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/default_environment.hpp"
#include "oer/lighting/rig.hpp"

using namespace oer;
using nlohmann::json;

namespace {

const std::string kId(64, 'a');

bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_same_rig(const Rig& a, const Rig& b) {
    EXPECT_EQ(a.source_width, b.source_width);
    EXPECT_EQ(a.source_height, b.source_height);
    EXPECT_EQ(a.source_range, b.source_range);
    EXPECT_EQ(a.model, b.model);
    EXPECT_EQ(a.order, b.order);
    EXPECT_EQ(a.window.kind, b.window.kind);
    ASSERT_EQ(a.lights.size(), b.lights.size());
    for (std::size_t k = 0; k < a.lights.size(); ++k) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(same_bits(a.lights[k].direction[c], b.lights[k].direction[c]));
            EXPECT_TRUE(same_bits(a.lights[k].intensity[c], b.lights[k].intensity[c]));
        }
        EXPECT_TRUE(same_bits(a.lights[k].angular_radius, b.lights[k].angular_radius));
        EXPECT_EQ(a.lights[k].pixels, b.lights[k].pixels);
    }
    ASSERT_EQ(a.sh.all.coefficients.size(), b.sh.all.coefficients.size());
    for (std::size_t i = 0; i < a.sh.all.coefficients.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(same_bits(a.sh.all.coefficients[i][c], b.sh.all.coefficients[i][c]));
        }
    }
    ASSERT_EQ(a.sh.per_light.size(), b.sh.per_light.size());
    for (std::size_t k = 0; k < a.sh.per_light.size(); ++k) {
        EXPECT_EQ(a.sh.per_light[k].coefficients, b.sh.per_light[k].coefficients);
    }
}

// Real rigs of the default studio: every light, a window, the thesis model.
std::vector<Rig> real_rigs() {
    const HdrImage map = make_default_environment(256, 128);
    RigOptions windowed;
    windowed.window = WindowChoice::Auto;
    windowed.sh_order = 5;
    RigOptions thesis;
    thesis.model = LightingModel::Thesis;
    thesis.light_count = 2;
    // As a JPEG panorama's would be: marked as of low dynamic range.
    LoadedImage panorama{map, {}, DynamicRange::Low};
    return {build_rig(map, {}, RigOptions{}), build_rig(map, {}, windowed),
            build_rig(map, {}, thesis), build_rig(panorama, RigOptions{})};
}

// The stored pair for a rig, and a way to damage it.
struct Stored {
    json rig;
    json masks;
};

Stored stored(const Rig& rig) {
    return {api::rig_to_json(rig, kId), api::light_masks_to_json(rig)};
}

void expect_rejected(const Stored& document, const std::string& member) {
    try {
        api::rig_from_json(document.rig, document.masks);
        ADD_FAILURE() << "accepted a document with a damaged " << member;
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput);
        EXPECT_NE(std::string(error.what()).find(member), std::string::npos) << error.what();
    }
}

}  // namespace

TEST(RigFromJson, RoundTripsRealRigsExactly) {
    for (const Rig& rig : real_rigs()) {
        const Stored document = stored(rig);
        // Through text, as the store keeps it.
        const Rig back = api::rig_from_json(json::parse(document.rig.dump()),
                                            json::parse(document.masks.dump()));
        expect_same_rig(rig, back);
        EXPECT_EQ(api::rig_to_json(back, kId), document.rig);
        EXPECT_EQ(api::rig_options_to_json(back.options), api::rig_options_to_json(rig.options));
    }
}

TEST(RigFromJson, MasksAreRunsOfConsecutivePixels) {
    Rig rig;
    rig.source_width = 10;
    rig.source_height = 5;
    Light light;
    light.pixels = {3, 4, 5, 9, 20, 21};
    rig.lights.push_back(light);
    EXPECT_EQ(api::light_masks_to_json(rig), json::parse("[[3, 3, 9, 1, 20, 2]]"));
}

TEST(RigFromJson, TheLargestMasksAreWithinTheStoredRigBounds) {
    // The most values masks can have: a light of every other pixel of the map, a run each.
    const HdrImage map = make_default_environment(1024, 512);
    Rig rig = build_rig(map, {}, RigOptions{});
    ASSERT_FALSE(rig.lights.empty());
    rig.lights.resize(1);
    rig.lights[0].pixels.clear();
    for (std::uint32_t i = 0; i < map.pixel_count(); i += 2) {
        rig.lights[0].pixels.push_back(i);
    }
    const std::string text =
        json{{"rig", api::rig_to_json(rig, kId)}, {"masks", api::light_masks_to_json(rig)}}.dump();
    const json parsed =
        checked_json::parse_bounded(text, api::stored_rig_bounds(map.pixel_count()));
    EXPECT_EQ(parsed.at("masks").at(0).size(), map.pixel_count());
    // A map of an eighth of the pixels could not have written it.
    EXPECT_THROW(checked_json::parse_bounded(text, api::stored_rig_bounds(map.pixel_count() / 8)),
                 checked_json::JsonParseError);
}

TEST(RigFromJson, RejectsDamagedDocuments) {
    const Rig rig = real_rigs().front();
    ASSERT_FALSE(rig.lights.empty());
    const Stored good = stored(rig);

    Stored document = good;
    document.rig.erase("sh");
    expect_rejected(document, "sh");

    document = good;
    document.rig["sh"]["radiance"].erase(0);
    expect_rejected(document, "sh/radiance");

    document = good;
    document.rig["lights"][0]["direction"] = json::array({1, "x", 0});
    expect_rejected(document, "lights/0/direction/1");

    document = good;
    document.rig["lights"][0]["luminance_share"] = 2.0;
    expect_rejected(document, "lights/0/luminance_share");

    document = good;
    document.rig["lighting_model"] = "photon";
    expect_rejected(document, "lighting_model");

    document = good;
    document.rig["options"]["sh_order"] = 99;
    expect_rejected(document, "options/sh_order");

    document = good;
    document.rig["light_count"]["chosen"] = 7;
    expect_rejected(document, "light_count/chosen");

    document = good;
    document.rig["id"] = "not-an-id";
    expect_rejected(document, "id");

    document = good;
    document.masks[0].push_back(0);  // odd length
    expect_rejected(document, "masks/0");

    document = good;
    document.masks.erase(0);
    expect_rejected(document, "masks");

    document = good;
    document.rig["lights"][0]["pixels"] = document.rig["lights"][0]["pixels"].get<int>() + 1;
    expect_rejected(document, "masks/0");

    document = good;
    document.rig["source"]["dynamic_range"] = "medium";
    expect_rejected(document, "source/dynamic_range");

    document = good;
    document.rig = json::array();
    expect_rejected(document, "document");
}

// What the server writes it reads back: rigs of random maps and of hostile ones (what a
// decoder may hand over before repair_radiance: NaN, +-Inf, the largest floats, denormals, a
// black map, one blinding pixel), each written as the store keeps it and read through the
// store's own reader, which checks every range of api/openapi.yaml. Without the clamp of
// luminance_share, the denormal map's light came out above 1 and the reader refused it (issue
// 14 saw the same with Inf pixels: 1.0000000000000004, the rig dropped on every restart).
TEST(RigFromJson, RigsOfRandomAndHostileMapsReadBack) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    constexpr float kLargest = std::numeric_limits<float>::max();
    constexpr float kDenormal = std::numeric_limits<float>::denorm_min();
    std::mt19937 random(20261202);
    std::vector<std::pair<std::string, HdrImage>> maps;
    const auto add = [&](const std::string& name, const auto& radiance) {
        HdrImage map(64, 32);
        for (std::size_t i = 0; i < map.pixel_count(); ++i) {
            map.set(i, radiance(i));
        }
        maps.emplace_back(name, std::move(map));
    };
    for (int seed = 0; seed < 6; ++seed) {
        // Heavy-tailed radiance: most pixels dim, a few bright enough to be found as lights.
        std::exponential_distribution<float> dim(1.0f);
        std::uniform_real_distribution<float> unit(0.0f, 1.0f);
        add("random " + std::to_string(seed), [&](std::size_t) {
            const float tail = unit(random) < 0.01f ? 1e4f * unit(random) : 0.0f;
            return glm::vec3(dim(random), dim(random), dim(random)) + tail;
        });
    }
    add("one Inf pixel", [](std::size_t i) { return glm::vec3(i == 700 ? kInf : 0.5f); });
    add("every pixel Inf", [](std::size_t) { return glm::vec3(kInf); });
    add("NaN and -Inf", [](std::size_t i) {
        return glm::vec3(i % 3 == 0 ? std::nanf("") : 1.0f, i % 5 == 0 ? -kInf : 1.0f, 2.0f);
    });
    add("the largest floats", [](std::size_t) { return glm::vec3(kLargest); });
    add("denormals", [](std::size_t i) { return glm::vec3(i % 2 == 0 ? kDenormal : 0.0f); });
    add("black", [](std::size_t) { return glm::vec3(0.0f); });
    add("one blinding pixel", [](std::size_t i) { return glm::vec3(i == 100 ? 1e30f : 1e-3f); });
    for (auto& [name, map] : maps) {
        const RepairCounts repaired = repair_radiance(map);
        for (const RigOptions& options : {RigOptions{}, [] {
                                              RigOptions thesis;
                                              thesis.model = LightingModel::Thesis;
                                              return thesis;
                                          }()}) {
            const Rig rig = build_rig(map, repaired, options);
            const Stored document = stored(rig);
            try {
                // As the store writes and reads it: one text, parsed within the bounds of a
                // stored rig of this map's size.
                const json text = checked_json::parse_bounded(
                    json{{"rig", document.rig}, {"masks", document.masks}}.dump(),
                    api::stored_rig_bounds(map.pixel_count()));
                const Rig back = api::rig_from_json(text.at("rig"), text.at("masks"));
                expect_same_rig(rig, back);
            } catch (const Error& error) {
                ADD_FAILURE() << name
                              << ": the reader refuses what the writer wrote: " << error.what();
            }
            for (const Light& light : rig.lights) {
                EXPECT_GE(light.luminance_share, 0.0) << name;
                EXPECT_LE(light.luminance_share, 1.0) << name;
            }
        }
    }
}
