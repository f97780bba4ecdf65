// The shadow-catching ground over HTTP (`ground=shadow`): the built-in product on its own page
// colour. Over white, what is neither the product nor its shadow is exactly white and its
// shadow is darker; switching every light off leaves only the contact shadow the transfer
// gives; over transparency the shadow is black in the alpha; and the shadow-only floor reuses
// the opaque floor's transfer (no bake of its own).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#include "http_support.hpp"

using namespace oer;
using namespace oer::itest;

namespace {

const std::string kScene =
    "/v1/render?environment=default&mesh=default&width=256&height=256&samples=1&format=png";

struct OffProduct {
    long pixels = 0;    // off the product's silhouette
    long white = 0;     // of those, exactly (255, 255, 255)
    int darkest = 255;  // their lowest channel
};

OffProduct off_product(const Rgba8Image& frame, const Rgba8Image& silhouette) {
    OffProduct result;
    for (std::size_t i = 0; i < frame.pixels.size(); i += 4) {
        if (silhouette.pixels[i + 3] != 0) {
            continue;
        }
        const std::uint8_t* p = &frame.pixels[i];
        ++result.pixels;
        result.white += p[0] == 255 && p[1] == 255 && p[2] == 255 ? 1 : 0;
        result.darkest = std::min({result.darkest, int(p[0]), int(p[1]), int(p[2])});
    }
    return result;
}

}  // namespace

TEST(ShadowCatcherOverHttp, OnWhiteOnlyTheProductAndItsShadowDiffer) {
    TempRoot root;
    TestServer server(test_config(root.data()));
    auto client = server.client();
    const Rgba8Image silhouette = get_frame(*client, kScene + "&ground=off&background=transparent");
    const Rgba8Image opaque = get_frame(*client, kScene);
    const double bakes = transfers_computed(*client);

    const Rgba8Image white = get_frame(*client, kScene + "&ground=shadow&background=%23ffffff");
    ASSERT_EQ(white.width, 256);
    const OffProduct lit = off_product(white, silhouette);
    // The horizon and most of the floor are the page's white, exactly; the shadow under the
    // product is clearly darker.
    EXPECT_GT(lit.white, lit.pixels / 2) << lit.white << " of " << lit.pixels;
    EXPECT_LT(lit.darkest, 200);
    // The opaque floor is no white page.
    EXPECT_LT(off_product(opaque, silhouette).white, lit.pixels / 20);
    // The shadow-only floor is the opaque floor's scene: no bake of its own.
    EXPECT_EQ(transfers_computed(*client), bakes);

    // Every light off: their shadows go, the contact shadow (the residual map's occlusion) stays.
    const auto rig = client->Get("/v1/environments/default");
    ASSERT_TRUE(rig);
    const std::size_t lights = Json::parse(rig->body).at("lights").size();
    ASSERT_GT(lights, 0u);
    std::string off = "&lights=0";
    for (std::size_t k = 1; k < lights; ++k) {
        off += ",0";
    }
    const Rgba8Image unlit_frame =
        get_frame(*client, kScene + "&ground=shadow&background=%23ffffff" + off);
    const OffProduct unlit = off_product(unlit_frame, silhouette);
    // (Under the residual map alone the contact shadow is a larger share of the floor's light,
    // so it reaches farther: fewer pixels stay exactly white, but far from the product all do.)
    std::printf("off the product, lights on: %ld of %ld white, darkest %d; off: %ld, darkest %d\n",
                lit.white, lit.pixels, lit.darkest, unlit.white, unlit.darkest);
    EXPECT_GT(unlit.white, lit.pixels / 4);
    // The lights' shadows go: pixels clearly in a light's shadow (under 230) come back to
    // nearly the page's white (250 or more). (Their darkest pixel need not get lighter: in the
    // default studio's bright room the residual map lights the floor most, so the contact
    // shadow under the stand, alone, is darker than with the lights adding to it.)
    long returned = 0;
    for (std::size_t i = 0; i < white.pixels.size(); i += 4) {
        returned +=
            silhouette.pixels[i + 3] == 0 && white.pixels[i] < 230 && unlit_frame.pixels[i] >= 250
                ? 1
                : 0;
    }
    std::printf("in a light's shadow with the lights on, back to white with them off: %ld\n",
                returned);
    EXPECT_GT(returned, 200);
    EXPECT_LT(unlit.darkest, 250) << "the contact shadow";

    // Over transparency: black, the shadow in the alpha, none far from the product.
    const Rgba8Image clear = get_frame(*client, kScene + "&ground=shadow&background=transparent");
    int strongest = 0;
    long transparent = 0;
    for (std::size_t i = 0; i < clear.pixels.size(); i += 4) {
        if (silhouette.pixels[i + 3] != 0) {
            continue;
        }
        const std::uint8_t* p = &clear.pixels[i];
        if (p[3] > 0) {
            EXPECT_EQ(p[0] + p[1] + p[2], 0) << "pixel " << i / 4;
        }
        strongest = std::max(strongest, int(p[3]));
        transparent += p[3] == 0 ? 1 : 0;
    }
    EXPECT_GT(strongest, 255 - lit.darkest - 8);
    EXPECT_GT(transparent, lit.pixels / 2);
}
