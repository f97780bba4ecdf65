#include "oer/gl/render_thread.hpp"

#include <pthread.h>

#include <exception>
#include <string>
#include <utility>

#include "oer/core/error.hpp"
#include "oer/core/thread_priority.hpp"

namespace oer {

RenderThread::RenderThread(int nice) {
    if (nice < 0 || nice > 19) {
        throw Error(ErrorKind::InvalidInput,
                    "a render thread's nice increment is 0..19, got " + std::to_string(nice));
    }
    std::promise<void> started;
    std::future<void> ready = started.get_future();
    // The thread owns the promise, so that its shared state outlives set_value even when this
    // constructor returns (or throws) first.
    thread_ =
        std::thread([this, nice, promise = std::move(started)]() mutable { run(promise, nice); });
    try {
        ready.get();
    } catch (...) {
        thread_.join();
        throw;
    }
}

RenderThread::~RenderThread() {
    {
        const std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

std::size_t RenderThread::queue_depth() const {
    const std::lock_guard lock(mutex_);
    return jobs_.size();
}

void RenderThread::enqueue(std::function<void()> job) {
    {
        const std::lock_guard lock(mutex_);
        jobs_.push_back(std::move(job));
    }
    wake_.notify_one();
}

void RenderThread::run(std::promise<void>& started, int nice) {
    pthread_setname_np(pthread_self(), "oer-render");
    std::unique_ptr<GlContext> context;
    try {
        if (nice > 0) {
            lower_thread_priority(nice, "the render thread");
        }
        context = GlContext::create();
        info_ = context->info();
    } catch (...) {
        started.set_exception(std::current_exception());
        return;
    }
    started.set_value();

    for (;;) {
        std::function<void()> job;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
            if (jobs_.empty()) {
                break;  // stopping, and every job submitted has run
            }
            job = std::move(jobs_.front());
            jobs_.pop_front();
        }
        try {
            job();  // a packaged_task: its exception goes to its future
        } catch (...) {
            // Nothing to report to: keep serving the other jobs.
        }
    }
    context.reset();
}

}  // namespace oer
