#pragma once
// Each client's fair share of uncached rendering: a token bucket per client (its address),
// filled with seconds of render work at a steady rate up to a burst, and drawn by the work each
// uncached frame took (its render, and the transfer bake or specular cube it needed). A client
// whose bucket is empty (in debt after a costly frame) is answered 429 with Retry-After (when
// it will have earned its way out) before anything of its next frame runs, so that one client
// asking for frame after frame cannot take the render workers from everyone else. Frames from
// the cache and revalidations are never charged. The work is measured, not estimated: a frame
// whose transfer is already baked costs its render alone.
//
// A refusal is held before it is sent (FrameService: up to kRefusalHold, or until the client
// would have earned its way out, or leaves): a client that ignores Retry-After and asks again
// at once would otherwise make thousands of refusals a second, and those took the CPU from the
// renders of every other client (measured by tests/integration/render_budget_test.cpp: another
// address's uncached frames went from 30 ms to 75 ms at 4,800 refusals a second). Held, each of
// its connections (at most --max-connections-per-client) asks about once a second and sleeps
// meanwhile; a client that waits as told is never held. This is a tarpit, as mail servers hold
// a sender over its rate.
//
// The buckets of idle clients refill, and a full bucket is forgotten: what is kept is bounded
// by the clients active within the time it takes to refill one (at most kMaxClients; beyond,
// the least in debt are forgotten first).
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
    // rate: seconds of render work a client earns per second; burst: the most it can save up,
    // and the most debt it can run into. rate 0: no limit.
    ClientWorkBudget(double rate, double burst);

    // Whether client may start uncached work now: nullopt when its bucket is not empty, else
    // the seconds after which it will be.
    std::optional<double> wait_before_work(const std::string& client,
                                           Clock::time_point now = Clock::now());
    // Draws `seconds` of work done for client from its bucket (into debt, down to -burst).
    void charge(const std::string& client, double seconds, Clock::time_point now = Clock::now());

    std::size_t clients() const;  // the buckets kept (not full)

    static constexpr std::size_t kMaxClients = 100'000;
    // The longest a refusal is held before it is sent.
    static constexpr std::chrono::milliseconds kRefusalHold{1000};

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
