// The benchmarks' shared helpers that turn measurements into printed figures: a wrong parse of
// the server's per-pass times or a wrong percentile would print wrong figures without failing.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "bench_support.hpp"
#include "oer/core/error.hpp"

using namespace oer;
using Entries = std::vector<std::pair<std::string, double>>;

namespace {

// The message parse_server_timing throws for `header`, or "" when it accepts it.
std::string rejection(const std::string& header) {
    try {
        bench::parse_server_timing(header);
    } catch (const Error& error) {
        EXPECT_EQ(error.kind(), ErrorKind::InvalidInput) << header;
        return error.what();
    }
    return "";
}

}  // namespace

TEST(BenchSupport, ServerTimingReadsOerServersEntriesInOrder) {
    // As server/src/frame_service.cpp writes it: the renderer's passes by name, then encode.
    EXPECT_EQ(
        bench::parse_server_timing("geometry_pass;dur=1.25, readback;dur=0.50, "
                                   "shadow_pass;dur=0.00, encode;dur=12.75"),
        (Entries{
            {"geometry_pass", 1.25}, {"readback", 0.5}, {"shadow_pass", 0.0}, {"encode", 12.75}}));
    EXPECT_EQ(bench::parse_server_timing("total;dur=7"), (Entries{{"total", 7.0}}));
    // A cached frame has no Server-Timing: no entries.
    EXPECT_EQ(bench::parse_server_timing(""), Entries{});
}

TEST(BenchSupport, ServerTimingErrorsQuoteTheHeader) {
    EXPECT_EQ(rejection("shadow_pass"), "Server-Timing \"shadow_pass\": 'shadow_pass' has no dur");
    EXPECT_EQ(rejection("encode;dur=fast"),
              "Server-Timing \"encode;dur=fast\": 'encode' has dur 'fast', not a number");
    EXPECT_EQ(rejection("encode;dur=1.5ms"),
              "Server-Timing \"encode;dur=1.5ms\": 'encode' has dur '1.5ms', not a number");
    EXPECT_EQ(rejection("a;dur=1, ;dur=2"),
              "Server-Timing \"a;dur=1, ;dur=2\": an entry without a name");
}

TEST(BenchSupport, PercentilesAreNearestRankSamples) {
    const std::vector<double> values = {50.0, 10.0, 30.0, 20.0, 40.0};
    EXPECT_EQ(bench::percentile(values, 0.0), 10.0);
    EXPECT_EQ(bench::percentile(values, 0.5), 30.0);
    EXPECT_EQ(bench::percentile(values, 0.9), 50.0);   // rank 0.9 * 4 = 3.6, nearest 4
    EXPECT_EQ(bench::percentile(values, 0.65), 40.0);  // rank 2.6: nearest 3, truncated 2
    EXPECT_EQ(bench::percentile(values, 1.0), 50.0);
    EXPECT_EQ(bench::percentile({}, 0.5), 0.0);
}
