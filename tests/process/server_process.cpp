#include "server_process.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/inotify.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <regex>
#include <thread>

#include "http_support.hpp"

extern char** environ;

namespace oer::ptest {

namespace fs = std::filesystem;

namespace {

// This process's environment with `extra` (NAME=VALUE) set over it.
std::vector<std::string> environment_with(const std::vector<std::string>& extra) {
    std::map<std::string, std::string> variables;
    for (char** entry = environ; *entry; ++entry) {
        const std::string text = *entry;
        variables[text.substr(0, text.find('='))] = text;
    }
    for (const std::string& text : extra) {
        variables[text.substr(0, text.find('='))] = text;
    }
    std::vector<std::string> result;
    for (const auto& [name, text] : variables) {
        result.push_back(text);
    }
    return result;
}

std::vector<char*> c_strings(std::vector<std::string>& strings) {
    std::vector<char*> pointers;
    for (std::string& text : strings) {
        pointers.push_back(text.data());
    }
    pointers.push_back(nullptr);
    return pointers;
}

// Numbers the servers' log files; servers may be started from several threads at once.
std::atomic<int> spawn_count = 0;

}  // namespace

ServerProcess::ServerProcess(ServerLaunch launch) : launch_(std::move(launch)) {
    spawn();
    if (running()) {
        wait_until_ready();
    }
}

void ServerProcess::spawn() {
    std::map<std::string, std::string> options = {{"host", "127.0.0.1"},
                                                  {"port", "0"},
                                                  {"admin-port", "0"},
                                                  {"data-dir", launch_.data_dir.string()},
                                                  {"transfer-ray-budget", "100000"},
                                                  {"access-log", "on"}};
    for (const auto& [name, value] : launch_.options) {
        options[name] = value;
    }
    std::vector<std::string> arguments = launch_.wrapper;
    arguments.push_back(OER_SERVER_PATH);
    for (const auto& [name, value] : options) {
        arguments.push_back("--" + name);
        arguments.push_back(value);
    }
    const int number = ++spawn_count;
    out_ = launch_.log_dir / ("server-" + std::to_string(number) + ".out");
    err_ = launch_.log_dir / ("server-" + std::to_string(number) + ".err");
    pid_ = spawn_process(arguments, launch_.environment, out_, err_);
}

pid_t spawn_process(std::vector<std::string> arguments, const std::vector<std::string>& environment,
                    const fs::path& out, const fs::path& err) {
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, out.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&files, STDERR_FILENO, err.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    // The child must not inherit a mask or a disposition of ours (the server blocks SIGINT and
    // SIGTERM itself to sigwait for them).
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGPIPE);
    sigaddset(&defaults, SIGTERM);
    sigaddset(&defaults, SIGINT);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    std::vector<std::string> variables = environment_with(environment);
    std::vector<char*> argv = c_strings(arguments);
    std::vector<char*> envp = c_strings(variables);
    pid_t pid = -1;
    const int spawned =
        ::posix_spawnp(&pid, argv[0], &files, &attributes, argv.data(), envp.data());
    posix_spawnattr_destroy(&attributes);
    posix_spawn_file_actions_destroy(&files);
    if (spawned != 0) {
        ADD_FAILURE() << "cannot spawn " << argv[0] << ": " << std::strerror(spawned);
        return -1;
    }
    return pid;
}

ServerProcess::~ServerProcess() {
    if (running()) {
        kill();
    }
    if (::testing::Test::HasFailure()) {
        const std::string text = log();
        std::size_t start = text.size();
        for (int lines = 0; lines < 40 && start > 0; ++lines) {
            start = text.rfind('\n', start - 1);
            if (start == std::string::npos) {
                start = 0;
                break;
            }
        }
        std::cerr << "oer-server (" << err_.filename().string() << ", last lines):\n"
                  << text.substr(start) << "\n";
    }
}

void ServerProcess::wait_until_ready() {
    const auto deadline = std::chrono::steady_clock::now() + launch_.ready_within;
    const bool admin =
        launch_.options.count("admin-port") == 0 || launch_.options.at("admin-port") != "off";
    // The banner is written with one flush, its last line the page to open.
    while (banner().find("open the dressing room:") == std::string::npos) {
        if (const int status = reap(std::chrono::milliseconds(0)); status >= 0) {
            FAIL() << "oer-server ended with status " << status << " before it was ready:\n"
                   << log();
        }
        if (std::chrono::steady_clock::now() > deadline) {
            kill();
            FAIL() << "oer-server printed no banner within " << launch_.ready_within.count()
                   << " s:\n"
                   << log();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const std::string text = banner();
    std::smatch match;
    ASSERT_TRUE(std::regex_search(text, match, std::regex(R"(listening on http://[^:]+:(\d+))")))
        << text;
    port_ = std::stoi(match[1]);
    if (admin) {
        ASSERT_TRUE(std::regex_search(text, match, std::regex(R"(admin listener .*:(\d+)\n)")))
            << text;
        admin_port_ = std::stoi(match[1]);
    }
    const auto health = client(10)->Get("/healthz");
    ASSERT_TRUE(health && health->status == 200) << "/healthz after the banner failed";
}

std::unique_ptr<httplib::Client> ServerProcess::client(int read_timeout_seconds) const {
    auto result = std::make_unique<httplib::Client>("127.0.0.1", port_);
    result->set_connection_timeout(5, 0);
    result->set_read_timeout(read_timeout_seconds, 0);
    result->set_write_timeout(30, 0);
    return result;
}

std::unique_ptr<httplib::Client> ServerProcess::admin_client() const {
    auto result = std::make_unique<httplib::Client>("127.0.0.1", admin_port_);
    result->set_connection_timeout(5, 0);
    result->set_read_timeout(10, 0);
    return result;
}

int ServerProcess::reap(std::chrono::milliseconds within) {
    const int status = reap_process(pid_, within);
    if (status >= 0) {
        pid_ = -1;
    }
    return status;
}

int reap_process(pid_t pid, std::chrono::milliseconds within) {
    const auto deadline = std::chrono::steady_clock::now() + within;
    while (true) {
        int raw = 0;
        const pid_t done = ::waitpid(pid, &raw, WNOHANG);
        if (done == pid) {
            return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
        }
        if (done < 0) {
            ADD_FAILURE() << "waitpid(" << pid << "): " << std::strerror(errno);
            return 255;
        }
        if (std::chrono::steady_clock::now() >= deadline) {
            return -1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

int ServerProcess::stop() {
    if (!running()) {
        ADD_FAILURE() << "stop(): the server is not running";
        return -1;
    }
    ::kill(pid_, SIGTERM);
    const int status = reap(std::chrono::seconds(30));
    if (status < 0) {
        ADD_FAILURE() << "oer-server did not stop within 30 s of SIGTERM";
        kill();
        return -1;
    }
    return status;
}

void ServerProcess::kill() {
    if (!running()) {
        return;
    }
    ::kill(pid_, SIGKILL);
    int raw = 0;
    ::waitpid(pid_, &raw, 0);
    pid_ = -1;
}

std::string ServerProcess::log() const {
    return read_text(err_);
}

std::string ServerProcess::banner() const {
    return read_text(out_);
}

double admin_metric(const ServerProcess& server, const std::string& name,
                    const std::map<std::string, std::string>& labels) {
    return itest::scrape(*server.admin_client()).sum(name, labels);
}

bool computation_started(const ServerProcess& server, const std::string& computation) {
    return itest::eventually(
        [&] {
            return admin_metric(server, "oer_computations_in_progress",
                                {{"computation", computation}}) >= 1.0;
        },
        std::chrono::seconds(60));
}

std::vector<fs::path> temporary_files(const fs::path& folder) {
    std::vector<fs::path> found;
    std::error_code error;
    for (auto entry = fs::recursive_directory_iterator(folder, error);
         entry != fs::recursive_directory_iterator(); entry.increment(error)) {
        if (entry->path().filename().string().starts_with(".tmp-")) {
            found.push_back(entry->path());
        }
    }
    return found;
}

void set_untouched_for(const std::vector<fs::path>& files, std::chrono::minutes age) {
    for (const fs::path& file : files) {
        std::error_code error;
        fs::last_write_time(file, fs::file_time_type::clock::now() - age, error);
        EXPECT_TRUE(!error || error == std::errc::no_such_file_or_directory)
            << file << ": " << error.message();
    }
}

FolderWatch::FolderWatch(const fs::path& folder, std::uint32_t mask)
    : fd_(::inotify_init1(IN_CLOEXEC | IN_NONBLOCK)) {
    EXPECT_GE(fd_, 0) << std::strerror(errno);
    EXPECT_GE(::inotify_add_watch(fd_, folder.c_str(), mask), 0) << std::strerror(errno);
}

FolderWatch::~FolderWatch() {
    ::close(fd_);
}

std::optional<std::string> FolderWatch::wait(const std::string& prefix,
                                             std::chrono::milliseconds within) {
    const auto deadline = std::chrono::steady_clock::now() + within;
    alignas(inotify_event) char buffer[4096];
    while (std::chrono::steady_clock::now() < deadline) {
        pollfd poll_fd{fd_, POLLIN, 0};
        if (::poll(&poll_fd, 1, 10) <= 0) {
            continue;
        }
        const ssize_t length = ::read(fd_, buffer, sizeof buffer);
        for (ssize_t at = 0; at < length;) {
            const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
            const std::string name = event->len ? event->name : "";
            if (name.starts_with(prefix)) {
                return name;
            }
            at += ssize_t(sizeof(inotify_event) + event->len);
        }
    }
    return std::nullopt;
}

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A TCP port on 127.0.0.1 that nothing listens on now.
int free_loopback_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    const bool bound =
        fd >= 0 && ::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0 &&
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0;
    ::close(fd);
    EXPECT_TRUE(bound) << "no free loopback port: " << std::strerror(errno);
    return ntohs(address.sin_port);
}

}  // namespace oer::ptest
