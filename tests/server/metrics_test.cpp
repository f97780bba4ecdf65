// The Prometheus registry: exact exposition text, escaping, histogram buckets (cumulative,
// "less than or equal"), misuse caught as bugs, and concurrent updates; the text is also
// parsed back, as a scraper would.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "error_kind.hpp"
#include "oer/core/error.hpp"
#include "oer/server/metrics.hpp"

using namespace oer::server;
using oer::testing::kind_of_failure;

namespace {

struct Sample {
    std::string name;
    Labels labels;
    double value = 0.0;
};

// A reader of the text format 0.0.4, independent of the writer: comment lines must be
// "# HELP name text" or "# TYPE name type"; sample lines are name{label="value",...} value, with
// \\, \" and \n escapes in label values.
std::vector<Sample> parse_exposition(const std::string& text) {
    std::vector<Sample> samples;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        if (line.starts_with("#")) {
            EXPECT_TRUE(line.starts_with("# HELP ") || line.starts_with("# TYPE ")) << line;
            continue;
        }
        Sample sample;
        std::size_t i = 0;
        while (i < line.size() && line[i] != '{' && line[i] != ' ') {
            sample.name += line[i++];
        }
        if (i < line.size() && line[i] == '{') {
            ++i;
            while (line.at(i) != '}') {
                std::string name, value;
                while (line.at(i) != '=') {
                    name += line[i++];
                }
                EXPECT_EQ(line.at(++i), '"') << line;
                for (++i; line.at(i) != '"'; ++i) {
                    if (line[i] == '\\') {
                        const char escaped = line.at(++i);
                        value += escaped == 'n' ? '\n' : escaped;
                    } else {
                        value += line[i];
                    }
                }
                ++i;
                if (line.at(i) == ',') {
                    ++i;
                }
                sample.labels[name] = value;
            }
            ++i;
        }
        EXPECT_EQ(line.at(i), ' ') << line;
        const std::string number = line.substr(i + 1);
        sample.value = number == "+Inf" ? INFINITY : std::stod(number);
        samples.push_back(sample);
    }
    return samples;
}

double value_of(const std::vector<Sample>& samples, const std::string& name, const Labels& labels) {
    for (const Sample& sample : samples) {
        if (sample.name == name && sample.labels == labels) {
            return sample.value;
        }
    }
    ADD_FAILURE() << "no sample " << name;
    return NAN;
}

}  // namespace

TEST(Metrics, CountersWithLabelsInExactText) {
    MetricsRegistry registry;
    const std::string help = "HTTP requests answered.";
    Counter& ok = registry.counter("oer_http_requests_total", help,
                                   {{"status", "200"}, {"route", "/v1/render"}});
    ok.increment();
    ok.increment(2);
    registry.counter("oer_http_requests_total", help, {{"route", "/v1/render"}, {"status", "422"}})
        .increment();
    EXPECT_EQ(&registry.counter("oer_http_requests_total", help,
                                {{"route", "/v1/render"}, {"status", "200"}}),
              &ok);
    EXPECT_EQ(ok.value(), 3.0);
    EXPECT_EQ(registry.render_prometheus_text(),
              "# HELP oer_http_requests_total HTTP requests answered.\n"
              "# TYPE oer_http_requests_total counter\n"
              "oer_http_requests_total{route=\"/v1/render\",status=\"200\"} 3\n"
              "oer_http_requests_total{route=\"/v1/render\",status=\"422\"} 1\n");
}

TEST(Metrics, GaugesAndFamiliesInNameOrder) {
    MetricsRegistry registry;
    Gauge& depth = registry.gauge("oer_render_queue_depth", "Render requests waiting.");
    depth.set(4);
    depth.add(-1.5);
    registry.counter("oer_frames_total", "Frames rendered.").increment(0.25);
    EXPECT_EQ(registry.render_prometheus_text(),
              "# HELP oer_frames_total Frames rendered.\n"
              "# TYPE oer_frames_total counter\n"
              "oer_frames_total 0.25\n"
              "# HELP oer_render_queue_depth Render requests waiting.\n"
              "# TYPE oer_render_queue_depth gauge\n"
              "oer_render_queue_depth 2.5\n");
}

TEST(Metrics, HistogramBucketsAreCumulativeAndIncludeTheirBound) {
    MetricsRegistry registry;
    const std::vector<double> bounds{0.1, 0.5, 1};
    Histogram& latency =
        registry.histogram("oer_render_seconds", "Render latency.", bounds, {{"format", "jpeg"}});
    for (const double seconds : {0.05, 0.1, 0.3, 2.0}) {
        latency.observe(seconds);
    }
    EXPECT_EQ(registry.render_prometheus_text(),
              "# HELP oer_render_seconds Render latency.\n"
              "# TYPE oer_render_seconds histogram\n"
              "oer_render_seconds_bucket{format=\"jpeg\",le=\"0.1\"} 2\n"
              "oer_render_seconds_bucket{format=\"jpeg\",le=\"0.5\"} 3\n"
              "oer_render_seconds_bucket{format=\"jpeg\",le=\"1\"} 3\n"
              "oer_render_seconds_bucket{format=\"jpeg\",le=\"+Inf\"} 4\n"
              "oer_render_seconds_sum{format=\"jpeg\"} 2.45\n"
              "oer_render_seconds_count{format=\"jpeg\"} 4\n");
    const Histogram::Snapshot snapshot = latency.snapshot();
    EXPECT_EQ(snapshot.cumulative_counts, (std::vector<std::uint64_t>{2, 3, 3, 4}));
    EXPECT_EQ(snapshot.count, 4u);
    EXPECT_DOUBLE_EQ(snapshot.sum, 2.45);
}

TEST(Metrics, LatencyHistogramParsedBackIsCumulative) {
    MetricsRegistry registry;
    Histogram& histogram = registry.histogram("oer_preprocess_seconds", "Preprocessing latency.",
                                              kLatencyBucketsSeconds);
    // Observation i is i milliseconds: 0 .. 199.999 seconds.
    for (int i = 0; i < 200'000; i += 7) {
        histogram.observe(i / 1000.0);
    }
    const std::vector<Sample> samples = parse_exposition(registry.render_prometheus_text());
    double previous = 0.0;
    for (const double bound : kLatencyBucketsSeconds) {
        std::ostringstream le;
        le << bound;
        const double count = value_of(samples, "oer_preprocess_seconds_bucket", {{"le", le.str()}});
        // Observations i / 1000 <= bound with i a multiple of 7: floor(bound * 1000 / 7) + 1.
        EXPECT_EQ(count, std::floor(std::round(bound * 1000) / 7) + 1) << "le=" << bound;
        EXPECT_GE(count, previous);
        previous = count;
    }
    const double total = value_of(samples, "oer_preprocess_seconds_count", {});
    EXPECT_EQ(total, 28572.0);  // ceil(200000 / 7)
    EXPECT_EQ(value_of(samples, "oer_preprocess_seconds_bucket", {{"le", "+Inf"}}), total);
    EXPECT_NEAR(value_of(samples, "oer_preprocess_seconds_sum", {}), 0.007 * 28571 * 28572 / 2,
                1e-3);
}

TEST(Metrics, LabelValuesAndHelpAreEscaped) {
    MetricsRegistry registry;
    const std::string awkward = "a\\b\"c\nd";
    registry.counter("oer_odd_total", "Help with \\ and\na newline.", {{"path", awkward}})
        .increment(7);
    const std::string text = registry.render_prometheus_text();
    EXPECT_EQ(text,
              "# HELP oer_odd_total Help with \\\\ and\\na newline.\n"
              "# TYPE oer_odd_total counter\n"
              "oer_odd_total{path=\"a\\\\b\\\"c\\nd\"} 7\n");
    const std::vector<Sample> samples = parse_exposition(text);
    ASSERT_EQ(samples.size(), 1u);
    EXPECT_EQ(samples[0].labels.at("path"), awkward);
    EXPECT_EQ(samples[0].value, 7.0);
}

TEST(Metrics, MisuseIsABug) {
    MetricsRegistry registry;
    registry.counter("oer_a_total", "A.");
    const std::vector<double> bounds{1, 2};
    registry.histogram("oer_h_seconds", "H.", bounds);
    const std::vector<std::function<void()>> misuses{
        [&] { registry.gauge("oer_a_total", "A."); },
        [&] { registry.counter("oer_a_total", "Another description."); },
        [&] { registry.counter("1starts_with_digit", "X."); },
        [&] { registry.counter("has-dash", "X."); },
        [&] { registry.counter("", "X."); },
        [&] {
            registry.counter("oer_b_total", "B.", {{"bad-label", "x"}});
        },
        [&] {
            registry.counter("oer_b_total", "B.", {{"__reserved", "x"}});
        },
        [&] {
            registry.histogram("oer_h_seconds", "H.", bounds, {{"le", "1"}});
        },
        [&] {
            registry.histogram("oer_h_seconds", "H.", std::vector<double>{1, 3});
        },
        [&] {
            registry.histogram("oer_g_seconds", "G.", std::vector<double>{2, 1});
        },
        [&] {
            registry.histogram("oer_i_seconds", "I.", std::vector<double>{1, INFINITY});
        },
        [&] { registry.counter("oer_a_total", "A.").increment(-1); },
        [&] { registry.counter("oer_a_total", "A.").increment(NAN); },
        [&] { registry.histogram("oer_h_seconds", "H.", bounds).observe(NAN); },
    };
    for (std::size_t i = 0; i < misuses.size(); ++i) {
        EXPECT_EQ(kind_of_failure(misuses[i]), oer::ErrorKind::Internal) << "misuse " << i;
    }
    EXPECT_EQ(registry.counter("oer_a_total", "A.").value(), 0.0);
    EXPECT_EQ(registry.render_prometheus_text(),
              "# HELP oer_a_total A.\n"
              "# TYPE oer_a_total counter\n"
              "oer_a_total 0\n"
              "# HELP oer_h_seconds H.\n"
              "# TYPE oer_h_seconds histogram\n"
              "oer_h_seconds_bucket{le=\"1\"} 0\n"
              "oer_h_seconds_bucket{le=\"2\"} 0\n"
              "oer_h_seconds_bucket{le=\"+Inf\"} 0\n"
              "oer_h_seconds_sum 0\n"
              "oer_h_seconds_count 0\n");
}

TEST(Metrics, ConcurrentUpdatesAreAllCounted) {
    MetricsRegistry registry;
    constexpr int kThreads = 4, kUpdates = 20'000;
    const std::vector<double> bounds{0.5};
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            for (int i = 0; i < kUpdates; ++i) {
                registry.counter("oer_requests_total", "R.", {{"thread", std::to_string(t % 2)}})
                    .increment();
                registry.gauge("oer_depth", "D.").add(1);
                registry.histogram("oer_latency_seconds", "L.", bounds).observe(i % 2);
                if (i % 1000 == 0) {
                    registry.render_prometheus_text();
                }
            }
        });
    }
    for (auto& thread : threads) {
        thread.join();
    }
    const std::vector<Sample> samples = parse_exposition(registry.render_prometheus_text());
    EXPECT_EQ(value_of(samples, "oer_requests_total", {{"thread", "0"}}), 2.0 * kUpdates);
    EXPECT_EQ(value_of(samples, "oer_requests_total", {{"thread", "1"}}), 2.0 * kUpdates);
    EXPECT_EQ(value_of(samples, "oer_depth", {}), 4.0 * kUpdates);
    EXPECT_EQ(value_of(samples, "oer_latency_seconds_bucket", {{"le", "0.5"}}), 2.0 * kUpdates);
    EXPECT_EQ(value_of(samples, "oer_latency_seconds_count", {}), 4.0 * kUpdates);
    EXPECT_EQ(value_of(samples, "oer_latency_seconds_sum", {}), 2.0 * kUpdates);
}
