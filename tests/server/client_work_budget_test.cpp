// The per-client token bucket of uncached render work (server/src/client_work_budget.hpp), on
// an injected clock.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "client_work_budget.hpp"

using oer::server::ClientWorkBudget;
using Clock = ClientWorkBudget::Clock;
using std::chrono::milliseconds;

TEST(ClientWorkBudget, AClientSpendsItsBurstThenWaitsForWhatItEarns) {
    ClientWorkBudget budget(0.5, 10.0);  // half a second of work a second, 10 s saved up
    const Clock::time_point start = Clock::now();
    EXPECT_EQ(budget.charge("a", 4.0, start), std::nullopt);
    EXPECT_EQ(budget.charge("a", 6.0, start), std::nullopt);
    // Empty: 1 s of work needs 2 s of earning.
    const auto wait = budget.charge("a", 1.0, start);
    ASSERT_TRUE(wait);
    EXPECT_NEAR(*wait, 2.0, 1e-9);
    // A refusal charges nothing: after 1 s it has 0.5 s, after 2 s the 1 s it asked for.
    EXPECT_NEAR(budget.charge("a", 1.0, start + milliseconds(1000)).value_or(-1.0), 1.0, 1e-9);
    EXPECT_EQ(budget.charge("a", 1.0, start + milliseconds(2000)), std::nullopt);
}

TEST(ClientWorkBudget, ClientsAreChargedApart) {
    ClientWorkBudget budget(1.0, 5.0);
    const Clock::time_point now = Clock::now();
    EXPECT_EQ(budget.charge("127.0.0.1", 5.0, now), std::nullopt);
    EXPECT_TRUE(budget.charge("127.0.0.1", 0.1, now));
    EXPECT_EQ(budget.charge("127.0.0.2", 5.0, now), std::nullopt);
}

TEST(ClientWorkBudget, SavingsStopAtTheBurstAndOneRenderNeverNeedsMore) {
    ClientWorkBudget budget(1.0, 5.0);
    const Clock::time_point start = Clock::now();
    EXPECT_EQ(budget.charge("a", 5.0, start), std::nullopt);
    // An hour idle refills 5 s, not 3600.
    const Clock::time_point later = start + std::chrono::hours(1);
    EXPECT_EQ(budget.charge("a", 5.0, later), std::nullopt);
    EXPECT_TRUE(budget.charge("a", 0.5, later));
    // A render estimated beyond the burst costs the burst: a full bucket pays for it.
    EXPECT_EQ(budget.charge("b", 50.0, start), std::nullopt);
}

TEST(ClientWorkBudget, ARateOfZeroChargesNothing) {
    ClientWorkBudget budget(0.0, 1.0);
    for (int i = 0; i < 100; ++i) {
        EXPECT_EQ(budget.charge("a", 1.0), std::nullopt);
    }
    EXPECT_EQ(budget.clients(), 0u);
}

// What is kept stays bounded: clients whose buckets have refilled are forgotten when the table
// is full, and when every one is in debt the tenth least in debt goes.
TEST(ClientWorkBudget, TheBucketsKeptStayBounded) {
    ClientWorkBudget budget(1.0, 2.0);
    const Clock::time_point start = Clock::now();
    for (std::size_t i = 0; i < ClientWorkBudget::kMaxClients; ++i) {
        ASSERT_EQ(budget.charge("c" + std::to_string(i), 1.0, start), std::nullopt);
    }
    EXPECT_EQ(budget.clients(), ClientWorkBudget::kMaxClients);
    // Still in debt: the table is trimmed by a tenth to take the newcomer.
    EXPECT_EQ(budget.charge("newcomer", 1.0, start), std::nullopt);
    EXPECT_LE(budget.clients(), ClientWorkBudget::kMaxClients);
    EXPECT_GE(budget.clients(), ClientWorkBudget::kMaxClients * 8 / 10);
    // A second later the old buckets have refilled: the next time the table is full, they go.
    const Clock::time_point later = start + std::chrono::seconds(1);
    std::size_t added = 0;
    while (budget.clients() >= ClientWorkBudget::kMaxClients / 2 &&
           added < ClientWorkBudget::kMaxClients) {
        EXPECT_EQ(budget.charge("d" + std::to_string(added++), 1.0, later), std::nullopt);
    }
    EXPECT_LT(budget.clients(), ClientWorkBudget::kMaxClients / 2);
}
