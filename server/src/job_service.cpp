#include "job_service.hpp"

#include <pthread.h>

#include <algorithm>
#include <set>

#include "http_errors.hpp"
#include "oer/api/frame_encoding.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/core/thread_priority.hpp"

namespace oer::server {

namespace {

using Clock = std::chrono::steady_clock;

// How long the runner waits after a frame refused for a moment (the renderer not started yet,
// its queue full) before it asks again.
constexpr std::chrono::milliseconds kRetryPause{500};

const api::JobFrame* frame_named(const api::JobSpec& spec, const std::string& name) {
    const auto found = std::find_if(spec.frames.begin(), spec.frames.end(),
                                    [&](const api::JobFrame& frame) { return frame.name == name; });
    return found == spec.frames.end() ? nullptr : &*found;
}

std::set<std::string> failed_names(JobStore& store, const std::string& id) {
    std::set<std::string> names;
    for (const auto& [name, detail] : store.failures(id)) {
        names.insert(name);
    }
    return names;
}

}  // namespace

bool is_settled_state(std::string_view state) {
    return state == "done" || state == "failed" || state == "cancelled";
}

void LocalFrameQueue::push(const std::string& job, const std::vector<std::string>& frames) {
    {
        const std::lock_guard lock(mutex_);
        for (const std::string& frame : frames) {
            tasks_.push_back({job, frame, ""});
        }
    }
    pushed_.notify_all();
}

std::optional<FrameQueue::Task> LocalFrameQueue::take(std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    if (!pushed_.wait_for(lock, wait, [this] { return !tasks_.empty(); })) {
        return std::nullopt;
    }
    Task task = std::move(tasks_.front());
    tasks_.pop_front();
    return task;
}

JobService::JobService(JobStore& store, FrameService& frames, std::unique_ptr<FrameQueue> queue,
                       const api::RenderLimits& render_limits, JobBounds bounds,
                       std::chrono::hours retention, ServiceMetrics& metrics,
                       std::function<void(std::string_view)> log)
    : store_(store),
      frames_(frames),
      queue_(std::move(queue)),
      render_limits_(render_limits),
      bounds_(bounds),
      retention_(retention),
      metrics_(metrics),
      log_(std::move(log)) {
    if (retention_.count() > 0) {
        remove_expired();
    }
    for (const std::string& id : store_.ids()) {
        const auto resumed = job(id);
        if (!resumed || store_.cancelled(id) || queue_->durable()) {
            continue;
        }
        const std::set<std::string> done = store_.frames_done(id);
        const std::set<std::string> failed = failed_names(store_, id);
        std::vector<std::string> pending;
        for (const api::JobFrame& frame : resumed->spec.frames) {
            if (!done.contains(frame.name) && !failed.contains(frame.name)) {
                pending.push_back(frame.name);
            }
        }
        if (!pending.empty()) {
            log_("jobs: job " + id + " resumed, " + std::to_string(pending.size()) + " of " +
                 std::to_string(resumed->spec.frames.size()) + " frames to render");
            queue_->push(id, pending);
        }
    }
    runner_ = std::thread([this] { run(); });
    if (retention_.count() > 0) {
        sweeper_ = std::thread([this] {
            pthread_setname_np(pthread_self(), "oer-job-sweep");
            std::unique_lock lock(mutex_);
            while (!change_.wait_for(lock, kRetentionSweep, [this] { return stopping_.load(); })) {
                lock.unlock();
                remove_expired();
                lock.lock();
            }
        });
    }
}

JobService::~JobService() {
    stopping_.store(true);
    {
        // Between the sweeper's look at stopping_ and its wait, never: it holds the mutex.
        const std::lock_guard lock(mutex_);
    }
    change_.notify_all();
    runner_.join();
    if (sweeper_.joinable()) {
        sweeper_.join();
    }
}

JobHold JobService::hold(const std::string& id) {
    {
        const std::lock_guard lock(holds_mutex_);
        ++holds_[id];
    }
    return JobHold(nullptr, [this, id](void*) {
        const std::lock_guard lock(holds_mutex_);
        if (--holds_[id] == 0) {
            holds_.erase(id);
        }
    });
}

void JobService::remove_expired() {
    const auto before = std::filesystem::file_time_type::clock::now() - retention_;
    bool removed = false;
    for (const std::string& id : store_.ids()) {
        try {
            // The files' age first: a recent job, the most common, needs no status read.
            const auto written = store_.last_write(id);
            if (!written || *written >= before) {
                continue;
            }
            const auto state = status(id, false);
            if (!state || !is_settled_state(state->at("state").get<std::string>())) {
                continue;
            }
            std::optional<std::filesystem::path> detached;
            {
                // No hold is taken meanwhile: a reader comes before (the job waits for the next
                // sweep) or after (it finds no job).
                const std::lock_guard lock(holds_mutex_);
                if (holds_.contains(id) || !(detached = store_.detach(id))) {
                    continue;  // being read: the next sweep; removed by another replica
                }
                const std::lock_guard jobs_lock(mutex_);
                jobs_.erase(id);
            }
            store_.discard(*detached);
            removed = true;
            log_("jobs: job " + id + " (" + state->at("state").get<std::string>() +
                 ") removed: unchanged for more than " + std::to_string(retention_.count()) +
                 " h (--job-retention-hours)");
        } catch (const std::exception& error) {
            log_("error: jobs: job " + id + " could not be removed: " + error.what());
        }
    }
    if (removed) {
        changed();  // the event streams of removed jobs end
    }
}

std::shared_ptr<const JobService::Job> JobService::job(const std::string& id) {
    {
        const std::lock_guard lock(mutex_);
        if (const auto known = jobs_.find(id); known != jobs_.end()) {
            return known->second;
        }
    }
    // Made by another replica, or before a restart: read from the store, held, so that a job
    // removed meanwhile is never remembered.
    const JobHold held = hold(id);
    std::optional<nlohmann::json> record;
    try {
        record = store_.record(id);
        if (!record) {
            return nullptr;
        }
        auto loaded = std::make_shared<Job>();
        loaded->spec = api::job_from_stored_json(record->at("job"), render_limits_);
        loaded->client = record->at("client").get<std::string>();
        loaded->created = record->at("created").get<double>();
        loaded->seen_since = Clock::now();
        loaded->done_when_seen = store_.frames_done(id).size();
        const std::lock_guard lock(mutex_);
        return jobs_.try_emplace(id, std::move(loaded)).first->second;
    } catch (const std::exception& error) {
        log_("jobs: the stored job " + id + " cannot be read: " + error.what());
        return nullptr;
    }
}

std::string JobService::submit(const api::JobSpec& spec, const std::string& client) {
    // One check per distinct scene: a turntable's views differ by their camera only, which
    // the check does not depend on.
    std::set<std::string> checked;
    for (std::size_t i = 0; i < spec.frames.size(); ++i) {
        api::RenderSpec without_camera = spec.frames[i].spec;
        without_camera.camera.reset();
        if (!checked.insert(api::normalised_render_json(without_camera).dump()).second) {
            continue;
        }
        const std::string at = "frames/" + std::to_string(i) + "/render";
        try {
            frames_.check(spec.frames[i].spec);
        } catch (const api::InvalidParameter& invalid) {
            throw invalid.nested_in(at);
        } catch (const HttpError& refused) {
            Problem problem = refused.problem();
            if (problem.extensions.contains("parameter")) {
                problem.extensions["parameter"] =
                    at + "/" + problem.extensions["parameter"].get<std::string>();
            }
            problem.detail = "frame " + spec.frames[i].name + ": " + problem.detail;
            throw HttpError(problem, refused.headers());
        }
    }
    std::size_t frames = 0;
    std::uint64_t pixels = 0;
    {
        std::vector<std::pair<std::string, std::shared_ptr<const Job>>> own;
        {
            const std::lock_guard lock(mutex_);
            for (const auto& [id, known] : jobs_) {
                if (known->client == client) {
                    own.emplace_back(id, known);
                }
            }
        }
        for (const auto& [id, known] : own) {
            const JobHold held = hold(id);
            if (!job(id) || store_.cancelled(id)) {
                continue;  // removed meanwhile (settled: it holds no bound), or cancelled
            }
            const std::set<std::string> done = store_.frames_done(id);
            for (const api::JobFrame& frame : known->spec.frames) {
                if (!done.contains(frame.name)) {
                    ++frames;
                    pixels += std::uint64_t(frame.spec.width) * std::uint64_t(frame.spec.height);
                }
            }
        }
    }
    if (frames + spec.frames.size() > bounds_.client_frames ||
        pixels + api::job_pixels(spec) > bounds_.client_pixels) {
        throw HttpError(
            problem(ProblemKind::TooManyRenders,
                    "this client's unfinished jobs hold " + std::to_string(frames) +
                        " frames and " + std::to_string(pixels) + " pixels still to render; with " +
                        std::to_string(spec.frames.size()) + " frames more it would pass the " +
                        std::to_string(bounds_.client_frames) + " frames or " +
                        std::to_string(bounds_.client_pixels) +
                        " pixels a client may have waiting"),
            {{"Retry-After", "60"}});
    }
    const double created =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    const std::string id = store_.create(
        {{"client", client}, {"created", created}, {"job", api::stored_job_json(spec)}});
    auto made = std::make_shared<Job>();
    made->spec = spec;
    made->client = client;
    made->created = created;
    made->seen_since = Clock::now();
    {
        const std::lock_guard lock(mutex_);
        jobs_.emplace(id, std::move(made));
    }
    std::vector<std::string> names;
    for (const api::JobFrame& frame : spec.frames) {
        names.push_back(frame.name);
    }
    try {
        queue_->push(id, names);
    } catch (const Error& error) {
        // Stored but never to be rendered: cancelled, so that it holds none of the client's
        // bounds, and refused for now.
        store_.cancel(id);
        log_(std::string("jobs: job ") + id + " refused: " + error.what());
        throw unavailable("the job queue cannot take the job now; try again", 5);
    }
    changed();
    return id;
}

std::optional<nlohmann::json> JobService::status(const std::string& id, bool with_frames) {
    const JobHold held = hold(id);
    const auto known = job(id);
    if (!known) {
        return std::nullopt;
    }
    const std::set<std::string> done = store_.frames_done(id);
    const auto failures = store_.failures(id);
    const std::size_t total = known->spec.frames.size();
    const bool cancelled = store_.cancelled(id);
    std::string state = "queued";
    if (cancelled) {
        state = "cancelled";
    } else if (done.size() + failures.size() >= total) {
        state = failures.empty() ? "done" : "failed";
    } else if (!done.empty() || !failures.empty()) {
        state = "running";
    }
    nlohmann::json answer = {{"id", id},
                             {"state", state},
                             {"total", total},
                             {"done", done.size()},
                             {"failed", failures.size()},
                             {"frames_per_second", nullptr},
                             {"seconds_left", nullptr}};
    // The rate this replica has seen since it first saw the job: every replica's frames count,
    // since they are all in the store.
    const double elapsed = std::chrono::duration<double>(Clock::now() - known->seen_since).count();
    if (done.size() > known->done_when_seen && elapsed > 0.0) {
        const double rate = double(done.size() - known->done_when_seen) / elapsed;
        answer["frames_per_second"] = rate;
        if (state == "queued" || state == "running") {
            answer["seconds_left"] = double(total - done.size() - failures.size()) / rate;
        }
    }
    nlohmann::json sequences = nlohmann::json::array();
    for (const api::JobSequence& sequence : known->spec.sequences) {
        sequences.push_back(sequence.name);
    }
    answer["sequences"] = sequences;
    if (with_frames) {
        std::map<std::string, std::string> why(failures.begin(), failures.end());
        nlohmann::json frames = nlohmann::json::array();
        for (const api::JobFrame& frame : known->spec.frames) {
            nlohmann::json entry = {{"name", frame.name}};
            if (done.contains(frame.name)) {
                entry["state"] = "done";
            } else if (const auto failed = why.find(frame.name); failed != why.end()) {
                entry["state"] = "failed";
                entry["error"] = failed->second;
            } else {
                entry["state"] = "pending";
            }
            frames.push_back(std::move(entry));
        }
        answer["frames"] = std::move(frames);
    }
    return answer;
}

bool JobService::cancel(const std::string& id) {
    const JobHold held = hold(id);
    if (!job(id)) {
        return false;
    }
    store_.cancel(id);
    changed();
    return true;
}

std::uint64_t JobService::wait_for_change(std::uint64_t seen, std::chrono::milliseconds wait) {
    std::unique_lock lock(mutex_);
    change_.wait_for(lock, wait, [&] { return changes_ != seen || stopping_.load(); });
    return changes_;
}

std::optional<JobPage> JobService::list(const std::string& client, const std::string& after,
                                        std::size_t limit) {
    struct Listed {
        double created;
        std::string id;
    };
    std::vector<Listed> own;
    for (const std::string& id : store_.ids()) {
        if (const auto known = job(id); known && known->client == client) {
            own.push_back({known->created, id});
        }
    }
    std::sort(own.begin(), own.end(), [](const Listed& a, const Listed& b) {
        return a.created != b.created ? a.created > b.created : a.id > b.id;
    });
    auto next = own.begin();
    if (!after.empty()) {
        next = std::find_if(own.begin(), own.end(),
                            [&](const Listed& listed) { return listed.id == after; });
        if (next == own.end()) {
            return std::nullopt;
        }
        ++next;
    }
    JobPage page;
    for (; next != own.end() && page.jobs.size() < limit; ++next) {
        auto status = this->status(next->id, false);
        if (!status) {
            continue;  // removed since it was listed
        }
        page.jobs.push_back({{"id", next->id},
                             {"state", status->at("state")},
                             {"done", status->at("done")},
                             {"failed", status->at("failed")},
                             {"total", status->at("total")},
                             {"created", next->created}});
    }
    if (next != own.end() && !page.jobs.empty()) {
        page.next_after = page.jobs.back().at("id").get<std::string>();
    }
    return page;
}

void JobService::changed() {
    {
        const std::lock_guard lock(mutex_);
        ++changes_;
    }
    change_.notify_all();
}

std::optional<api::JobSpec> JobService::spec(const std::string& id) {
    const auto known = job(id);
    return known ? std::optional<api::JobSpec>(known->spec) : std::nullopt;
}

std::optional<JobFrameBytes> JobService::frame(const std::string& id, const std::string& name,
                                               bool* known) {
    const JobHold held = hold(id);
    const auto found = job(id);
    const api::JobFrame* frame = found ? frame_named(found->spec, name) : nullptr;
    if (known) {
        *known = frame != nullptr;
    }
    if (!frame) {
        return std::nullopt;
    }
    auto bytes = store_.frame(id, name);
    if (!bytes) {
        return std::nullopt;
    }
    return JobFrameBytes{std::move(*bytes), api::content_type_of(frame->spec.format)};
}

void JobService::run() {
    pthread_setname_np(pthread_self(), "oer-jobs");
    // The runner encodes and writes each frame itself: at the batch worker's priority, below
    // the interactive workers, not at the HTTP threads' above them.
    try {
        lower_thread_priority(kBatchNice, "the batch jobs' runner");
    } catch (const Error& error) {
        log_(std::string("warning: jobs: ") + error.what());
    }
    std::string last_failure;
    while (!stopping_.load()) {
        std::optional<FrameQueue::Task> task;
        try {
            task = queue_->take(std::chrono::milliseconds(200));
            if (!last_failure.empty()) {
                log_("jobs: the queue answers again");
                last_failure.clear();
            }
        } catch (const std::exception& error) {
            // Each new cause once, not a line every pause.
            if (error.what() != last_failure) {
                last_failure = error.what();
                log_("error: jobs: the queue failed: " + last_failure + "; trying again");
            }
            std::this_thread::sleep_for(kRetryPause);
            continue;
        }
        if (task && !render(*task)) {
            return;
        }
    }
}

bool JobService::render(const FrameQueue::Task& task) {
    const auto found = job(task.job);
    const api::JobFrame* frame = found ? frame_named(found->spec, task.frame) : nullptr;
    if (!frame || store_.cancelled(task.job)) {
        queue_->acknowledge(task);
        return true;
    }
    if (store_.has_frame(task.job, task.frame)) {
        metrics_.job_frames_skipped.increment();
        queue_->acknowledge(task);
        return true;
    }
    const FrameService::Client client{
        found->client, [this, id = task.job] { return stopping_.load() || store_.cancelled(id); },
        Lane::Batch};
    while (!stopping_.load()) {
        try {
            const EncodedFrame encoded = frames_.render(frame->spec, api::render_etag(frame->spec),
                                                        RequestForm::Json, client);
            store_.put_frame(task.job, task.frame, *encoded.bytes);
            metrics_.job_frames_stored.increment();
            // One line a frame, as the access log has one a request: which replica rendered
            // what, after a replica was killed mid-job.
            log_("jobs: frame " + task.frame + " of job " + task.job + " stored");
            queue_->acknowledge(task);
            changed();
            return true;
        } catch (...) {
            if (stopping_.load()) {
                break;
            }
            if (store_.cancelled(task.job)) {
                queue_->acknowledge(task);
                changed();
                return true;
            }
            const ErrorAnswer answer = error_answer(std::current_exception());
            if (answer.problem.status() == 503) {
                // Refused for now (the renderer starting, its worker busy): asked again.
                std::this_thread::sleep_for(kRetryPause);
                continue;
            }
            log_("jobs: frame " + task.frame + " of job " + task.job +
                 " failed: " + answer.problem.detail);
            try {
                store_.put_failure(task.job, task.frame, answer.problem.detail);
            } catch (const std::exception& error) {
                log_(std::string("jobs: its failure could not be stored: ") + error.what());
            }
            queue_->acknowledge(task);
            changed();
            return true;
        }
    }
    return false;
}

}  // namespace oer::server
