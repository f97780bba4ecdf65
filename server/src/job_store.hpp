#pragma once
// Batch jobs kept in the data folder, so that a job survives a restart and every replica
// sharing the folder sees it (job_service.hpp): DIR/jobs/<id>/job.json (the stored
// specification, api::stored_job_json, with the client and the time it was made),
// DIR/jobs/<id>/frames/<name> (each frame's encoded bytes, once rendered),
// DIR/jobs/<id>/failed/<name> (why a frame could not be rendered) and DIR/jobs/<id>/cancelled.
// Every file is written as the asset store writes its entries (write_file_atomically), so a
// frame is there whole or not at all: a frame's file is its record of being done.
//
// Paths are built only from ids checked by is_job_id and names checked by api::is_frame_name
// (no slash, no leading dot), so that nothing is read or written outside DIR/jobs.
#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace oer::server {

// 32 lowercase hexadecimal digits: 128 random bits, never guessed from another job's id.
bool is_job_id(std::string_view text);

class JobStore {
  public:
    // Creates DIR/jobs if missing (throws oer::Error (Io) when it cannot), and removes the
    // temporary files of frame writes a killed process left, as the asset store does its own:
    // those unmodified for kAbandonedTemporaryAge (younger ones may be another replica's writes
    // in progress), each logged; and the folders of removals a killed process left (detach).
    JobStore(const std::filesystem::path& data_dir, std::function<void(std::string_view)> log);

    // A new job's id, its record written whole before it returns.
    std::string create(const nlohmann::json& record);
    // Every stored job's id (the order of the folder).
    std::vector<std::string> ids() const;
    // nullopt when no job has that id (or it is not an id).
    std::optional<nlohmann::json> record(std::string_view id) const;

    void put_frame(std::string_view id, std::string_view name, std::string_view bytes);
    std::optional<std::string> frame(std::string_view id, std::string_view name) const;
    bool has_frame(std::string_view id, std::string_view name) const;
    // The names of the frames stored so far.
    std::set<std::string> frames_done(std::string_view id) const;

    void put_failure(std::string_view id, std::string_view name, std::string_view detail);
    // name -> why, for each frame that failed.
    std::vector<std::pair<std::string, std::string>> failures(std::string_view id) const;

    void cancel(std::string_view id);
    bool cancelled(std::string_view id) const;

    // When the job's files last changed: the newest write time of its record, frames, failures
    // and cancellation (of a settled job: when it settled, or was cancelled, or its frame in
    // flight at the cancellation was stored). nullopt when no job has that id.
    std::optional<std::filesystem::file_time_type> last_write(std::string_view id) const;
    // Takes the job out of the store: its folder renamed to a hidden name
    // (DIR/jobs/.removing-<id>-<random>), at once no longer a job for anyone reading the folder,
    // this process or another replica; the renamed folder, for discard(). nullopt when the job
    // was not there (removed meanwhile by another replica). Throws oer::Error (Io) when the
    // rename fails otherwise.
    std::optional<std::filesystem::path> detach(std::string_view id);
    // Removes a folder detach() renamed, with everything in it (what cannot be removed is
    // logged, and removed at the next start).
    void discard(const std::filesystem::path& detached);

  private:
    // DIR/jobs/<id>; throws oer::Error (InvalidInput) for a malformed id or frame name.
    std::filesystem::path job_folder(std::string_view id) const;
    std::filesystem::path entry(std::string_view id, std::string_view folder,
                                std::string_view name) const;

    const std::filesystem::path folder_;
    const std::function<void(std::string_view)> log_;
};

}  // namespace oer::server
