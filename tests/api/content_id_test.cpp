#include <gtest/gtest.h>

#include "oer/api/content_id.hpp"
#include "oer/api/rig_options.hpp"

using namespace oer;

TEST(ContentId, Sha256MatchesTheStandardTestVectors) {
    // FIPS 180-2, appendix B.1 and the empty message.
    EXPECT_EQ(api::sha256_hex(std::string_view("abc")),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(api::sha256_hex(std::string_view("")),
              "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(ContentId, RigIdDependsOnSourceAndOptions) {
    const RigOptions defaults;
    RigOptions other;
    other.sh_order = 5;
    const std::string a = api::rig_id("source-a", defaults);
    EXPECT_EQ(a, api::rig_id("source-a", defaults));
    EXPECT_NE(a, api::rig_id("source-b", defaults));
    EXPECT_NE(a, api::rig_id("source-a", other));
    EXPECT_EQ(a.size(), 64u);
    // Options given explicitly at their default value are the same options.
    EXPECT_EQ(a, api::rig_id("source-a", api::parse_rig_options({{"max_lights", "4"}})));
}
