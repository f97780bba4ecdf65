#include "job_store.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "oer/api/job_spec.hpp"
#include "oer/core/error.hpp"
#include "oer/server/asset_store.hpp"

namespace oer::server {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kHiddenPrefix = ".";  // write_file_atomically's ".tmp-..."
constexpr std::string_view kWriteTemporaryPrefix = ".tmp-";
constexpr std::string_view kRemovalPrefix = ".removing-";  // JobStore::remove's

std::optional<std::string> read_whole(const fs::path& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        return std::nullopt;
    }
    std::ostringstream bytes;
    bytes << file.rdbuf();
    if (file.bad()) {
        throw Error(ErrorKind::Io, "cannot read " + path.string());
    }
    return bytes.str();
}

// The names of a folder's entries, leaving out temporary files of writes in progress.
std::vector<std::string> names_in(const fs::path& folder) {
    std::vector<std::string> names;
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(folder, error)) {
        std::string name = entry.path().filename().string();
        if (!name.starts_with(kHiddenPrefix)) {
            names.push_back(std::move(name));
        }
    }
    return names;
}

}  // namespace

bool is_job_id(std::string_view text) {
    return text.size() == 32 && text.find_first_not_of("0123456789abcdef") == std::string::npos;
}

JobStore::JobStore(const fs::path& data_dir, std::function<void(std::string_view)> log)
    : folder_(data_dir / "jobs"), log_(std::move(log)) {
    std::error_code error;
    fs::create_directories(folder_, error);
    if (error) {
        throw Error(ErrorKind::Io, "cannot create " + folder_.string() + ": " + error.message());
    }
    // A removal a killed process left half done: its job was gone once renamed. Another
    // replica's removal in progress may be removed by both; each skips what the other took.
    for (const auto& entry : fs::directory_iterator(folder_, error)) {
        if (entry.path().filename().string().starts_with(kRemovalPrefix)) {
            std::error_code unremovable;
            fs::remove_all(entry.path(), unremovable);
            log_("jobs: removed " + entry.path().string() + ", left by an interrupted removal" +
                 (unremovable ? " (in part: " + unremovable.message() + ")" : ""));
        }
    }
    const auto abandoned_before = fs::file_time_type::clock::now() - kAbandonedTemporaryAge;
    for (const std::string& id : names_in(folder_)) {
        for (const char* sub : {"frames", "failed"}) {
            for (const auto& entry : fs::directory_iterator(folder_ / id / sub, error)) {
                std::error_code unreadable;
                if (entry.path().filename().string().starts_with(kWriteTemporaryPrefix) &&
                    entry.last_write_time(unreadable) < abandoned_before && !unreadable &&
                    fs::remove(entry.path(), unreadable)) {
                    log_("jobs: removed " + entry.path().string() +
                         ", left by an interrupted write");
                }
            }
        }
    }
}

fs::path JobStore::job_folder(std::string_view id) const {
    if (!is_job_id(id)) {
        throw Error(ErrorKind::InvalidInput, "a job id is 32 lowercase hexadecimal digits");
    }
    return folder_ / std::string(id);
}

fs::path JobStore::entry(std::string_view id, std::string_view folder,
                         std::string_view name) const {
    if (!api::is_frame_name(name)) {
        throw Error(ErrorKind::InvalidInput, "not a frame name");
    }
    return job_folder(id) / std::string(folder) / std::string(name);
}

std::string JobStore::create(const nlohmann::json& record) {
    std::random_device random;
    std::string id;
    for (int i = 0; i < 4; ++i) {
        char part[9];
        std::snprintf(part, sizeof part, "%08x", unsigned(random()));
        id += part;
    }
    const fs::path folder = job_folder(id);
    for (const char* sub : {"frames", "failed"}) {
        std::error_code error;
        fs::create_directories(folder / sub, error);
        if (error) {
            throw Error(ErrorKind::Io,
                        "cannot create " + (folder / sub).string() + ": " + error.message());
        }
    }
    // Last: a job is listed once its record is whole (ids() skips a folder without it).
    write_file_atomically(folder / "job.json", record.dump(), "the job " + id);
    return id;
}

std::vector<std::string> JobStore::ids() const {
    std::vector<std::string> ids;
    for (std::string& name : names_in(folder_)) {
        if (is_job_id(name) && fs::exists(folder_ / name / "job.json")) {
            ids.push_back(std::move(name));
        }
    }
    return ids;
}

std::optional<nlohmann::json> JobStore::record(std::string_view id) const {
    if (!is_job_id(id)) {
        return std::nullopt;
    }
    const auto text = read_whole(job_folder(id) / "job.json");
    if (!text) {
        return std::nullopt;
    }
    return nlohmann::json::parse(*text);
}

void JobStore::put_frame(std::string_view id, std::string_view name, std::string_view bytes) {
    write_file_atomically(entry(id, "frames", name), bytes,
                          "the frame " + std::string(name) + " of job " + std::string(id));
}

std::optional<std::string> JobStore::frame(std::string_view id, std::string_view name) const {
    return read_whole(entry(id, "frames", name));
}

bool JobStore::has_frame(std::string_view id, std::string_view name) const {
    return fs::exists(entry(id, "frames", name));
}

std::set<std::string> JobStore::frames_done(std::string_view id) const {
    const std::vector<std::string> names = names_in(job_folder(id) / "frames");
    return {names.begin(), names.end()};
}

void JobStore::put_failure(std::string_view id, std::string_view name, std::string_view detail) {
    write_file_atomically(entry(id, "failed", name), detail,
                          "the failure of frame " + std::string(name));
}

std::vector<std::pair<std::string, std::string>> JobStore::failures(std::string_view id) const {
    std::vector<std::pair<std::string, std::string>> failures;
    for (const std::string& name : names_in(job_folder(id) / "failed")) {
        if (const auto detail = read_whole(entry(id, "failed", name))) {
            failures.emplace_back(name, *detail);
        }
    }
    return failures;
}

void JobStore::cancel(std::string_view id) {
    write_file_atomically(job_folder(id) / "cancelled", "", "the cancellation of a job");
}

bool JobStore::cancelled(std::string_view id) const {
    return fs::exists(job_folder(id) / "cancelled");
}

std::optional<fs::file_time_type> JobStore::last_write(std::string_view id) const {
    const fs::path folder = job_folder(id);
    std::error_code error;
    auto newest = fs::last_write_time(folder / "job.json", error);
    if (error) {
        return std::nullopt;
    }
    const auto take = [&](const fs::path& path) {
        std::error_code unreadable;  // gone meanwhile (a temporary file renamed)
        const auto written = fs::last_write_time(path, unreadable);
        if (!unreadable) {
            newest = std::max(newest, written);
        }
    };
    take(folder / "cancelled");
    for (const char* sub : {"frames", "failed"}) {
        for (const auto& entry : fs::directory_iterator(folder / sub, error)) {
            take(entry.path());
        }
    }
    return newest;
}

std::optional<fs::path> JobStore::detach(std::string_view id) {
    const fs::path folder = job_folder(id);
    char suffix[9];
    std::snprintf(suffix, sizeof suffix, "%08x", unsigned(std::random_device{}()));
    fs::path detached = folder_ / (std::string(kRemovalPrefix) + std::string(id) + "-" + suffix);
    std::error_code error;
    fs::rename(folder, detached, error);
    if (error == std::errc::no_such_file_or_directory) {
        return std::nullopt;
    }
    if (error) {
        throw Error(ErrorKind::Io,
                    "cannot remove " + folder.string() + " (renaming it): " + error.message());
    }
    return detached;
}

void JobStore::discard(const fs::path& detached) {
    std::error_code error;
    fs::remove_all(detached, error);
    if (error) {
        log_("jobs: " + detached.string() + " was not removed whole (" + error.message() +
             "); the next start removes the rest");
    }
}

}  // namespace oer::server
