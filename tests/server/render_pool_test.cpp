#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <set>
#include <thread>

#include "oer/core/error.hpp"
#include "render_pool.hpp"

using namespace oer;
using oer::server::QueueFull;
using oer::server::RendererUnavailable;
using oer::server::RenderPool;

namespace {

// A job that holds its worker until `release` is set.
RenderPool::Job blocking_job(std::shared_future<void> release, std::atomic<int>& started) {
    return [release, &started](FrameRenderer&) {
        ++started;
        release.wait();
        return Frame{};
    };
}

Frame no_frame(FrameRenderer&) {
    return Frame{};
}

bool eventually(const std::function<bool()>& condition) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!condition()) {
        if (std::chrono::steady_clock::now() > end) {
            return false;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return true;
}

}  // namespace

TEST(RenderPool, RefusesJobsBeyondTheWorkersAndTheQueueAtOnce) {
    std::atomic<std::size_t> observed{0};
    RenderPool pool(1, 2, FrameLimits{}, [&observed](std::size_t waiting) { observed = waiting; });
    pool.start(no_frame);
    std::promise<void> gate;
    const std::shared_future<void> release = gate.get_future().share();
    std::atomic<int> started{0};

    std::vector<std::future<Frame>> accepted;
    for (int i = 0; i < 3; ++i) {  // one running, two waiting
        accepted.push_back(pool.submit(blocking_job(release, started)));
    }
    ASSERT_TRUE(eventually([&] { return started == 1; }));
    EXPECT_EQ(pool.waiting(), 2u);
    EXPECT_EQ(observed.load(), 2u);

    const auto before = std::chrono::steady_clock::now();
    EXPECT_THROW(pool.submit(blocking_job(release, started)), QueueFull);
    EXPECT_LT(std::chrono::steady_clock::now() - before, std::chrono::milliseconds(100));

    gate.set_value();
    for (auto& frame : accepted) {
        frame.get();
    }
    EXPECT_EQ(started, 3);
    ASSERT_TRUE(eventually([&] { return pool.waiting() == 0 && observed.load() == 0; }));
    // Room again once the jobs are done.
    EXPECT_NO_THROW(pool.submit(blocking_job(release, started)).get());
}

// Over capacity, a job waits for a place as the admission allows: it takes one freed within
// the wait, is refused when none is, and is refused at once when as many jobs wait already.
TEST(RenderPool, AJobOverCapacityTakesAPlaceFreedWithinTheWait) {
    using namespace std::chrono_literals;
    RenderPool pool(1, 0, FrameLimits{}, {}, {10s, 4});
    pool.start(no_frame);
    std::promise<void> gate;
    const std::shared_future<void> release = gate.get_future().share();
    std::atomic<int> started{0};
    auto first = pool.submit(blocking_job(release, started));
    ASSERT_TRUE(eventually([&] { return started == 1; }));

    std::atomic<bool> submitted{false};
    std::thread second([&] {
        pool.submit(no_frame).get();
        submitted = true;
    });
    std::this_thread::sleep_for(200ms);
    EXPECT_FALSE(submitted) << "a job over capacity was taken before a place was free";
    const auto freed = std::chrono::steady_clock::now();
    gate.set_value();
    first.get();
    second.join();
    EXPECT_TRUE(submitted);
    EXPECT_LT(std::chrono::steady_clock::now() - freed, 5s) << "it waited for the whole wait";
}

TEST(RenderPool, AJobOverCapacityIsRefusedAfterTheWait) {
    using namespace std::chrono_literals;
    RenderPool pool(1, 1, FrameLimits{}, {}, {300ms, 4});
    pool.start(no_frame);
    std::promise<void> gate;
    const std::shared_future<void> release = gate.get_future().share();
    std::atomic<int> started{0};
    auto running = pool.submit(blocking_job(release, started));
    auto queued = pool.submit(blocking_job(release, started));
    const auto before = std::chrono::steady_clock::now();
    EXPECT_THROW(pool.submit(no_frame), QueueFull);
    const auto waited = std::chrono::steady_clock::now() - before;
    EXPECT_GE(waited, 300ms);
    EXPECT_LT(waited, 3s);
    gate.set_value();
    running.get();
    queued.get();
}

TEST(RenderPool, BeyondTheWaitersTheRefusalIsAtOnce) {
    using namespace std::chrono_literals;
    RenderPool pool(1, 0, FrameLimits{}, {}, {10s, 1});
    pool.start(no_frame);
    std::promise<void> gate;
    const std::shared_future<void> release = gate.get_future().share();
    std::atomic<int> started{0};
    auto running = pool.submit(blocking_job(release, started));
    ASSERT_TRUE(eventually([&] { return started == 1; }));
    std::thread waiter([&] { pool.submit(no_frame).get(); });  // the one waiter allowed
    std::this_thread::sleep_for(200ms);
    const auto before = std::chrono::steady_clock::now();
    EXPECT_THROW(pool.submit(no_frame), QueueFull);
    EXPECT_LT(std::chrono::steady_clock::now() - before, 2s);
    gate.set_value();
    running.get();
    waiter.join();  // took the place the running job freed
}

TEST(RenderPool, AFailingJobFreesItsPlace) {
    RenderPool pool(1, 0, FrameLimits{});
    pool.start(no_frame);
    for (int i = 0; i < 3; ++i) {
        auto failing = pool.submit(
            [](FrameRenderer&) -> Frame { throw Error(ErrorKind::InvalidInput, "bad frame"); });
        EXPECT_THROW(failing.get(), Error);
    }
    EXPECT_EQ(pool.waiting(), 0u);
}

TEST(RenderPool, StartRunsTheTestOnEveryWorker) {
    RenderPool pool(2, 0, FrameLimits{});
    EXPECT_EQ(pool.info(), nullptr);
    EXPECT_EQ(pool.worker_count(), 0);
    std::mutex mutex;
    std::set<std::thread::id> threads;
    pool.start([&](FrameRenderer&) {
        const std::lock_guard lock(mutex);
        threads.insert(std::this_thread::get_id());
        return Frame{};
    });
    EXPECT_EQ(threads.size(), 2u);
    EXPECT_TRUE(pool.started());
    EXPECT_EQ(pool.worker_count(), 2);
    ASSERT_NE(pool.info(), nullptr);
    EXPECT_FALSE(pool.info()->renderer.empty());
}

// A pool whose start failed keeps no worker, answers every job with the reason, and starts
// when asked again once the cause is gone.
TEST(RenderPool, AFailedStartIsReportedUntilAStartSucceeds) {
    RenderPool pool(2, 4, FrameLimits{});
    try {
        pool.submit(no_frame);
        ADD_FAILURE() << "a pool that has not started took a job";
    } catch (const RendererUnavailable& error) {
        EXPECT_STREQ(error.what(), "the renderer has not started yet");
    }
    EXPECT_THROW(pool.start([](FrameRenderer&) -> Frame {
        throw Error(ErrorKind::Internal, "no GL device");
    }),
                 Error);
    EXPECT_FALSE(pool.started());
    EXPECT_EQ(pool.worker_count(), 0);
    EXPECT_EQ(pool.failure(), "no GL device");
    EXPECT_EQ(pool.waiting(), 0u);
    try {
        pool.submit(no_frame);
        ADD_FAILURE() << "a pool whose start failed took a job";
    } catch (const RendererUnavailable& error) {
        EXPECT_STREQ(error.what(), "the renderer could not start: no GL device");
    }

    pool.start(no_frame);
    EXPECT_TRUE(pool.started());
    EXPECT_EQ(pool.failure(), "");
    EXPECT_NO_THROW(pool.submit(no_frame).get());
}
