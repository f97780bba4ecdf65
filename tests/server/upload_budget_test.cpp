// The upload budget: slots and bytes reserved and given back, refusals at once (503 with
// Retry-After) while they are taken, and 413 for an upload that could never fit or that expands
// beyond its multiple of its own size.
#include <gtest/gtest.h>

#include <optional>

#include "http_errors.hpp"
#include "oer/core/error.hpp"
#include "upload_budget.hpp"

using namespace oer;
using namespace oer::server;

namespace {

constexpr std::uint64_t kMiB = 1ull << 20;

// The status and detail acquire() refuses with; nullopt when it reserved.
std::optional<std::pair<int, std::string>> refusal(UploadBudget& budget, std::uint64_t cost,
                                                   std::uint64_t upload_bytes) {
    try {
        const auto lease = budget.acquire(cost, upload_bytes, "this map");
    } catch (const HttpError& error) {
        EXPECT_EQ(error.headers(),
                  (HeaderList{{"Retry-After", std::to_string(kRetryAfterSeconds)}}));
        return std::pair(error.problem().status(), std::string(error.what()));
    } catch (const Error& error) {
        return std::pair(problem_type(problem_kind_of(error.kind())).status,
                         std::string(error.what()));
    }
    return std::nullopt;
}

}  // namespace

TEST(UploadBudget, SlotsAndBytesAreReservedUntilTheLeaseEnds) {
    UploadBudget budget(UploadBudgetLimits{100 * kMiB, 2, 0});
    {
        const auto first = budget.acquire(60 * kMiB, 1, "a");
        EXPECT_EQ(budget.reserved_bytes(), 60 * kMiB);
        EXPECT_EQ(budget.busy_slots(), 1);
        // 60 + 50 > 100: no room for the bytes although a slot is free.
        const auto bytes = refusal(budget, 50 * kMiB, 1);
        ASSERT_TRUE(bytes);
        EXPECT_EQ(bytes->first, 503);
        EXPECT_NE(bytes->second.find("1 of 2, 60 MiB of 100 MiB reserved; this one needs 50 MiB"),
                  std::string::npos)
            << bytes->second;
        {
            const auto second = budget.acquire(40 * kMiB, 1, "b");
            EXPECT_EQ(budget.reserved_bytes(), 100 * kMiB);
            // Both slots taken: even a tiny upload waits.
            ASSERT_TRUE(refusal(budget, 1, 1));
        }
        EXPECT_EQ(budget.busy_slots(), 1);
        EXPECT_EQ(refusal(budget, 40 * kMiB, 1), std::nullopt);
    }
    EXPECT_EQ(budget.reserved_bytes(), 0u);
    EXPECT_EQ(budget.busy_slots(), 0);
}

TEST(UploadBudget, AnUploadThatCouldNeverFitIs413) {
    UploadBudget budget(UploadBudgetLimits{100 * kMiB, 2, 0});
    const auto over = refusal(budget, 101 * kMiB, 1);
    ASSERT_TRUE(over);
    EXPECT_EQ(over->first, 413);
    EXPECT_EQ(over->second,
              "this map would take 101 MiB to decode and preprocess, more than the server's "
              "upload memory (100 MiB)");
    EXPECT_EQ(budget.busy_slots(), 0);
}

// max(64 MiB, expansion x bytes): a small upload may always reach 64 MiB, a larger one its
// multiple, and no more.
TEST(UploadBudget, AnUploadMayExpandToItsMultipleOrTheFloor) {
    UploadBudget budget(UploadBudgetLimits{4096 * kMiB, 2, 40});
    EXPECT_EQ(refusal(budget, kExpansionFloor, 155), std::nullopt);
    const auto bomb = refusal(budget, kExpansionFloor + 1, 155);
    ASSERT_TRUE(bomb);
    EXPECT_EQ(bomb->first, 413);
    EXPECT_NE(bomb->second.find("more than its 155 bytes may (40 times their size, or 64 MiB)"),
              std::string::npos)
        << bomb->second;
    EXPECT_EQ(refusal(budget, 40 * 10 * kMiB, 10 * kMiB), std::nullopt);
    EXPECT_TRUE(refusal(budget, 40 * 10 * kMiB + 1, 10 * kMiB));
    // Off: any expansion within the budget.
    UploadBudget any(UploadBudgetLimits{4096 * kMiB, 2, 0});
    EXPECT_EQ(refusal(any, 1024 * kMiB, 155), std::nullopt);
}
