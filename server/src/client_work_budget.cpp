#include "client_work_budget.hpp"

#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

namespace oer::server {

ClientWorkBudget::ClientWorkBudget(double rate, double burst) : rate_(rate), burst_(burst) {}

double ClientWorkBudget::tokens_at(const Bucket& bucket, Clock::time_point now) const {
    const double elapsed = std::chrono::duration<double>(now - bucket.updated).count();
    return std::min(burst_, bucket.tokens + rate_ * std::max(0.0, elapsed));
}

std::optional<double> ClientWorkBudget::wait_before_work(const std::string& client,
                                                         Clock::time_point now) {
    if (rate_ <= 0.0) {
        return std::nullopt;
    }
    const std::lock_guard lock(mutex_);
    const auto found = buckets_.find(client);
    if (found == buckets_.end()) {
        return std::nullopt;
    }
    const double tokens = tokens_at(found->second, now);
    if (tokens > 0.0) {
        return std::nullopt;
    }
    return -tokens / rate_;
}

void ClientWorkBudget::charge(const std::string& client, double seconds, Clock::time_point now) {
    if (rate_ <= 0.0) {
        return;
    }
    const std::lock_guard lock(mutex_);
    const auto found = buckets_.find(client);
    const double tokens = found == buckets_.end() ? burst_ : tokens_at(found->second, now);
    if (found == buckets_.end() && buckets_.size() >= kMaxClients) {
        forget_full(now);
    }
    buckets_[client] = Bucket{std::max(-burst_, tokens - seconds), now};
}

void ClientWorkBudget::forget_full(Clock::time_point now) {
    std::erase_if(buckets_,
                  [&](const auto& entry) { return tokens_at(entry.second, now) >= burst_; });
    if (buckets_.size() < kMaxClients) {
        return;
    }
    // Every client kept is in debt: the tenth least in debt is forgotten (refilled).
    std::vector<std::pair<double, std::string>> by_tokens;
    by_tokens.reserve(buckets_.size());
    for (const auto& [client, bucket] : buckets_) {
        by_tokens.emplace_back(tokens_at(bucket, now), client);
    }
    const auto tenth = by_tokens.begin() + std::ptrdiff_t(by_tokens.size() / 10);
    std::nth_element(by_tokens.begin(), tenth, by_tokens.end(), std::greater<>());
    for (auto it = by_tokens.begin(); it != tenth; ++it) {
        buckets_.erase(it->second);
    }
}

std::size_t ClientWorkBudget::clients() const {
    const std::lock_guard lock(mutex_);
    return buckets_.size();
}

}  // namespace oer::server
