#include <gtest/gtest.h>

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/light_switches.hpp"

using namespace oer;
using oer::api::InvalidParameter;

TEST(LightSwitches, ParsesOnOffAndChecksTheCount) {
    EXPECT_EQ(api::parse_light_switches("1,0,1", 3), (std::vector<double>{1.0, 0.0, 1.0}));
    EXPECT_EQ(api::parse_light_switches(std::nullopt, 2), (std::vector<double>{1.0, 1.0}));
    EXPECT_THROW(api::parse_light_switches("1,0", 3), InvalidParameter);
    EXPECT_THROW(api::parse_light_switches("1,0,1,1", 3), InvalidParameter);
    EXPECT_THROW(api::parse_light_switches("1,2,1", 3), InvalidParameter);
    EXPECT_THROW(api::parse_light_switches("1,,1", 3), InvalidParameter);
    EXPECT_THROW(api::parse_light_switches("", 1), InvalidParameter);
}

TEST(LightSwitches, ListsAreWeightsAndSwitchesStayOnOff) {
    EXPECT_EQ(api::parse_light_list("1,0.5,0,4", 4), (std::vector<double>{1.0, 0.5, 0.0, 4.0}));
    EXPECT_THROW(api::parse_light_list("1,4.5", 4), InvalidParameter);
    EXPECT_THROW(api::parse_light_list("1,0,1", 2), InvalidParameter);
    // The environment's irradiance takes on/off only.
    EXPECT_THROW(api::parse_light_switches("1,0.5,1", 3), InvalidParameter);
}
