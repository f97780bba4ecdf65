#pragma once
// The service's metrics and their Prometheus text exposition (format 0.0.4), without an
// external library: counters and gauges with label sets, and histograms with fixed buckets.
// Every operation is thread-safe. Series live as long as the registry, so a caller may keep
// the reference it gets and update it without a lookup.
#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

namespace oer::server {

enum class MetricType { Counter, Gauge, Histogram };

// Label name -> value; ordered, so one label set has one spelling.
using Labels = std::map<std::string, std::string>;

// Upper bounds, in seconds, for render and preprocess latencies: from a cached frame (a few
// milliseconds) to preprocessing a large map (tens of seconds).
inline constexpr std::array<double, 14> kLatencyBucketsSeconds{
    0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 30.0, 60.0, 120.0};

class Counter {
  public:
    void increment(double amount = 1.0);  // amount must be finite and >= 0 (oer::Error)
    double value() const { return value_.load(); }

  private:
    std::atomic<double> value_{0.0};
};

class Gauge {
  public:
    void set(double value) { value_.store(value); }
    void add(double amount) { value_.fetch_add(amount); }
    double value() const { return value_.load(); }

  private:
    std::atomic<double> value_{0.0};
};

class Histogram {
  public:
    struct Snapshot {
        std::vector<std::uint64_t> cumulative_counts;  // per upper bound, then +Inf (== count)
        double sum = 0.0;
        std::uint64_t count = 0;
    };

    // Bounds finite and strictly increasing (oer::Error otherwise); +Inf is implicit.
    explicit Histogram(std::span<const double> upper_bounds);
    void observe(double value);  // a NaN throws oer::Error
    const std::vector<double>& upper_bounds() const { return upper_bounds_; }
    Snapshot snapshot() const;  // consistent: taken under the same lock as observe

  private:
    const std::vector<double> upper_bounds_;
    mutable std::mutex mutex_;
    std::vector<std::uint64_t> counts_;  // per bucket, not cumulative; last is (max bound, +Inf)
    double sum_ = 0.0;
};

class MetricsRegistry {
  public:
    // The series of family `name` with these labels, created (zero) on first use. A family has
    // one type, one help text and, for histograms, one set of bounds: asking for it with a
    // different one, an invalid metric or label name, or a histogram label "le", throws
    // oer::Error (Internal), since each of those is a bug in the caller.
    Counter& counter(const std::string& name, const std::string& help, const Labels& labels = {});
    Gauge& gauge(const std::string& name, const std::string& help, const Labels& labels = {});
    Histogram& histogram(const std::string& name, const std::string& help,
                         std::span<const double> upper_bounds, const Labels& labels = {});

    // Every family in name order, every series in label order: "# HELP", "# TYPE", then the
    // samples (histograms as name_bucket{le=...}, name_sum, name_count).
    std::string render_prometheus_text() const;

  private:
    struct Family {
        MetricType type;
        std::string help;
        std::vector<double> upper_bounds;  // histograms only
        std::map<Labels, std::unique_ptr<Counter>> counters;
        std::map<Labels, std::unique_ptr<Gauge>> gauges;
        std::map<Labels, std::unique_ptr<Histogram>> histograms;
    };

    // With mutex_ held: the family, created or checked against type, help and bounds.
    Family& family(const std::string& name, MetricType type, const std::string& help,
                   std::span<const double> upper_bounds, const Labels& labels);

    mutable std::mutex mutex_;
    std::map<std::string, Family> families_;
};

}  // namespace oer::server
