#pragma once
// The render workers: one RenderThread (one GL context) and one FrameRenderer each, made and
// used on that thread only. HTTP threads submit jobs and wait on the future with their own
// deadline. The number of jobs in flight is bounded (every worker busy plus max_waiting
// queued): past it submit() throws QueueFull at once, so a burst of requests gets prompt 503s
// instead of an ever longer queue.
#include <atomic>
#include <cstddef>
#include <functional>
#include <future>
#include <memory>
#include <stdexcept>
#include <vector>

#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/gl_context.hpp"

namespace oer::server {

class QueueFull : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

class RenderPool {
  public:
    using Job = std::function<Frame(FrameRenderer&)>;
    // Called with the number of jobs waiting for a worker whenever it changes (for a gauge).
    using DepthObserver = std::function<void(std::size_t waiting)>;

    // Starts `workers` threads, each creating its GL context and FrameRenderer; throws what
    // GlContext::create throws.
    RenderPool(int workers, int max_waiting, const FrameLimits& limits,
               DepthObserver observer = {});
    // Finishes the jobs in flight, then destroys each renderer on its own thread.
    ~RenderPool();
    RenderPool(const RenderPool&) = delete;
    RenderPool& operator=(const RenderPool&) = delete;

    // Runs job on the worker with the fewest jobs; the future carries its frame or exception.
    // Throws QueueFull when workers + max_waiting jobs are already in flight.
    std::future<Frame> submit(Job job);

    // Runs job once on every worker and waits (the test frame that makes the pool ready);
    // rethrows the first failure.
    void run_on_every_worker(const Job& job);

    std::size_t waiting() const;  // jobs accepted but not yet started
    int worker_count() const { return int(workers_.size()); }
    const GlInfo& info() const;
    const FrameLimits& limits() const { return limits_; }  // every worker's

  private:
    struct Worker;
    std::future<Frame> enqueue(Worker& worker, Job job);
    void notify();

    const std::size_t capacity_;
    const FrameLimits limits_;
    const DepthObserver observer_;
    std::atomic<std::size_t> in_flight_{0};
    std::atomic<std::size_t> running_{0};
    std::vector<std::unique_ptr<Worker>> workers_;
};

}  // namespace oer::server
