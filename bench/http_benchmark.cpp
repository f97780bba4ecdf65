// The service over HTTP on loopback: a Service started in-process (default configuration, a
// temporary data folder) and a load generator of N client threads with keep-alive
// connections, each scenario bounded in time. Requests per second and p50 / p99 latency for
//   (a) cached 512x512 JPEG frames: the same request again, answered from the frame cache;
//   (b) ETag revalidations: If-None-Match, answered 304;
//   (c) uncached warm 512x512 JPEG frames: a new camera every request, so every frame renders
//       (shadow maps cached, since the scene and lights do not change);
//   (d) preview frames while dragging: the preview recipe of api/openapi.yaml (the web client's
//       PREVIEW: half of each side, samples=1, quality=50, shadow_resolution=256,
//       shadow_filter=hard) of (c)'s frame, a new orbit yaw every request, against (c)'s p50;
//   (e) preview frames while the environment turns: the same preview at a fixed camera with a
//       new environment_yaw every request, so every light moves and every shadow map is new
//       (the dressing room's environment slider), against the full frame doing the same;
//   (f) a colour change and the floor's toggle: (c)'s frame with a new base colour each
//       request, and with the floor toggled each request, against (c)'s p50;
//   (g) a new product: the Stanford bunny's OBJ (made new each time by a comment, so that its
//       content id is new) from the start of its upload to its first frame (Prefer: wait=0, a
//       preliminary frame while its transfer bakes) and to its refined frame; then, its
//       preparation done, its floor's first toggle against a new frame with the floor;
// beside the docs/design.md section 8 targets, with "met" / "NOT met" (never a failure). Process
// CPU time per request is printed too: the machine is shared, and the load generator runs in
// the same process, so it is an upper bound on the server's own cost. For the frames that
// render, the p50 of each pass the server reports in Server-Timing follows, and of the rest of
// each request's time (HTTP, parsing, the render queue), so that the figures say where the time
// goes.
//
// Usage: http_benchmark [--seconds S] [--render-workers N] (S per scenario and client count,
// default 4; N the service's render workers, default its own: run it with 1 and 2 to see
// whether a second worker pays, in frames a second and CPU per frame at 2 clients).
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "bench_support.hpp"
#include "oer/server/service.hpp"
#include "oer/server/service_config.hpp"
#include "targets.hpp"

using namespace oer;
using oer::bench::Clock;

namespace {

// What one request of a scenario got: whether it was the expected answer, and the server's
// Server-Timing header (empty for a cached frame or a 304).
struct Answer {
    bool expected = false;
    std::string server_timing;
};

Answer answer_of(const httplib::Result& result, bool expected) {
    return {expected, result ? result->get_header_value("Server-Timing") : std::string()};
}

struct Result {
    std::size_t requests = 0;
    std::size_t failures = 0;
    double seconds = 0.0;
    double cpu_ms = 0.0;
    std::vector<double> latencies_ms;
    // Per Server-Timing entry, one time per rendered frame; "outside the renderer" is each
    // such request's latency less the renderer's total and the encoding.
    std::vector<std::string> pass_order;
    std::map<std::string, std::vector<double>> passes_ms;

    double percentile(double p) const { return bench::percentile(latencies_ms, p); }

    void add_passes(const std::string& header, double latency_ms) {
        if (header.empty()) {
            return;
        }
        double renderer_ms = 0.0;
        for (const auto& [name, ms] : bench::parse_server_timing(header)) {
            add_pass(name, ms);
            if (name == "total" || name == "encode") {
                renderer_ms += ms;
            }
        }
        add_pass("outside the renderer", latency_ms - renderer_ms);
    }

  private:
    void add_pass(const std::string& name, double ms) {
        if (!passes_ms.contains(name)) {
            pass_order.push_back(name);
        }
        passes_ms[name].push_back(ms);
    }
};

// One request of a scenario: sends it and says what it got.
using Request = std::function<Answer(httplib::Client& client, std::size_t sequence)>;

Result run(int port, int clients, double seconds, const Request& request) {
    Result result;
    std::mutex mutex;
    std::vector<std::pair<std::string, double>> timed;  // (Server-Timing, latency in ms)
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
            std::vector<std::string> timings;
            std::size_t failures = 0;
            while (Clock::now() < deadline) {
                const auto begin = Clock::now();
                Answer answer = request(client, sequence++);
                latencies.push_back(bench::ms_since(begin));
                timings.push_back(std::move(answer.server_timing));
                failures += !answer.expected;
            }
            std::lock_guard lock(mutex);
            result.latencies_ms.insert(result.latencies_ms.end(), latencies.begin(),
                                       latencies.end());
            for (std::size_t i = 0; i < timings.size(); ++i) {
                timed.emplace_back(std::move(timings[i]), latencies[i]);
            }
            result.failures += failures;
        });
    }
    for (std::thread& thread : threads) {
        thread.join();
    }
    // Read here, not in the clients' threads, so that a malformed header is reported (main's
    // catch) rather than terminating the process.
    for (const auto& [header, latency_ms] : timed) {
        result.add_passes(header, latency_ms);
    }
    result.seconds = bench::ms_since(start) / 1e3;
    result.cpu_ms = bench::process_cpu_ms() - cpu_start;
    result.requests = result.latencies_ms.size();
    return result;
}

void report(const char* name, int clients, const Result& result, double target_p50_ms) {
    const double p50 = result.percentile(0.5);
    std::printf(
        "%-40s %2d client%s %7zu req %9.1f req/s  p50 %8.3f ms  p90 %8.3f ms  p99 %8.3f ms  "
        "cpu %7.3f ms/req  failures %zu",
        name, clients, clients == 1 ? " " : "s", result.requests,
        double(result.requests) / result.seconds, p50, result.percentile(0.9),
        result.percentile(0.99), result.requests ? result.cpu_ms / double(result.requests) : 0.0,
        result.failures);
    if (target_p50_ms > 0.0) {
        std::printf("  target p50 <= %g ms: %s", target_p50_ms,
                    p50 <= target_p50_ms ? "met" : "NOT met");
    }
    std::printf("\n");
    std::fflush(stdout);
}

// The p50 of each pass of Server-Timing over the frames that rendered, in the server's order.
void report_passes(const Result& result) {
    if (result.pass_order.empty()) {
        return;
    }
    std::string passes;
    for (const std::string& pass : result.pass_order) {
        char entry[96];
        std::snprintf(entry, sizeof entry, "%s %.2f ms", pass.c_str(),
                      bench::percentile(result.passes_ms.at(pass), 0.5));
        passes += (passes.empty() ? "" : ", ") + std::string(entry);
    }
    std::printf("    Server-Timing p50 over %zu frames: %s\n",
                result.passes_ms.at(result.pass_order.front()).size(), passes.c_str());
    std::fflush(stdout);
}

// A preview case beside its full frame, measured in the same run: the target, and the ratio of
// their medians.
void report_preview(const char* name, const Result& preview, const char* full_name,
                    const Result& full) {
    report(name, 1, preview, bench::targets::kPreviewP50Ms);
    report_passes(preview);
    const double full_p50 = full.percentile(0.5);
    std::printf("    against %s p50 %.3f ms: %.3fx of its time\n", full_name, full_p50,
                full_p50 > 0.0 ? preview.percentile(0.5) / full_p50 : 0.0);
    std::fflush(stdout);
}

// The benchmark's scene: the default scene from an orbit at pitch 15 and distance 3, `side`
// pixels square; `yaw` turns the camera about it, `environment_yaw` the environment (every
// light with it). Numbers as the fixed-point text of std::to_string, which the API reads.
std::string scene_query(int side, double yaw, double environment_yaw) {
    return "/v1/render?environment=default&mesh=default&width=" + std::to_string(side) +
           "&height=" + std::to_string(side) +
           "&format=jpeg&pitch=15&distance=3&yaw=" + std::to_string(yaw) +
           "&environment_yaw=" + std::to_string(environment_yaw);
}

constexpr int kFullSide = 512;
constexpr const char* kBunny = "/usr/share/glmark2/models/bunny.obj";

// The full frame at the service's defaults (JPEG quality 85, 4 samples, 2048-texel PCF shadow
// maps).
std::string frame_query(double yaw, double environment_yaw = 0.0) {
    return scene_query(kFullSide, yaw, environment_yaw);
}

// (g): a product new to the service, uploaded, then drawn at once and refined. Seconds from the
// start of the upload to the first frame and to the frame with the transfer; negative when a
// step failed (printed).
struct NewProductTimes {
    double upload_s = -1.0;
    double first_s = -1.0;
    double refined_s = -1.0;
    // Once its preparation is done: a frame from a new angle, and the same with the floor off
    // (the floorless scene was baked ahead at upload).
    double normal_ms = -1.0;
    double floor_toggle_ms = -1.0;
};

NewProductTimes new_product(int port, const std::string& obj, int serial) {
    httplib::Client client("127.0.0.1", port);
    client.set_read_timeout(120, 0);
    const std::string bytes = obj + "\n# http_benchmark upload " + std::to_string(serial) + "\n";
    const auto start = Clock::now();
    const auto upload = client.Post("/v1/meshes", bytes, "model/obj");
    if (!upload || upload->status != 201) {
        std::printf("    upload failed: %s\n",
                    upload ? (std::to_string(upload->status) + " " + upload->body).c_str()
                           : httplib::to_string(upload.error()).c_str());
        return {};
    }
    NewProductTimes times;
    times.upload_s = bench::ms_since(start) / 1e3;
    const std::size_t id_at = upload->body.find("\"id\":\"");
    const std::string id =
        upload->body.substr(id_at + 6, upload->body.find('"', id_at + 6) - id_at - 6);
    const std::string query = "/v1/render?environment=default&mesh=" + id +
                              "&width=512&height=512&format=jpeg&pitch=15&yaw=30";
    const auto first = client.Get(query.c_str(), {{"Prefer", "wait=0"}});
    if (!first || first->status != 200) {
        std::printf("    first frame failed\n");
        return times;
    }
    times.first_s = bench::ms_since(start) / 1e3;
    // As the viewer does: ask again every 0.5 s until the frame is whole.
    for (bool preliminary = first->has_header("X-Oer-Preliminary"); preliminary;) {
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        const auto again = client.Get(query.c_str(), {{"Prefer", "wait=0"}});
        if (!again || again->status != 200) {
            std::printf("    refined frame failed\n");
            return times;
        }
        preliminary = again->has_header("X-Oer-Preliminary");
    }
    times.refined_s = bench::ms_since(start) / 1e3;
    const std::string preparation = "/v1/meshes/" + id + "/preparation";
    for (const auto deadline = Clock::now() + std::chrono::seconds(120); Clock::now() < deadline;
         std::this_thread::sleep_for(std::chrono::milliseconds(100))) {
        const auto answer = client.Get(preparation.c_str());
        if (!answer || answer->status != 200 ||
            nlohmann::json::parse(answer->body).at("without_floor").at("state") != "baking") {
            break;
        }
    }
    const auto timed = [&](const std::string& variant) {
        const auto begin = Clock::now();
        const auto answer = client.Get((query + variant).c_str());
        return answer && answer->status == 200 && !answer->has_header("X-Oer-Preliminary")
                   ? bench::ms_since(begin)
                   : -1.0;
    };
    times.normal_ms = timed("&exposure=0.01");
    times.floor_toggle_ms = timed("&ground=off");
    return times;
}

// The preview recipe (api/openapi.yaml, GET /v1/render; web/oer-viewer.js PREVIEW) of that frame.
std::string preview_query(double yaw, double environment_yaw = 0.0) {
    return scene_query(kFullSide / 2, yaw, environment_yaw) +
           "&samples=1&quality=50&shadow_resolution=256&shadow_filter=hard";
}

}  // namespace

int main(int argc, char** argv) {
    double seconds = 4.0;
    int render_workers = 0;
    for (int i = 1; i < argc; ++i) {
        if (std::string(argv[i]) == "--seconds" && i + 1 < argc) {
            seconds = std::atof(argv[++i]);
        } else if (std::string(argv[i]) == "--render-workers" && i + 1 < argc) {
            render_workers = std::atoi(argv[++i]);
        } else {
            std::fprintf(stderr, "usage: %s [--seconds S] [--render-workers N]\n", argv[0]);
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
    // Its clients share one address and measure latency: the per-client share of rendering
    // would turn a long run's uncached frames into 429s.
    config.client_render_rate = 0.0;
    if (render_workers > 0) {
        config.render_workers = render_workers;
    }
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
                return answer_of(answer, answer && answer->status == 200 &&
                                             answer->get_header_value("X-Oer-Cache") == "hit");
            };
            const Request revalidate = [&](httplib::Client& client, std::size_t) {
                const auto answer = client.Get(cached_query.c_str(), {{"If-None-Match", etag}});
                return answer_of(answer, answer && answer->status == 304);
            };
            // A frame that must render: a request the cache has not seen.
            const auto rendered = [](httplib::Client& client, const std::string& query) {
                const auto answer = client.Get(query.c_str());
                return answer_of(answer, answer && answer->status == 200 &&
                                             answer->get_header_value("X-Oer-Cache") == "miss");
            };
            // A new angle each request: steps of 0.01 degree from -359 (within the API's +-360
            // for 71900 requests), never repeated within a case.
            const auto step = [](std::size_t sequence) { return -359.0 + 0.01 * double(sequence); };
            std::size_t uncached_offset = 0;
            const Request uncached = [&](httplib::Client& client, std::size_t sequence) {
                return rendered(client, frame_query(step(uncached_offset + sequence)));
            };
            // (d): the orbit turns, the lights stay: the 256-texel shadow maps are made once.
            const Request preview_orbit = [&](httplib::Client& client, std::size_t sequence) {
                return rendered(client, preview_query(step(sequence)));
            };
            // (e): the environment turns under a still camera: every shadow map is new.
            const Request preview_environment = [&](httplib::Client& client, std::size_t sequence) {
                return rendered(client, preview_query(30.0, step(sequence)));
            };
            const Request full_environment = [&](httplib::Client& client, std::size_t sequence) {
                return rendered(client, frame_query(30.0, step(sequence)));
            };
            std::printf(
                "\ndocs/design.md section 8: warm 512x512 JPEG over HTTP p50 <= %g ms; a frame "
                "already in the cache (ETag hit or LRU) <= %g ms; preview frame while dragging "
                "p50 <= %g ms (the preview recipe at half of each side: %dx%d)\n",
                bench::targets::kWarmJpegP50Ms, bench::targets::kCachedFrameMs,
                bench::targets::kPreviewP50Ms, kFullSide / 2, kFullSide / 2);
            report("(a) cached 512x512 JPEG", 1, run(port, 1, seconds, cached),
                   bench::targets::kCachedFrameMs);
            report("(a) cached 512x512 JPEG", 4, run(port, 4, seconds, cached), 0.0);
            report("(b) ETag 304 revalidation", 1, run(port, 1, seconds, revalidate),
                   bench::targets::kCachedFrameMs);
            report("(b) ETag 304 revalidation", 4, run(port, 4, seconds, revalidate), 0.0);
            const Result full_orbit = run(port, 1, seconds, uncached);
            report("(c) uncached warm 512x512 JPEG", 1, full_orbit, bench::targets::kWarmJpegP50Ms);
            report_passes(full_orbit);
            uncached_offset = 20000;  // yaw -159 on: cameras the first run did not use
            report("(c) uncached warm 512x512 JPEG", 2, run(port, 2, seconds, uncached), 0.0);

            // Each preview case starts after one request outside its sequence, which pays for
            // what only its first frame needs (its 256-texel shadow maps, for (d)).
            rendered(warm, preview_query(359.5));
            report_preview("(d) preview 256x256, orbit turning",
                           run(port, 1, seconds, preview_orbit), "(c) 1 client", full_orbit);
            rendered(warm, preview_query(30.0, 359.5));
            const Result previews_turning = run(port, 1, seconds, preview_environment);
            const Result full_turning = run(port, 1, seconds, full_environment);
            report_preview("(e) preview 256x256, environment turning", previews_turning,
                           "the full 512x512 frame, environment turning", full_turning);
            report("(e) full 512x512, environment turning", 1, full_turning, 0.0);
            report_passes(full_turning);

            // (f): the camera still, a new colour each request; then the floor toggled.
            const Request recolour = [&](httplib::Client& client, std::size_t sequence) {
                const double red = double(sequence % 997) / 997.0;
                return rendered(
                    client, frame_query(30.0) + "&base_color=" + std::to_string(red) + ",0.3,0.2");
            };
            const Request toggle_floor = [&](httplib::Client& client, std::size_t sequence) {
                return rendered(client, frame_query(step(40000 + sequence)) +
                                            (sequence % 2 == 0 ? "&ground=off" : ""));
            };
            const Result recoloured = run(port, 1, seconds, recolour);
            const Result toggled = run(port, 1, seconds, toggle_floor);
            const double normal_p50 = full_orbit.percentile(0.5);
            for (const auto& [name, result] :
                 {std::pair<const char*, const Result&>{"(f) colour change", recoloured},
                  std::pair<const char*, const Result&>{"(f) floor toggle", toggled}}) {
                report(name, 1, result, 0.0);
                const double ratio = result.percentile(0.5) / normal_p50;
                std::printf("    against (c) p50 %.3f ms: %.2fx   target <= %gx: %s\n", normal_p50,
                            ratio, bench::targets::kChangeOverNormalFrame,
                            ratio <= bench::targets::kChangeOverNormalFrame ? "met" : "NOT met");
            }

            // (g): three new products, one after another; the medians.
            const std::string obj = bench::read_file(kBunny);
            std::vector<double> uploads, firsts, refined, normals, toggles;
            for (int serial = 0; serial < 3; ++serial) {
                const NewProductTimes times = new_product(port, obj, serial);
                if (times.upload_s >= 0.0) {
                    uploads.push_back(times.upload_s);
                }
                if (times.first_s >= 0.0) {
                    firsts.push_back(times.first_s);
                }
                if (times.refined_s >= 0.0) {
                    refined.push_back(times.refined_s);
                }
                if (times.normal_ms >= 0.0 && times.floor_toggle_ms >= 0.0) {
                    normals.push_back(times.normal_ms);
                    toggles.push_back(times.floor_toggle_ms);
                }
            }
            const double first_p50 = bench::percentile(firsts, 0.5);
            const double refined_p50 = bench::percentile(refined, 0.5);
            std::printf(
                "(g) new product (the bunny, 69k triangles), upload to first frame: p50 %.2f s "
                "of %zu   target <= %g s: %s\n",
                first_p50, firsts.size(), bench::targets::kNewProductFirstFrameS,
                first_p50 <= bench::targets::kNewProductFirstFrameS ? "met" : "NOT met");
            std::printf(
                "    of which the upload itself (parsing and storing the OBJ): p50 %.2f s\n",
                bench::percentile(uploads, 0.5));
            std::printf(
                "(g) new product, upload to refined frame: p50 %.2f s of %zu   target <= "
                "%g s: %s\n",
                refined_p50, refined.size(), bench::targets::kNewProductRefinedS,
                refined_p50 <= bench::targets::kNewProductRefinedS ? "met" : "NOT met");
            const double toggle_ratio =
                bench::percentile(toggles, 0.5) / bench::percentile(normals, 0.5);
            std::printf(
                "(g) new product prepared, the floor's first toggle: p50 %.1f ms against %.1f ms "
                "for a new frame with it: %.2fx   target <= %gx: %s\n",
                bench::percentile(toggles, 0.5), bench::percentile(normals, 0.5), toggle_ratio,
                bench::targets::kChangeOverNormalFrame,
                toggle_ratio <= bench::targets::kChangeOverNormalFrame ? "met" : "NOT met");
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
