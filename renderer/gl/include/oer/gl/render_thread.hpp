#pragma once
// One thread that owns one GL context: callers submit jobs, which run on that thread in
// order, so that the GL API is used from one thread only and is thread-safe by construction.
// Several RenderThreads may run side by side, each with its own context.
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>

#include "oer/gl/gl_context.hpp"

namespace oer {

class RenderThread {
  public:
    // Starts the thread and creates its context (current on that thread for every job); waits
    // for it and throws what GlContext::create throws. `nice` (0..19) is added to the thread's
    // nice value before the context exists, so that the threads the driver starts for it
    // (llvmpipe's rasterizers) inherit it: a server runs its frames below its request threads,
    // which then preempt them at once (setpriority(2): the nice value is per thread on Linux).
    explicit RenderThread(int nice = 0);
    // Finishes the jobs already submitted (and those they submit), then destroys the context
    // and joins. No job is dropped: every future becomes ready.
    ~RenderThread();
    RenderThread(const RenderThread&) = delete;
    RenderThread& operator=(const RenderThread&) = delete;

    const GlInfo& info() const { return info_; }

    // Runs job() on the GL thread, after the jobs submitted before it; the future carries its
    // result or its exception (the thread keeps running). A job must not wait for a job it
    // submits to the same thread.
    template <typename Job>
    auto submit(Job job) -> std::future<std::invoke_result_t<Job>> {
        using Result = std::invoke_result_t<Job>;
        auto task = std::make_shared<std::packaged_task<Result()>>(std::move(job));
        std::future<Result> result = task->get_future();
        enqueue([task] { (*task)(); });
        return result;
    }

    // The jobs waiting to start (not counting one that is running).
    std::size_t queue_depth() const;

  private:
    void enqueue(std::function<void()> job);
    // The thread's body: lowers its priority by nice, creates the context, reports it through
    // `started`, runs jobs.
    void run(std::promise<void>& started, int nice);

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> jobs_;
    bool stopping_ = false;
    GlInfo info_;
    std::thread thread_;
};

}  // namespace oer
