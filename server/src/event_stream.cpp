#include "event_stream.hpp"

#include <chrono>
#include <memory>
#include <string_view>

namespace oer::server {

namespace {

// How often an event stream says it is alive when nothing changes (a comment line), so that
// proxies that close idle connections (nginx: proxy_read_timeout, 60 s by default) keep it.
constexpr std::chrono::seconds kEventKeepAlive{15};

}  // namespace

void send_progress_events(httplib::Response& response, ProgressEvents events) {
    response.set_header("Cache-Control", "no-store");
    // Each event as it comes, not held in a proxy's buffer (nginx reads this header).
    response.set_header("X-Accel-Buffering", "no");
    struct Stream {
        ProgressEvents events;
        std::string last;  // the change of the last event sent
        bool sent = false;
        std::chrono::steady_clock::time_point written = std::chrono::steady_clock::now();
    };
    auto stream = std::make_shared<Stream>();
    stream->events = std::move(events);
    response.set_chunked_content_provider(
        "text/event-stream", [stream](std::size_t, httplib::DataSink& sink) {
            const auto status = stream->events.status();
            if (!status) {
                sink.done();
                return true;
            }
            const std::string change = stream->events.change(*status);
            if (!stream->sent || change != stream->last) {
                const std::string event = "event: progress\ndata: " + status->dump() + "\n\n";
                if (!sink.write(event.data(), event.size())) {
                    return false;
                }
                stream->last = change;
                stream->sent = true;
                stream->written = std::chrono::steady_clock::now();
            } else if (std::chrono::steady_clock::now() - stream->written > kEventKeepAlive) {
                static constexpr std::string_view kAlive = ": alive\n\n";
                if (!sink.write(kAlive.data(), kAlive.size())) {
                    return false;
                }
                stream->written = std::chrono::steady_clock::now();
            }
            if (stream->events.settled(*status)) {
                sink.done();
                return true;
            }
            stream->events.wait();
            return sink.is_writable();
        });
}

}  // namespace oer::server
