#pragma once
// Batch jobs' frames shared out between replicas through a Redis stream with a consumer group
// (Redis Streams: XADD, XREADGROUP, XACK, XAUTOCLAIM), through hiredis, the C client Redis
// itself ships (Debian's libhiredis): one entry per frame (its job's id and its name), added by
// the replica that took the job; every replica reads new entries as a consumer of one group, so
// each entry goes to one replica, and stays pending under it until it acknowledges it (XACK,
// then XDEL: the stream holds the frames still to render). A replica killed mid-frame leaves
// its entry pending: once it has been idle kClaimAfter, another replica claims it (XAUTOCLAIM)
// and renders the frame, unless it finds it stored already (job_service.hpp). A live replica
// keeps its entry from being claimed while it renders, however long the frame takes, by
// claiming it again for itself every kHeartbeat (XCLAIM resets the entry's idle time), from a
// thread and a connection of its own.
//
// The queue is the only thing replicas share besides the data folder: the job's specification,
// frames, failures and cancellation are files there (job_store.hpp).
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "job_service.hpp"

struct redisContext;

namespace oer::server {

class RedisFrameQueue : public FrameQueue {
  public:
    static constexpr std::chrono::seconds kHeartbeat{1};
    static constexpr std::chrono::seconds kClaimAfter{5};

    // url: redis://HOST[:PORT] (6379 by default); throws oer::Error (InvalidInput) for a bad
    // one. Connects at the first command, and again after any failure, so that a replica starts
    // while its queue does not answer yet (a pod before the queue's) and carries on once it
    // does; meanwhile each command throws oer::Error (Io) naming the server.
    // consumer: this replica's name in the group, unique among the replicas.
    RedisFrameQueue(const std::string& url, std::string consumer);
    ~RedisFrameQueue() override;

    void push(const std::string& job, const std::vector<std::string>& frames) override;
    // A pending entry idle past kClaimAfter first (a dead replica's), else a new one.
    std::optional<Task> take(std::chrono::milliseconds wait) override;
    void acknowledge(const Task& task) override;
    bool durable() const override { return true; }

  private:
    class Connection;
    void heartbeat();

    const std::string consumer_;
    std::unique_ptr<Connection> pusher_;  // HTTP threads' pushes, under push_mutex_
    std::unique_ptr<Connection> taker_;   // the runner's takes and acknowledgements
    std::unique_ptr<Connection> keeper_;  // the heartbeat's claims
    bool group_made_ = false;             // by take(), on the runner's thread only
    std::mutex push_mutex_;
    std::mutex current_mutex_;
    std::condition_variable stopping_changed_;
    bool stopping_ = false;  // guarded by current_mutex_
    std::string current_;    // the entry being rendered ("" for none), under current_mutex_
    std::thread heartbeat_;
};

}  // namespace oer::server
