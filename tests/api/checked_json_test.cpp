// The one bounded JSON parser (oer/core/checked_json.hpp): values and nesting counted exactly,
// documents over a bound refused before anything is built.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "oer/core/checked_json.hpp"

using namespace oer;
using checked_json::JsonBounds;
using checked_json::JsonParseError;
using checked_json::parse_bounded;

namespace {

JsonParseError::Cause cause_of(const std::string& text, const JsonBounds& bounds) {
    try {
        parse_bounded(text, bounds);
    } catch (const JsonParseError& error) {
        return error.cause();
    }
    ADD_FAILURE() << text << ": parsed";
    return JsonParseError::Cause::Syntax;
}

}  // namespace

TEST(CheckedJson, EveryValueCountsObjectsAndArraysIncluded) {
    // The outer array, 1, the inner array, 2, "x", the object, null: 7 values (keys are not).
    const std::string text = R"([1, [2, "x"], {"a": null}])";
    EXPECT_EQ(parse_bounded(text, {7, 8}).size(), 3u);
    EXPECT_EQ(cause_of(text, {6, 8}), JsonParseError::Cause::TooMany);
    try {
        parse_bounded(text, {6, 8});
    } catch (const JsonParseError& error) {
        EXPECT_STREQ(error.what(), "the JSON holds more than 6 values");
    }
}

TEST(CheckedJson, NestingCountsObjectsAndArraysInsideEachOther) {
    const std::string three = R"({"a": [{"b": 1}]})";
    EXPECT_NO_THROW(parse_bounded(three, {100, 3}));
    EXPECT_EQ(cause_of(three, {100, 2}), JsonParseError::Cause::TooDeep);
    EXPECT_EQ(cause_of(std::string(100000, '[') + std::string(100000, ']'), {100000000, 128}),
              JsonParseError::Cause::TooDeep);
    EXPECT_NO_THROW(parse_bounded("5", {1, 0}));  // a scalar document nests nothing
}

TEST(CheckedJson, SyntaxErrorsSayWhereWithoutTheLibrarysTag) {
    try {
        parse_bounded("{\n  \"a\": x}", {100, 8});
        FAIL() << "parsed";
    } catch (const JsonParseError& error) {
        EXPECT_EQ(error.cause(), JsonParseError::Cause::Syntax);
        const std::string message = error.what();
        EXPECT_EQ(message.rfind("parse error at line 2, column", 0), 0u) << message;
    }
    EXPECT_EQ(cause_of("[1, 2", {100, 8}), JsonParseError::Cause::Syntax);
    EXPECT_EQ(cause_of("[1] trailing", {100, 8}), JsonParseError::Cause::Syntax);
}

TEST(CheckedJson, ManyValuesAreRefusedWithoutBuildingThem) {
    // 2 million values in 4 MB, bound 1000: refused at the 1001st, long before the end.
    std::string text = "[0";
    for (int i = 1; i < 2'000'000; ++i) {
        text += ",0";
    }
    text += "]";
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(cause_of(text, {1000, 8}), JsonParseError::Cause::TooMany);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              0.05);
    // An array of many small objects parses in linear time (nlohmann's parser callback, which
    // scans the array each time an object in it ends, took 21 s for 131000; linear, it takes
    // 0.3 s optimised and 2.1 s under the sanitizers on a loaded 2-core machine).
    std::string objects = "[{\"k\":0}";
    for (int i = 1; i < 131'000; ++i) {
        objects += ",{\"k\":0}";
    }
    objects += "]";
    const auto again = std::chrono::steady_clock::now();
    EXPECT_EQ(parse_bounded(objects, {1'000'000, 8}).size(), 131'000u);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - again).count(), 6.0);
}
