#include "render_pool.hpp"

#include <algorithm>

#include "oer/gl/render_thread.hpp"

namespace oer::server {

struct RenderPool::Worker {
    explicit Worker(int nice) : thread(nice) {}
    RenderThread thread;
    std::unique_ptr<FrameRenderer> renderer;  // touched only by jobs on `thread`
    std::atomic<std::size_t> pending{0};
};

RenderPool::RenderPool(int workers, int max_waiting, const FrameLimits& limits,
                       DepthObserver observer, RenderAdmission admission, int nice)
    : worker_target_(std::max(workers, 1)),
      nice_(nice),
      capacity_(std::size_t(worker_target_) + std::size_t(std::max(max_waiting, 0))),
      limits_(limits),
      observer_(std::move(observer)),
      admission_(admission) {}

RenderPool::~RenderPool() {
    for (const auto& worker : workers_) {
        Worker* raw = worker.get();
        raw->thread.submit([raw] { raw->renderer.reset(); }).wait();
    }
}

void RenderPool::start(const Job& test) {
    if (started()) {
        return;
    }
    try {
        for (int i = 0; i < worker_target_; ++i) {
            auto worker = std::make_unique<Worker>(nice_);
            Worker* raw = worker.get();
            workers_.push_back(std::move(worker));
            raw->thread
                .submit([raw, this] { raw->renderer = std::make_unique<FrameRenderer>(limits_); })
                .get();
        }
        std::vector<std::future<Frame>> results;
        for (const auto& worker : workers_) {
            in_flight_.fetch_add(1);
            results.push_back(enqueue(*worker, test));
        }
        for (auto& result : results) {
            result.get();
        }
    } catch (const std::exception& error) {
        for (const auto& worker : workers_) {
            Worker* raw = worker.get();
            raw->thread.submit([raw] { raw->renderer.reset(); }).wait();
        }
        workers_.clear();
        const std::lock_guard lock(failure_mutex_);
        failure_ = error.what();
        throw;
    }
    {
        const std::lock_guard lock(failure_mutex_);
        failure_.clear();
    }
    started_.store(true, std::memory_order_release);
}

std::string RenderPool::failure() const {
    const std::lock_guard lock(failure_mutex_);
    return failure_;
}

std::future<Frame> RenderPool::submit(Job job) {
    if (!started()) {
        const std::string why = failure();
        throw RendererUnavailable(why.empty() ? "the renderer has not started yet"
                                              : "the renderer could not start: " + why);
    }
    if (!admit()) {
        throw QueueFull("the render queue is full (" + std::to_string(capacity_) +
                        " frames in flight)");
    }
    Worker& worker = **std::min_element(
        workers_.begin(), workers_.end(),
        [](const auto& a, const auto& b) { return a->pending.load() < b->pending.load(); });
    return enqueue(worker, std::move(job));
}

bool RenderPool::take_place() {
    std::size_t in_flight = in_flight_.load();
    while (in_flight < capacity_) {
        if (in_flight_.compare_exchange_weak(in_flight, in_flight + 1)) {
            return true;
        }
    }
    return false;
}

bool RenderPool::admit() {
    if (take_place()) {
        return true;
    }
    std::unique_lock lock(admission_mutex_);
    if (admission_.wait <= std::chrono::milliseconds::zero() ||
        admission_waiters_ >= admission_.max_waiters) {
        return false;
    }
    ++admission_waiters_;
    const bool admitted =
        place_freed_.wait_for(lock, admission_.wait, [this] { return take_place(); });
    --admission_waiters_;
    return admitted;
}

void RenderPool::free_place() {
    in_flight_.fetch_sub(1);
    // Through the mutex, so that a waiter between its check and its sleep cannot miss this.
    { const std::lock_guard lock(admission_mutex_); }
    place_freed_.notify_one();
}

std::future<Frame> RenderPool::enqueue(Worker& worker, Job job) {
    worker.pending.fetch_add(1);
    notify();
    return worker.thread.submit([this, &worker, job = std::move(job)] {
        running_.fetch_add(1);
        notify();
        // Counted down however the job ends, so that a failing job never leaks capacity.
        struct Done {
            RenderPool* pool;
            Worker* worker;
            ~Done() {
                pool->running_.fetch_sub(1);
                worker->pending.fetch_sub(1);
                pool->free_place();
                pool->notify();
            }
        } done{this, &worker};
        return job(*worker.renderer);
    });
}

void RenderPool::notify() {
    if (observer_) {
        observer_(waiting());
    }
}

std::size_t RenderPool::waiting() const {
    const std::size_t in_flight = in_flight_.load();
    const std::size_t running = running_.load();
    return in_flight > running ? in_flight - running : 0;
}

const GlInfo* RenderPool::info() const {
    return started() ? &workers_.front()->thread.info() : nullptr;
}

}  // namespace oer::server
