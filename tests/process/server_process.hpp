#pragma once
// The real `oer-server` binary as a process of its own, for the tests that kill it, fill its
// disk or hide its GL driver (tests/process): spawned with posix_spawn on loopback ports it
// picks itself (--port 0, --admin-port 0, read back from its banner), on a data folder the test
// gives, its stdout and stderr kept in files; ready once its banner is printed and /healthz
// answers; stopped with SIGTERM (and its exit status checked) or killed with SIGKILL.
#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <httplib.h>

namespace oer::ptest {

struct ServerLaunch {
    ServerLaunch(std::filesystem::path data, std::filesystem::path logs)
        : data_dir(std::move(data)), log_dir(std::move(logs)) {}

    std::filesystem::path data_dir;
    // Where its stdout and stderr go (server-N.out, server-N.err): outside the data folder, whose
    // file system a test may fill.
    std::filesystem::path log_dir;
    // Flags (without "--") over the defaults: --host 127.0.0.1, --port 0, --admin-port 0, the
    // data folder, --transfer-ray-budget 100000 (the integration tests' smallest bake: 64 rays a
    // point) and --access-log on. A value "off" for admin-port runs it without the admin listener.
    std::map<std::string, std::string> options;
    // NAME=VALUE set in the server's environment (beside this process's own).
    std::vector<std::string> environment;
    // A command the server runs under, oer-server's command line appended to it (unshare, say).
    std::vector<std::string> wrapper;
    // Longest the banner and /healthz may take.
    std::chrono::seconds ready_within{60};
};

class ServerProcess {
  public:
    // Spawns the server and waits until it is ready (fatal failures inside: the test checks
    // HasFatalFailure or running()).
    explicit ServerProcess(ServerLaunch launch);
    // Kills it if it still runs; prints the end of its log when the test failed.
    ~ServerProcess();
    ServerProcess(const ServerProcess&) = delete;
    ServerProcess& operator=(const ServerProcess&) = delete;

    pid_t pid() const { return pid_; }
    bool running() const { return pid_ > 0; }
    int port() const { return port_; }
    int admin_port() const { return admin_port_; }  // -1 without the admin listener
    const ServerLaunch& launch() const { return launch_; }

    // Clients with generous timeouts (no test may hang for ever).
    std::unique_ptr<httplib::Client> client(int read_timeout_seconds = 120) const;
    std::unique_ptr<httplib::Client> admin_client() const;

    // SIGTERM, then waits (up to 30 s, then SIGKILL and a test failure); the exit status, or
    // 128 + the signal that ended it.
    int stop();
    // kill -9, reaped at once.
    void kill();

    std::string log() const;     // its stderr so far
    std::string banner() const;  // its stdout so far

  private:
    void spawn();
    void wait_until_ready();
    int reap(std::chrono::milliseconds within);  // the status, or -1 when still running

    ServerLaunch launch_;
    pid_t pid_ = -1;
    int port_ = -1;
    int admin_port_ = -1;
    std::filesystem::path out_, err_;
};

// Spawns arguments (the first looked up in PATH) with its standard input /dev/null, its output
// and errors into the files out and err, no signal blocked or ignored, and this process's
// environment with `environment` (NAME=VALUE) set over it: its pid, or -1 after a test failure.
pid_t spawn_process(std::vector<std::string> arguments, const std::vector<std::string>& environment,
                    const std::filesystem::path& out, const std::filesystem::path& err);
// Waits up to `within` for the child pid to end: its exit status, or 128 + the signal that
// ended it, or -1 while it still runs.
int reap_process(pid_t pid, std::chrono::milliseconds within);

// inotify on one folder: waits for an event of `mask` on a name starting with prefix (the
// moments of a store's writes: a temporary file created, closed, renamed into place).
class FolderWatch {
  public:
    FolderWatch(const std::filesystem::path& folder, std::uint32_t mask);
    ~FolderWatch();
    FolderWatch(const FolderWatch&) = delete;
    FolderWatch& operator=(const FolderWatch&) = delete;

    // The name of the first event on a name starting with prefix; nullopt after the deadline.
    std::optional<std::string> wait(const std::string& prefix, std::chrono::milliseconds within);

  private:
    int fd_;
};

// A value of /metrics (its sum over the series whose labels include `labels`), from the admin
// listener.
double admin_metric(const ServerProcess& server, const std::string& name,
                    const std::map<std::string, std::string>& labels = {});

// Polls the server's oer_computations_in_progress{computation=...} ("rig", "specular",
// "transfer") until it is up: false when it is not within 60 s.
bool computation_started(const ServerProcess& server, const std::string& computation);

// Files under folder whose name starts with the asset store's temporary prefix ".tmp-".
std::vector<std::filesystem::path> temporary_files(const std::filesystem::path& folder);

// Sets each file's modification time so long before now (a file removed meanwhile is skipped).
void set_untouched_for(const std::vector<std::filesystem::path>& files, std::chrono::minutes age);

// A TCP port on 127.0.0.1 that nothing listens on now (a test failure when none is found).
int free_loopback_port();

// A file's whole content ("" when it cannot be read).
std::string read_text(const std::filesystem::path& path);

// Bytes as the text they hold.
inline std::string_view as_text(const std::vector<std::byte>& bytes) {
    return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

// A map whose preprocessing takes long enough to be killed at several moments (0.85 s measured
// at 2048x1024 on 2 cores at a load of 10), within the upload budget: its discs compress its EXR
// to some 50 KB, far more than the 200 times a real map expands, so it must stay under the
// budget's 64 MiB floor (2048x1024 would take 72 MiB to decode and preprocess; 1792x896 takes
// 55 MiB).
constexpr int kLargeMapWidth = 1792;

// The side of the noise texture of a box written to the store: a 15 MB file (noise does not
// compress), whose write and flush last long enough to be interrupted, while the mesh is a box,
// quick to load and draw.
constexpr int kTextureSide = 2048;

}  // namespace oer::ptest
