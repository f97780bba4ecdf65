#include "oer/gl/render_thread.hpp"

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <string>
#include <utility>

#include "oer/core/error.hpp"

namespace oer {

namespace {

// Adds nice to the calling thread's nice value (Linux: setpriority on a thread id affects that
// thread alone).
void lower_priority(int nice) {
    const pid_t self = ::gettid();
    errno = 0;
    const int current = ::getpriority(PRIO_PROCESS, id_t(self));
    if ((current == -1 && errno != 0) ||
        ::setpriority(PRIO_PROCESS, id_t(self), current + nice) != 0) {
        throw Error(ErrorKind::Internal, "cannot lower the render thread's priority by " +
                                             std::to_string(nice) + ": " + std::strerror(errno));
    }
}

}  // namespace

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
            lower_priority(nice);
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
