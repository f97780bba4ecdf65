#pragma once
// Each client's fair share of uncached rendering: a token bucket per client (its address, or
// its API key where it gives one), filled with seconds of render work at a steady rate up to a
// burst, and drawn by each uncached render's estimated seconds (render_cost.hpp) before it is
// queued. A client whose bucket cannot pay is answered 429 with Retry-After (when it will have
// earned enough), so that one client flooding uncached frames cannot take the render workers
// from everyone else. Frames from the cache and revalidations are never charged.
//
// The buckets of idle clients are full, and a full bucket is forgotten: what is kept is
// bounded by the clients active within the time it takes to refill a bucket (at most
// kMaxClients; beyond that, the fullest are forgotten first).
#include <chrono>
#include <cstddef>
#include <map>
#include <mutex>
#include <optional>
#include <string>

namespace oer::server {

class ClientWorkBudget {
  public:
    using Clock = std::chrono::steady_clock;
    // rate: seconds of render work a client earns per second; burst: the most it can save up
    // (and the most one render may cost: the service's --max-render-seconds). rate 0: no limit.
    ClientWorkBudget(double rate, double burst);

    // Charges `seconds` of work to client. nullopt when it could pay; else the seconds after
    // which it could (nothing charged).
    std::optional<double> charge(const std::string& client, double seconds,
                                 Clock::time_point now = Clock::now());

    std::size_t clients() const;  // the buckets kept (not full)

    static constexpr std::size_t kMaxClients = 100'000;

  private:
    struct Bucket {
        double tokens = 0.0;
        Clock::time_point updated;
    };
    // The bucket's tokens at now (the rate applied since it was last updated).
    double tokens_at(const Bucket& bucket, Clock::time_point now) const;
    void forget_full(Clock::time_point now);

    const double rate_;
    const double burst_;
    mutable std::mutex mutex_;
    std::map<std::string, Bucket> buckets_;
};

}  // namespace oer::server
