#pragma once
// Batch jobs (POST /v1/jobs, docs/jobs.md): a job's specification and each of its frames are
// kept in the data folder (job_store.hpp), its frames wait in a FrameQueue, and one runner
// thread takes them one at a time and renders them through FrameService on the batch lane:
// a worker of its own at the lowest priority (render_pool.hpp's kBatchNice), so that an
// interactive frame never waits in a queue behind a batch frame and takes the cores from it.
//
// The stored frames are the truth of a job's progress: a frame is done when its file is
// there. So a job resumes after a restart without rendering a finished frame again (the frames
// without a file are queued again, unless the queue is durable and holds them still), and
// replicas sharing the data folder and a durable queue (redis_frame_queue.hpp) render each
// frame once, or twice at most when a replica is killed between its render and its
// acknowledgement: a task whose frame is stored already is acknowledged without rendering.
//
// Bounds: a job's frames and pixels (api::JobLimits, 413 at parsing), and per client, the
// frames and pixels its unfinished jobs still have to render on this replica (429).
//
// Retention: a settled job (done, failed, cancelled) whose files have not changed for the
// retention is removed from the store, at start and every kRetentionSweep after. A job being
// read here (a ZIP streamed, a sequence encoded, a status read: hold()) is left to the next
// sweep; a removal renames the job's folder before removing it (JobStore::remove), so a reader
// that comes after finds no job (404), never a job without its files.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "frame_service.hpp"
#include "job_store.hpp"
#include "oer/api/job_spec.hpp"
#include "service_metrics.hpp"

namespace oer::server {

// Where a job's frames wait for a renderer: in this process (LocalFrameQueue), or in a queue
// every replica takes work from and acknowledges (RedisFrameQueue).
class FrameQueue {
  public:
    struct Task {
        std::string job;
        std::string frame;
        std::string receipt;  // what acknowledge needs (a stream entry's id)
    };
    virtual ~FrameQueue() = default;
    virtual void push(const std::string& job, const std::vector<std::string>& frames) = 0;
    // The next frame to render, waiting at most `wait`; nullopt when none came.
    virtual std::optional<Task> take(std::chrono::milliseconds wait) = 0;
    // The task's frame is stored, or never will be (failed, cancelled): it leaves the queue.
    virtual void acknowledge(const Task& task) = 0;
    // Whether the queue keeps its tasks across this process's restarts (then a resumed job's
    // frames are not queued again).
    virtual bool durable() const = 0;
};

class LocalFrameQueue : public FrameQueue {
  public:
    void push(const std::string& job, const std::vector<std::string>& frames) override;
    std::optional<Task> take(std::chrono::milliseconds wait) override;
    void acknowledge(const Task&) override {}
    bool durable() const override { return false; }

  private:
    std::mutex mutex_;
    std::condition_variable pushed_;
    std::deque<Task> tasks_;
};

struct JobBounds {
    api::JobLimits job;
    std::size_t client_frames = 2000;  // frames a client's unfinished jobs may still hold
    std::uint64_t client_pixels = 512ull << 20;
};

// Whether a job in this state has no frame left to render: done, failed or cancelled.
bool is_settled_state(std::string_view state);

// How often settled jobs are looked at for removal: a job outlives its retention by at most
// this (the retention is set in hours).
inline constexpr std::chrono::minutes kRetentionSweep{10};

// One page of a client's jobs (GET /v1/jobs), newest first: each job's id, state, done,
// failed, total and created (seconds since the epoch); next_after, when set, is the cursor of
// the next page (the id of the page's last job).
struct JobPage {
    std::vector<nlohmann::json> jobs;
    std::optional<std::string> next_after;
};

// While held, retention does not remove the job (JobService::hold).
using JobHold = std::shared_ptr<void>;

// A stored frame's bytes and media type.
struct JobFrameBytes {
    std::string bytes;
    std::string content_type;
};

class JobService {
  public:
    // Removes the settled jobs past the retention (0: none, ever), resumes the stored jobs not
    // finished nor cancelled, and starts the runner and the retention's sweeps.
    JobService(JobStore& store, FrameService& frames, std::unique_ptr<FrameQueue> queue,
               const api::RenderLimits& render_limits, JobBounds bounds,
               std::chrono::hours retention, ServiceMetrics& metrics,
               std::function<void(std::string_view)> log);
    // Stops the runner, leaving an unfinished frame to the next start (or another replica),
    // and the sweeps.
    ~JobService();
    JobService(const JobService&) = delete;
    JobService& operator=(const JobService&) = delete;

    const JobBounds& bounds() const { return bounds_; }
    // Checks each frame as a render would (FrameService::check; its parameter named from the
    // job's root), and the client's bounds (429), then stores and queues the job; its id.
    std::string submit(const api::JobSpec& spec, const std::string& client);
    // The job's progress (GET /v1/jobs/{id}); nullopt for an unknown id. With frames, each
    // frame's state too.
    std::optional<nlohmann::json> status(const std::string& id, bool with_frames);
    // false for an unknown id.
    bool cancel(const std::string& id);
    // The jobs `client` submitted (on any replica sharing the store), newest first (by their
    // creation, then by id), `limit` (1 or more) after the job `after` ("": from the newest);
    // nullopt when `after` is no job of the client's (removed meanwhile, or another's).
    std::optional<JobPage> list(const std::string& client, const std::string& after,
                                std::size_t limit);
    // Keeps the job from removal while the hold lives; taken before its files are read, so
    // that a reader finds the job whole or not at all.
    JobHold hold(const std::string& id);
    // Waits up to `wait` for any job's progress here to change after `seen` (a count of
    // changes); the count now.
    std::uint64_t wait_for_change(std::uint64_t seen, std::chrono::milliseconds wait);

    // A rendered frame; nullopt when the job has no frame of that name or it is not rendered
    // yet (`known`, when given, is set to whether the job has a frame of that name).
    std::optional<JobFrameBytes> frame(const std::string& id, const std::string& name,
                                       bool* known = nullptr);
    // The job's specification (nullopt: no such job).
    std::optional<api::JobSpec> spec(const std::string& id);
    JobStore& store() { return store_; }

  private:
    struct Job {
        api::JobSpec spec;
        std::string client;
        double created = 0.0;                              // seconds since the epoch, as stored
        std::chrono::steady_clock::time_point seen_since;  // when this process first saw it
        std::size_t done_when_seen = 0;
    };
    std::shared_ptr<const Job> job(const std::string& id);
    void run();
    // Removes the settled jobs whose files are older than the retention, except those held.
    void remove_expired();
    // Renders and stores one task's frame, or skips it; false when the runner stops first.
    bool render(const FrameQueue::Task& task);
    void changed();

    JobStore& store_;
    FrameService& frames_;
    const std::unique_ptr<FrameQueue> queue_;
    const api::RenderLimits render_limits_;
    const JobBounds bounds_;
    const std::chrono::hours retention_;
    ServiceMetrics& metrics_;
    const std::function<void(std::string_view)> log_;

    std::mutex mutex_;
    std::condition_variable change_;
    std::uint64_t changes_ = 0;                               // guarded by mutex_
    std::map<std::string, std::shared_ptr<const Job>> jobs_;  // guarded by mutex_
    std::atomic<bool> stopping_{false};
    std::mutex holds_mutex_;
    std::map<std::string, std::size_t> holds_;  // job id -> holds; guarded by holds_mutex_
    std::thread runner_;
    std::thread sweeper_;  // the retention's; none without a retention
};

}  // namespace oer::server
