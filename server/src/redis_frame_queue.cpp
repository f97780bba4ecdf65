#include "redis_frame_queue.hpp"

#include <hiredis/hiredis.h>

#include <charconv>

#include "oer/core/error.hpp"

namespace oer::server {

namespace {

constexpr const char* kStream = "oer:job-frames";
constexpr const char* kGroup = "oer-renderers";

struct ReplyFree {
    void operator()(redisReply* reply) const { freeReplyObject(reply); }
};
using Reply = std::unique_ptr<redisReply, ReplyFree>;

timeval timeval_of(std::chrono::milliseconds duration) {
    return {time_t(duration.count() / 1000), suseconds_t((duration.count() % 1000) * 1000)};
}

// A stream entry [id, [field, value, ...]] as a task; nullopt for one deleted meanwhile (nil).
std::optional<FrameQueue::Task> task_of(const redisReply* entry) {
    if (entry->type != REDIS_REPLY_ARRAY || entry->elements != 2 ||
        entry->element[1]->type != REDIS_REPLY_ARRAY) {
        return std::nullopt;
    }
    FrameQueue::Task task;
    task.receipt.assign(entry->element[0]->str, entry->element[0]->len);
    const redisReply* fields = entry->element[1];
    for (std::size_t i = 0; i + 1 < fields->elements; i += 2) {
        const std::string name(fields->element[i]->str, fields->element[i]->len);
        std::string value(fields->element[i + 1]->str, fields->element[i + 1]->len);
        (name == "job" ? task.job : task.frame) = std::move(value);
    }
    return task;
}

// Made again after any failure of a take: a Redis restarted without its data has lost the
// group too (NOGROUP), and the next take makes it again.
class GroupCheck {
  public:
    explicit GroupCheck(bool& made) : made_(made) {}
    ~GroupCheck() {
        if (!passed_) {
            made_ = false;
        }
    }
    void passed() { passed_ = true; }

  private:
    bool& made_;
    bool passed_ = false;
};

}  // namespace

// One connection, made again after any failure (the server restarted, the network dropped),
// its commands' errors thrown as oer::Error (Io) naming the server.
class RedisFrameQueue::Connection {
  public:
    Connection(std::string host, int port) : host_(std::move(host)), port_(port) {}
    ~Connection() { reset(); }

    // Runs the command (its arguments as given, binary-safe); a Redis error reply is thrown
    // unless it starts with `tolerated`.
    Reply run(const std::vector<std::string>& arguments, std::chrono::milliseconds timeout,
              std::string_view tolerated = {}) {
        connect(timeout);
        std::vector<const char*> argv;
        std::vector<std::size_t> lengths;
        for (const std::string& argument : arguments) {
            argv.push_back(argument.data());
            lengths.push_back(argument.size());
        }
        Reply reply(static_cast<redisReply*>(
            redisCommandArgv(context_, int(argv.size()), argv.data(), lengths.data())));
        if (!reply) {
            const std::string why = context_->errstr;
            reset();
            throw Error(ErrorKind::Io,
                        "the queue at " + where() + ": " + arguments.front() + " failed: " + why);
        }
        if (reply->type == REDIS_REPLY_ERROR &&
            (tolerated.empty() ||
             !std::string_view(reply->str, reply->len).starts_with(tolerated))) {
            throw Error(ErrorKind::Io, "the queue at " + where() + " refused " + arguments.front() +
                                           ": " + std::string(reply->str, reply->len));
        }
        return reply;
    }

    // Several commands in one round trip (pipelined).
    void run_all(const std::vector<std::vector<std::string>>& commands) {
        connect(std::chrono::seconds(5));
        for (const auto& arguments : commands) {
            std::vector<const char*> argv;
            std::vector<std::size_t> lengths;
            for (const std::string& argument : arguments) {
                argv.push_back(argument.data());
                lengths.push_back(argument.size());
            }
            redisAppendCommandArgv(context_, int(argv.size()), argv.data(), lengths.data());
        }
        for (std::size_t i = 0; i < commands.size(); ++i) {
            void* raw = nullptr;
            if (redisGetReply(context_, &raw) != REDIS_OK) {
                const std::string why = context_->errstr;
                reset();
                throw Error(ErrorKind::Io, "the queue at " + where() + ": " + why);
            }
            const Reply reply(static_cast<redisReply*>(raw));
            if (reply->type == REDIS_REPLY_ERROR) {
                throw Error(ErrorKind::Io, "the queue at " + where() + " refused " +
                                               commands[i].front() + ": " +
                                               std::string(reply->str, reply->len));
            }
        }
    }

    std::string where() const { return host_ + ":" + std::to_string(port_); }

  private:
    // The read timeout covers the longest command: a blocking read's wait, plus a margin.
    void connect(std::chrono::milliseconds timeout) {
        if (!context_) {
            context_ =
                redisConnectWithTimeout(host_.c_str(), port_, timeval_of(std::chrono::seconds(5)));
            if (!context_ || context_->err) {
                const std::string why = context_ ? context_->errstr : "out of memory";
                reset();
                throw Error(ErrorKind::Io, "cannot reach the queue at " + where() + ": " + why);
            }
        }
        redisSetTimeout(context_, timeval_of(timeout + std::chrono::seconds(5)));
    }
    void reset() {
        if (context_) {
            redisFree(context_);
            context_ = nullptr;
        }
    }

    const std::string host_;
    const int port_;
    redisContext* context_ = nullptr;
};

RedisFrameQueue::RedisFrameQueue(const std::string& url, std::string consumer)
    : consumer_(std::move(consumer)) {
    constexpr std::string_view kScheme = "redis://";
    std::string_view rest(url);
    if (!rest.starts_with(kScheme)) {
        throw Error(ErrorKind::InvalidInput, "a queue's url is redis://HOST[:PORT], not " + url);
    }
    rest.remove_prefix(kScheme.size());
    std::string host(rest.substr(0, rest.find(':')));
    int port = 6379;
    if (const auto colon = rest.find(':'); colon != std::string_view::npos) {
        const std::string_view digits = rest.substr(colon + 1);
        const auto [end, error] =
            std::from_chars(digits.data(), digits.data() + digits.size(), port);
        if (error != std::errc() || end != digits.data() + digits.size() || port < 1 ||
            port > 65535) {
            throw Error(ErrorKind::InvalidInput, "a queue's port is 1..65535, in " + url);
        }
    }
    if (host.empty()) {
        throw Error(ErrorKind::InvalidInput, "a queue's url names its host: " + url);
    }
    pusher_ = std::make_unique<Connection>(host, port);
    taker_ = std::make_unique<Connection>(host, port);
    keeper_ = std::make_unique<Connection>(host, port);
    heartbeat_ = std::thread([this] { heartbeat(); });
}

RedisFrameQueue::~RedisFrameQueue() {
    {
        const std::lock_guard lock(current_mutex_);
        stopping_ = true;
    }
    stopping_changed_.notify_all();
    heartbeat_.join();
}

void RedisFrameQueue::push(const std::string& job, const std::vector<std::string>& frames) {
    std::vector<std::vector<std::string>> commands;
    for (const std::string& frame : frames) {
        commands.push_back({"XADD", kStream, "*", "job", job, "frame", frame});
    }
    const std::lock_guard lock(push_mutex_);
    pusher_->run_all(commands);
}

std::optional<FrameQueue::Task> RedisFrameQueue::take(std::chrono::milliseconds wait) {
    const std::string idle =
        std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(kClaimAfter).count());
    if (!group_made_) {
        // From the stream's first entry, so that frames added before any replica made the
        // group are rendered too; a group made already (by another replica) is kept as it is.
        taker_->run({"XGROUP", "CREATE", kStream, kGroup, "0", "MKSTREAM"}, std::chrono::seconds(5),
                    "BUSYGROUP");
        group_made_ = true;
    }
    GroupCheck check(group_made_);
    std::optional<Task> task;
    // [next cursor, [entries], [deleted ids]]
    const Reply claimed =
        taker_->run({"XAUTOCLAIM", kStream, kGroup, consumer_, idle, "0-0", "COUNT", "1"}, wait);
    if (claimed->type == REDIS_REPLY_ARRAY && claimed->elements >= 2 &&
        claimed->element[1]->type == REDIS_REPLY_ARRAY && claimed->element[1]->elements > 0) {
        task = task_of(claimed->element[1]->element[0]);
    }
    if (!task) {
        // [[stream, [entries]]], or nil when none came within the wait.
        const Reply read =
            taker_->run({"XREADGROUP", "GROUP", kGroup, consumer_, "COUNT", "1", "BLOCK",
                         std::to_string(wait.count()), "STREAMS", kStream, ">"},
                        wait);
        if (read->type == REDIS_REPLY_ARRAY && read->elements == 1 &&
            read->element[0]->elements == 2 && read->element[0]->element[1]->elements > 0) {
            task = task_of(read->element[0]->element[1]->element[0]);
        }
    }
    check.passed();
    if (task) {
        const std::lock_guard lock(current_mutex_);
        current_ = task->receipt;
    }
    return task;
}

void RedisFrameQueue::acknowledge(const Task& task) {
    {
        const std::lock_guard lock(current_mutex_);
        current_.clear();
    }
    taker_->run({"XACK", kStream, kGroup, task.receipt}, std::chrono::seconds(5));
    taker_->run({"XDEL", kStream, task.receipt}, std::chrono::seconds(5));
}

void RedisFrameQueue::heartbeat() {
    std::unique_lock lock(current_mutex_);
    while (!stopping_changed_.wait_for(lock, kHeartbeat, [this] { return stopping_; })) {
        const std::string entry = current_;
        if (entry.empty()) {
            continue;
        }
        lock.unlock();
        try {
            keeper_->run({"XCLAIM", kStream, kGroup, consumer_, "0", entry, "JUSTID"},
                         std::chrono::seconds(5));
        } catch (const Error&) {
            // The queue is away: the runner sees it too, and says so.
        }
        lock.lock();
    }
}

}  // namespace oer::server
