#include "bake_lane.hpp"

#include <pthread.h>

#include <exception>
#include <future>

#include "oer/core/thread_priority.hpp"

namespace oer::server {

BakeLane::BakeLane(int nice, std::size_t max_queued) : max_queued_(max_queued) {
    std::promise<void> started;
    std::future<void> ready = started.get_future();
    thread_ = std::thread([this, nice, &started] { run(nice, started); });
    try {
        ready.get();
    } catch (...) {
        thread_.join();
        throw;
    }
}

BakeLane::~BakeLane() {
    {
        const std::lock_guard lock(mutex_);
        jobs_.clear();
        stopping_.request_stop();
    }
    wake_.notify_all();
    thread_.join();
}

bool BakeLane::submit(Job job) {
    {
        const std::lock_guard lock(mutex_);
        if (stopping_.stop_requested() || jobs_.size() >= max_queued_) {
            return false;
        }
        jobs_.push_back(std::move(job));
    }
    wake_.notify_one();
    return true;
}

void BakeLane::run(int nice, std::promise<void>& started) {
    pthread_setname_np(pthread_self(), "oer-bake");
    try {
        lower_thread_priority(nice, "the bake lane");
    } catch (...) {
        started.set_exception(std::current_exception());
        return;
    }
    started.set_value();
    for (;;) {
        Job job;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stopping_.stop_requested() || !jobs_.empty(); });
            if (stopping_.stop_requested()) {
                return;
            }
            job = std::move(jobs_.front());
            jobs_.pop_front();
        }
        job(stopping_.get_token());
    }
}

}  // namespace oer::server
