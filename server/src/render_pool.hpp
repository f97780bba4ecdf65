#pragma once
// The render workers: one RenderThread (one GL context) and one FrameRenderer each, made and
// used on that thread only, 10 below the HTTP threads' priority (nice). HTTP threads submit jobs
// and wait on the future with their own deadline. The number of jobs in flight is bounded (every
// worker busy plus max_waiting queued), so that a burst of requests never makes an ever longer
// queue. A job beyond it waits for a place at most RenderAdmission::wait (taking the first that a
// finished job frees), and is then refused: submit() throws QueueFull, answered 503 with
// Retry-After.
//
// Why wait before refusing (measured by tests/integration/load_test.cpp): a client
// that retries a refusal at once, as load generators and impatient scripts do, gets refusals as
// fast as the server can answer them. 64 such clients on 2 cores made 7400-8000 refusals a
// second, and the renders, sharing the CPU with them (the scheduler shares it by runnable
// thread, and each such client keeps one runnable, on its side or on the server's), took 5
// times as long: 18-20 % of the frames that 5 clients waiting their turn got. Held for the wait,
// such a client costs one request per wait, and the renders keep their pace. The waiters are
// bounded too (RenderAdmission::max_waiters), since each holds an HTTP thread; past them the
// refusal is at once. This is the blocking limiter of Netflix's concurrency-limits library (a
// bounded wait for a permit, then rejection).
//
// A pool starts without workers: start() makes them and may fail (no GL device, a driver that
// cannot make a context), and the service keeps running meanwhile, answering renders 503
// (RendererUnavailable) and saying why, while it tries again.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/gl_context.hpp"

namespace oer::server {

// The workers' nice increment (inherited by the driver's rasterizer threads): frames are
// throughput work, answers from memory latency work, so HTTP threads preempt the renders
// rather than wait for a time slice behind them. With the workers saturated on 2 cores, 16
// clients' cached frames had a p99 of 6-12 ms at the same priority and 4-4.5 ms at 5 or 10
// below (tests/integration/load_test.cpp); with no requests the renders have the CPU alone.
inline constexpr int kRenderNice = 10;
// The batch jobs' worker (job_service.hpp): the lowest priority, as the bake lane's, so that
// an interactive frame takes the cores from a batch frame at once (nice 19 against 10 weighs
// 15 against 110 in the kernel's fair scheduler: under 12 % of a contended core).
inline constexpr int kBatchNice = 19;

class QueueFull : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// The pool has no workers: not started yet, or its start failed (the message says why).
class RendererUnavailable : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// How a job beyond the workers and the queue is treated: it waits up to `wait` for a place,
// while fewer than `max_waiters` wait; otherwise it is refused at once.
struct RenderAdmission {
    std::chrono::milliseconds wait{0};
    std::size_t max_waiters = 0;
};

class RenderPool {
  public:
    using Job = std::function<Frame(FrameRenderer&)>;
    // Called with the number of jobs waiting for a worker whenever it changes (for a gauge).
    using DepthObserver = std::function<void(std::size_t waiting)>;

    // Makes no worker yet: start() does.
    // nice: the workers' nice increment (kRenderNice; the batch jobs' pool, kBatchNice).
    RenderPool(int workers, int max_waiting, const FrameLimits& limits, DepthObserver observer = {},
               RenderAdmission admission = {}, int nice = kRenderNice);
    // Finishes the jobs in flight, then destroys each renderer on its own thread.
    ~RenderPool();
    RenderPool(const RenderPool&) = delete;
    RenderPool& operator=(const RenderPool&) = delete;

    // Starts the worker threads, each creating its GL context and FrameRenderer, and runs
    // `test` once on every worker (the test frame that makes the pool ready). On any failure
    // it destroys what it made, remembers the failure (failure()) and rethrows it. Not to be
    // called by two threads at once; a started pool ignores it.
    void start(const Job& test);
    bool started() const { return started_.load(std::memory_order_acquire); }
    // Why the last start failed; empty when none did.
    std::string failure() const;

    // Runs job on the worker with the fewest jobs; the future carries its frame or exception.
    // Throws RendererUnavailable before the pool has started, QueueFull when workers +
    // max_waiting jobs are in flight and no place freed within the admission wait.
    std::future<Frame> submit(Job job);

    std::size_t waiting() const;  // jobs accepted but not yet started
    // No job accepted and unfinished: what a batch frame waits for (FrameService::rendered).
    bool idle() const { return in_flight_.load() == 0; }
    int worker_count() const { return started() ? int(workers_.size()) : 0; }
    // The first worker's GL; nullptr before the pool has started.
    const GlInfo* info() const;
    const FrameLimits& limits() const { return limits_; }  // every worker's

  private:
    struct Worker;
    std::future<Frame> enqueue(Worker& worker, Job job);
    void notify();
    // Takes a place in flight if there is one; whether it did.
    bool take_place();
    // Takes a place, waiting for one as the admission allows; whether it did.
    bool admit();
    // A job ended: its place goes to a waiting job, if any.
    void free_place();

    const int worker_target_;
    const int nice_;
    const std::size_t capacity_;
    const FrameLimits limits_;
    const DepthObserver observer_;
    const RenderAdmission admission_;
    std::atomic<std::size_t> in_flight_{0};
    std::mutex admission_mutex_;
    std::condition_variable place_freed_;
    std::size_t admission_waiters_ = 0;  // guarded by admission_mutex_
    std::atomic<std::size_t> running_{0};
    // Written by start() only before started_ is set (release), read only after it is seen
    // set (acquire).
    std::vector<std::unique_ptr<Worker>> workers_;
    std::atomic<bool> started_{false};
    mutable std::mutex failure_mutex_;
    std::string failure_;
};

}  // namespace oer::server
