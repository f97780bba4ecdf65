// The per-client token bucket of uncached render work (server/src/client_work_budget.hpp), on
// an injected clock.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "client_work_budget.hpp"

using oer::server::ClientWorkBudget;
using Clock = ClientWorkBudget::Clock;
using std::chrono::milliseconds;

TEST(ClientWorkBudget, AClientWorksUntilItsBucketIsEmptyThenWaitsForWhatItEarns) {
    ClientWorkBudget budget(0.5, 10.0);  // half a second of work a second, 10 s saved up
    const Clock::time_point start = Clock::now();
    EXPECT_EQ(budget.wait_before_work("a", start), std::nullopt);
    budget.charge("a", 4.0, start);
    EXPECT_EQ(budget.wait_before_work("a", start), std::nullopt);
    // A frame that took more than was left runs into debt: 1 s of debt takes 2 s to earn.
    budget.charge("a", 7.0, start);
    const auto wait = budget.wait_before_work("a", start);
    ASSERT_TRUE(wait);
    EXPECT_NEAR(*wait, 2.0, 1e-9);
    EXPECT_NEAR(budget.wait_before_work("a", start + milliseconds(1000)).value_or(-1.0), 1.0, 1e-9);
    EXPECT_EQ(budget.wait_before_work("a", start + milliseconds(2001)), std::nullopt);
}

TEST(ClientWorkBudget, ClientsAreChargedApart) {
    ClientWorkBudget budget(1.0, 5.0);
    const Clock::time_point now = Clock::now();
    budget.charge("127.0.0.1", 5.0, now);
    EXPECT_TRUE(budget.wait_before_work("127.0.0.1", now));
    EXPECT_EQ(budget.wait_before_work("127.0.0.2", now), std::nullopt);
}

TEST(ClientWorkBudget, SavingsAndDebtStopAtTheBurst) {
    ClientWorkBudget budget(1.0, 5.0);
    const Clock::time_point start = Clock::now();
    budget.charge("a", 5.0, start);
    // An hour idle refills 5 s, not 3600: 6 s of work leaves 1 s of debt.
    const Clock::time_point later = start + std::chrono::hours(1);
    budget.charge("a", 6.0, later);
    EXPECT_NEAR(budget.wait_before_work("a", later).value_or(-1.0), 1.0, 1e-9);
    // A frame of 100 s leaves at most the burst in debt: 5 s to wait, not 95.
    budget.charge("b", 100.0, start);
    EXPECT_NEAR(budget.wait_before_work("b", start).value_or(-1.0), 5.0, 1e-9);
}

TEST(ClientWorkBudget, ARateOfZeroChargesNothing) {
    ClientWorkBudget budget(0.0, 1.0);
    for (int i = 0; i < 100; ++i) {
        budget.charge("a", 1.0);
        EXPECT_EQ(budget.wait_before_work("a"), std::nullopt);
    }
    EXPECT_EQ(budget.clients(), 0u);
}

// What is kept stays bounded: clients whose buckets have refilled are forgotten when the table
// is full, and when every one is in debt the tenth least in debt goes.
TEST(ClientWorkBudget, TheBucketsKeptStayBounded) {
    ClientWorkBudget budget(1.0, 2.0);
    const Clock::time_point start = Clock::now();
    for (std::size_t i = 0; i < ClientWorkBudget::kMaxClients; ++i) {
        budget.charge("c" + std::to_string(i), 1.0, start);
    }
    EXPECT_EQ(budget.clients(), ClientWorkBudget::kMaxClients);
    // All still saving: the table is trimmed by a tenth to take the newcomer.
    budget.charge("newcomer", 1.0, start);
    EXPECT_LE(budget.clients(), ClientWorkBudget::kMaxClients);
    EXPECT_GE(budget.clients(), ClientWorkBudget::kMaxClients * 8 / 10);
    // A second later the old buckets have refilled: the next time the table is full, they go.
    const Clock::time_point later = start + std::chrono::seconds(1);
    std::size_t added = 0;
    while (budget.clients() >= ClientWorkBudget::kMaxClients / 2 &&
           added < ClientWorkBudget::kMaxClients) {
        budget.charge("d" + std::to_string(added++), 1.0, later);
    }
    EXPECT_LT(budget.clients(), ClientWorkBudget::kMaxClients / 2);
}
