#pragma once
// Bakes that nobody waits for: a mesh's first frames' transfer, baked from its upload on, and
// the transfer of a scene whose frame was answered preliminary (FrameService::bake_ahead). One
// thread (and the bake's own threads, which inherit it) at the lowest priority, nice 19, beside
// the render workers rather than on them, so that frames (a preliminary one first of all) are
// drawn while it bakes and take the cores from it: at the workers' nice 10 a new product's
// preliminary frame shared the 2 cores with its bake and took 2.6-4.7 s (its shadow pass 1.7-3
// s) instead of about 1 s; a bounded queue, beyond which a bake is not queued (the frame that needs
// it bakes it then, on its worker). A frame that needs a transfer the lane is baking waits for that
// bake (TransferRegistry shares it) rather than start another.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <stop_token>
#include <thread>

namespace oer::server {

inline constexpr int kBakeLaneNice = 19;

class BakeLane {
  public:
    using Job = std::function<void(const std::stop_token& stop)>;

    // Starts the thread, its nice value raised by nice; throws oer::Error (Internal) when the
    // system refuses that.
    BakeLane(int nice, std::size_t max_queued);
    // Drops the jobs not started, asks the running one to stop (its token), and joins.
    ~BakeLane();
    BakeLane(const BakeLane&) = delete;
    BakeLane& operator=(const BakeLane&) = delete;

    // Queues job; false (queuing nothing) when max_queued jobs wait already.
    bool submit(Job job);

  private:
    void run(int nice, std::promise<void>& started);

    const std::size_t max_queued_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<Job> jobs_;       // guarded by mutex_
    std::stop_source stopping_;  // the destructor's request, seen by the running job
    std::thread thread_;
};

}  // namespace oer::server
