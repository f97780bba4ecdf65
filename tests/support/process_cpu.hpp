#pragma once
// CPU time of this test process: the servers the integration tests start run in it, so while the
// test's own thread sleeps, what the process uses is the server's work.
#include <sys/resource.h>

#include <chrono>
#include <thread>

namespace oer::testing {

// User and system CPU seconds of every thread of this process so far.
inline double process_cpu_seconds() {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    const auto seconds = [](const timeval& time) {
        return double(time.tv_sec) + time.tv_usec * 1e-6;
    };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// The share of one core the process used over the next `window`, which the caller sleeps
// through (1.0: one core busy throughout).
inline double cpu_share_over(std::chrono::milliseconds window) {
    const double before = process_cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(window);
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return (process_cpu_seconds() - before) / elapsed;
}

}  // namespace oer::testing
