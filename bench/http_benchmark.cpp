// The service over HTTP on loopback: a Service started in-process (default configuration, a
// temporary data folder) and a load generator of N client threads with keep-alive
// connections, each scenario bounded in time. Requests per second and p50 / p99 latency for
//   (a) cached 512x512 JPEG frames: the same request again, answered from the frame cache;
//   (b) ETag revalidations: If-None-Match, answered 304;
//   (c) uncached warm 512x512 JPEG frames: a new camera every request, so every frame renders
//       (shadow maps cached, since the scene and lights do not change);
// beside the DESIGN.md section 8 targets, with "met" / "NOT met" (never a failure). Process
// CPU time per request is printed too: the machine is shared, and the load generator runs in
// the same process, so it is an upper bound on the server's own cost.
//
// Usage: http_benchmark [--seconds S] (per scenario and client count; default 4).
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <unistd.h>

#include "bench_support.hpp"
#include "oer/server/service.hpp"
#include "oer/server/service_config.hpp"
#include "targets.hpp"

using namespace oer;
using oer::bench::Clock;

namespace {

struct Result {
    std::size_t requests = 0;
    std::size_t failures = 0;
    double seconds = 0.0;
    double cpu_ms = 0.0;
    std::vector<double> latencies_ms;

    double percentile(double p) const {
        if (latencies_ms.empty()) {
            return 0.0;
        }
        std::vector<double> sorted = latencies_ms;
        std::sort(sorted.begin(), sorted.end());
        const std::size_t index =
            std::min(sorted.size() - 1, std::size_t(p * double(sorted.size() - 1) + 0.5));
        return sorted[index];
    }
};

// One request of a scenario: sends it and says whether the answer was the expected one.
using Request = std::function<bool(httplib::Client& client, std::size_t sequence)>;

Result run(int port, int clients, double seconds, const Request& request) {
    Result result;
    std::mutex mutex;
    std::atomic<std::size_t> sequence{0};
    const double cpu_start = bench::process_cpu_ms();
    const auto start = Clock::now();
    const auto deadline =
        start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    std::vector<std::thread> threads;
    for (int c = 0; c < clients; ++c) {
        threads.emplace_back([&] {
            httplib::Client client("127.0.0.1", port);
            client.set_keep_alive(true);
            client.set_read_timeout(60, 0);
            std::vector<double> latencies;
            std::size_t failures = 0;
            while (Clock::now() < deadline) {
                const auto begin = Clock::now();
                const bool ok = request(client, sequence++);
                latencies.push_back(bench::ms_since(begin));
                failures += !ok;
            }
            std::lock_guard lock(mutex);
            result.latencies_ms.insert(result.latencies_ms.end(), latencies.begin(),
                                       latencies.end());
            result.failures += failures;
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    result.seconds = bench::ms_since(start) / 1e3;
    result.cpu_ms = bench::process_cpu_ms() - cpu_start;
    result.requests = result.latencies_ms.size();
    return result;
}

void report(const char* name, int clients, const Result& result, double target_p50_ms) {
    const double p50 = result.percentile(0.5);
    std::printf(
        "%-34s %2d client%s %7zu req %9.1f req/s  p50 %8.3f ms  p99 %8.3f ms  "
        "cpu %7.3f ms/req  failures %zu",
        name, clients, clients == 1 ? " " : "s", result.requests,
        double(result.requests) / result.seconds, p50, result.percentile(0.99),
        result.requests ? result.cpu_ms / double(result.requests) : 0.0, result.failures);
    if (target_p50_ms > 0.0) {
        std::printf("  target p50 <= %g ms: %s", target_p50_ms,
                    p50 <= target_p50_ms ? "met" : "NOT met");
    }
    std::printf("\n");
    std::fflush(stdout);
}

std::string frame_query(double yaw) {
    return "/v1/render?environment=default&mesh=default&width=512&height=512&format=jpeg"
           "&pitch=15&distance=3&yaw=" +
           std::to_string(yaw);
}

}  // namespace

int main(int argc, char** argv) {
    double seconds = 4.0;
    for (int i = 1; i < argc; ++i) {
        if (std::string(argv[i]) == "--seconds" && i + 1 < argc) {
            seconds = std::atof(argv[++i]);
        } else {
            std::fprintf(stderr, "usage: %s [--seconds S]\n", argv[0]);
            return 2;
        }
    }
    std::random_device random;
    const std::filesystem::path data =
        std::filesystem::temp_directory_path() /
        ("oer-http-benchmark-" + std::to_string(::getpid()) + "-" + std::to_string(random()));
    server::ServiceConfig config;
    config.host = "127.0.0.1";
    config.port = 0;
    config.data_dir = data;
    config.access_log = false;
    int status = 0;
    try {
        server::Service service(config, [](std::string_view) {});
        service.start();
        std::printf(
            "http_benchmark: %s, %d render worker(s), %d HTTP threads, %u cores, %.0f s "
            "per run\n",
            service.url().c_str(), config.render_workers, config.http_threads,
            std::thread::hardware_concurrency(), seconds);
        const int port = service.port();

        // Warm up: the scene's shadow maps, and the frame the cached scenarios ask for.
        httplib::Client warm("127.0.0.1", port);
        warm.set_read_timeout(60, 0);
        const std::string cached_query = frame_query(30.0);
        const auto first = warm.Get(cached_query.c_str());
        if (!first || first->status != 200) {
            std::fprintf(stderr, "warm-up render failed: %s\n",
                         first ? (std::to_string(first->status) + " " + first->body).c_str()
                               : httplib::to_string(first.error()).c_str());
            status = 1;
        } else {
            const std::string etag = first->get_header_value("ETag");
            std::printf("warm-up frame: %zu bytes of JPEG, ETag %s, Server-Timing \"%s\"\n",
                        first->body.size(), etag.c_str(),
                        first->get_header_value("Server-Timing").c_str());

            const Request cached = [&](httplib::Client& client, std::size_t) {
                const auto answer = client.Get(cached_query.c_str());
                return answer && answer->status == 200 &&
                       answer->get_header_value("X-Oer-Cache") == "hit";
            };
            const Request revalidate = [&](httplib::Client& client, std::size_t) {
                const auto answer = client.Get(cached_query.c_str(), {{"If-None-Match", etag}});
                return answer && answer->status == 304;
            };
            // A new camera each request: yaw steps of 0.01 degree from -359 (within the API's +-360
            // for 71900 requests), never repeated.
            const Request uncached = [&](httplib::Client& client, std::size_t sequence) {
                const auto answer =
                    client.Get(frame_query(-359.0 + 0.01 * double(sequence)).c_str());
                return answer && answer->status == 200 &&
                       answer->get_header_value("X-Oer-Cache") == "miss";
            };
            std::size_t uncached_offset = 0;
            const Request uncached_offset_request = [&](httplib::Client& client,
                                                        std::size_t sequence) {
                return uncached(client, uncached_offset + sequence);
            };
            std::printf(
                "\nDESIGN.md section 8: warm 512x512 JPEG over HTTP p50 <= %g ms; a frame "
                "already in the cache (ETag hit or LRU) <= %g ms; preview frame while dragging "
                "p50 <= %g ms (not measured here: the web client's preview request does not "
                "exist yet)\n",
                bench::targets::kWarmJpegP50Ms, bench::targets::kCachedFrameMs,
                bench::targets::kPreviewP50Ms);
            report("(a) cached 512x512 JPEG", 1, run(port, 1, seconds, cached),
                   bench::targets::kCachedFrameMs);
            report("(a) cached 512x512 JPEG", 4, run(port, 4, seconds, cached), 0.0);
            report("(b) ETag 304 revalidation", 1, run(port, 1, seconds, revalidate),
                   bench::targets::kCachedFrameMs);
            report("(b) ETag 304 revalidation", 4, run(port, 4, seconds, revalidate), 0.0);
            const Result one = run(port, 1, seconds, uncached_offset_request);
            report("(c) uncached warm 512x512 JPEG", 1, one, bench::targets::kWarmJpegP50Ms);
            uncached_offset = 20000;  // yaw -159 on: cameras the first run did not use
            report("(c) uncached warm 512x512 JPEG", 2,
                   run(port, 2, seconds, uncached_offset_request), 0.0);
        }
        service.stop();
    } catch (const std::exception& error) {
        std::fprintf(stderr, "http_benchmark: %s\n", error.what());
        status = 1;
    }
    std::error_code ignored;
    std::filesystem::remove_all(data, ignored);
    return status;
}
