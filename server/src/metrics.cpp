#include "oer/server/metrics.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "oer/core/error.hpp"

namespace oer::server {

namespace {

bool is_name_start(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}

bool is_name_char(char c) {
    return is_name_start(c) || (c >= '0' && c <= '9');
}

// Prometheus data model: metric names [a-zA-Z_:][a-zA-Z0-9_:]*, label names [a-zA-Z_][a-zA-Z0-9_]*
// with names starting "__" reserved.
bool is_metric_name(const std::string& name) {
    return !name.empty() && (is_name_start(name[0]) || name[0] == ':') &&
           std::all_of(name.begin(), name.end(),
                       [](char c) { return is_name_char(c) || c == ':'; });
}

bool is_label_name(const std::string& name) {
    return !name.empty() && is_name_start(name[0]) && !name.starts_with("__") &&
           std::all_of(name.begin(), name.end(), is_name_char);
}

// HELP text escapes backslash and newline; label values also the double quote.
std::string escape(const std::string& text, bool quote) {
    std::string escaped;
    escaped.reserve(text.size());
    for (const char c : text) {
        if (c == '\\') {
            escaped += "\\\\";
        } else if (c == '\n') {
            escaped += "\\n";
        } else if (c == '"' && quote) {
            escaped += "\\\"";
        } else {
            escaped += c;
        }
    }
    return escaped;
}

// Go's ParseFloat spellings, which Prometheus reads: shortest round-trip decimal, +Inf, -Inf,
// NaN.
std::string format_number(double value) {
    if (std::isnan(value)) {
        return "NaN";
    }
    if (std::isinf(value)) {
        return value > 0 ? "+Inf" : "-Inf";
    }
    std::array<char, 32> buffer{};
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    return std::string(buffer.data(), result.ptr);
}

// {a="1",b="2"}, with `extra` (the bucket's le) last; empty when there are no labels at all.
std::string format_labels(const Labels& labels, const std::string& extra = "") {
    std::string text;
    for (const auto& [name, value] : labels) {
        text += (text.empty() ? "" : ",") + name + "=\"" + escape(value, true) + "\"";
    }
    if (!extra.empty()) {
        text += (text.empty() ? "" : ",") + extra;
    }
    return text.empty() ? "" : "{" + text + "}";
}

std::string type_name(MetricType type) {
    switch (type) {
        case MetricType::Counter:
            return "counter";
        case MetricType::Gauge:
            return "gauge";
        case MetricType::Histogram:
            return "histogram";
    }
    throw Error(ErrorKind::Internal, "unknown metric type");
}

void check_upper_bounds(std::span<const double> upper_bounds) {
    for (std::size_t i = 0; i < upper_bounds.size(); ++i) {
        if (!std::isfinite(upper_bounds[i]) || (i > 0 && upper_bounds[i] <= upper_bounds[i - 1])) {
            throw Error(ErrorKind::Internal,
                        "histogram bounds must be finite and strictly increasing; bound " +
                            std::to_string(i) + " is " + format_number(upper_bounds[i]));
        }
    }
}

}  // namespace

void Counter::increment(double amount) {
    if (!(amount >= 0.0) || std::isinf(amount)) {
        throw Error(ErrorKind::Internal,
                    "a counter only grows by a finite amount >= 0, got " + format_number(amount));
    }
    value_.fetch_add(amount);
}

Histogram::Histogram(std::span<const double> upper_bounds)
    : upper_bounds_(upper_bounds.begin(), upper_bounds.end()), counts_(upper_bounds.size() + 1) {
    check_upper_bounds(upper_bounds_);
}

void Histogram::observe(double value) {
    if (std::isnan(value)) {
        throw Error(ErrorKind::Internal, "histogram observation is NaN");
    }
    // Buckets are "less than or equal": a value on a bound counts in that bound's bucket.
    const auto bucket =
        std::lower_bound(upper_bounds_.begin(), upper_bounds_.end(), value) - upper_bounds_.begin();
    const std::lock_guard lock(mutex_);
    ++counts_[std::size_t(bucket)];
    sum_ += value;
}

Histogram::Snapshot Histogram::snapshot() const {
    const std::lock_guard lock(mutex_);
    Snapshot snapshot;
    snapshot.sum = sum_;
    for (const std::uint64_t count : counts_) {
        snapshot.count += count;
        snapshot.cumulative_counts.push_back(snapshot.count);
    }
    return snapshot;
}

MetricsRegistry::Family& MetricsRegistry::family(const std::string& name, MetricType type,
                                                 const std::string& help,
                                                 std::span<const double> upper_bounds,
                                                 const Labels& labels) {
    if (!is_metric_name(name)) {
        throw Error(ErrorKind::Internal, "invalid metric name \"" + name + "\"");
    }
    for (const auto& [label, value] : labels) {
        if (!is_label_name(label) || (type == MetricType::Histogram && label == "le")) {
            throw Error(ErrorKind::Internal,
                        "invalid label name \"" + label + "\" for metric " + name);
        }
    }
    check_upper_bounds(upper_bounds);
    std::vector<double> bounds(upper_bounds.begin(), upper_bounds.end());
    Family& family = families_.try_emplace(name, Family{type, help, std::move(bounds), {}, {}, {}})
                         .first->second;
    if (family.type != type) {
        throw Error(ErrorKind::Internal, "metric " + name + " is a " + type_name(family.type) +
                                             ", not a " + type_name(type));
    }
    if (family.help != help) {
        throw Error(ErrorKind::Internal, "metric " + name + " was described as \"" + family.help +
                                             "\", not \"" + help + "\"");
    }
    if (!std::equal(family.upper_bounds.begin(), family.upper_bounds.end(), upper_bounds.begin(),
                    upper_bounds.end())) {
        throw Error(ErrorKind::Internal, "histogram " + name + " has other bucket bounds");
    }
    return family;
}

Counter& MetricsRegistry::counter(const std::string& name, const std::string& help,
                                  const Labels& labels) {
    const std::lock_guard lock(mutex_);
    auto& series = family(name, MetricType::Counter, help, {}, labels).counters[labels];
    if (!series) {
        series = std::make_unique<Counter>();
    }
    return *series;
}

Gauge& MetricsRegistry::gauge(const std::string& name, const std::string& help,
                              const Labels& labels) {
    const std::lock_guard lock(mutex_);
    auto& series = family(name, MetricType::Gauge, help, {}, labels).gauges[labels];
    if (!series) {
        series = std::make_unique<Gauge>();
    }
    return *series;
}

Histogram& MetricsRegistry::histogram(const std::string& name, const std::string& help,
                                      std::span<const double> upper_bounds, const Labels& labels) {
    const std::lock_guard lock(mutex_);
    auto& series =
        family(name, MetricType::Histogram, help, upper_bounds, labels).histograms[labels];
    if (!series) {
        series = std::make_unique<Histogram>(upper_bounds);
    }
    return *series;
}

std::string MetricsRegistry::render_prometheus_text() const {
    const std::lock_guard lock(mutex_);
    std::string text;
    for (const auto& [name, family] : families_) {
        text += "# HELP " + name + " " + escape(family.help, false) + "\n";
        text += "# TYPE " + name + " " + type_name(family.type) + "\n";
        for (const auto& [labels, counter] : family.counters) {
            text += name + format_labels(labels) + " " + format_number(counter->value()) + "\n";
        }
        for (const auto& [labels, gauge] : family.gauges) {
            text += name + format_labels(labels) + " " + format_number(gauge->value()) + "\n";
        }
        for (const auto& [labels, histogram] : family.histograms) {
            const Histogram::Snapshot snapshot = histogram->snapshot();
            for (std::size_t i = 0; i < snapshot.cumulative_counts.size(); ++i) {
                const double bound = i < family.upper_bounds.size()
                                         ? family.upper_bounds[i]
                                         : std::numeric_limits<double>::infinity();
                text += name + "_bucket" +
                        format_labels(labels, "le=\"" + format_number(bound) + "\"") + " " +
                        std::to_string(snapshot.cumulative_counts[i]) + "\n";
            }
            text +=
                name + "_sum" + format_labels(labels) + " " + format_number(snapshot.sum) + "\n";
            text += name + "_count" + format_labels(labels) + " " + std::to_string(snapshot.count) +
                    "\n";
        }
    }
    return text;
}

}  // namespace oer::server
