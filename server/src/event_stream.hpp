#pragma once
// Server-sent events of one resource's progress (GET /v1/jobs/{id}/events,
// GET /v1/meshes/{id}/preparation/events): one `progress` event each time its status changes,
// its data the status's JSON, and the end of the stream after a settled status's event. The
// stream holds an HTTP thread while it lasts, as every connection does (bounded_http_server.hpp:
// at most --max-connections-per-client of them per client address).
#include <functional>
#include <optional>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

namespace oer::server {

struct ProgressEvents {
    // The resource's status now; nullopt once it is gone (deleted meanwhile): the stream ends.
    std::function<std::optional<nlohmann::json>()> status;
    // What of a status must differ from the last event's for another event: the whole status
    // (its dump) unless some of it changes at every look (a fraction, an estimate of the time
    // left), which would make an event of every look.
    std::function<std::string(const nlohmann::json&)> change;
    // Whether the status is final: the stream ends after its event.
    std::function<bool(const nlohmann::json&)> settled;
    // Returns once the status may have changed, or after a short while; called between looks.
    std::function<void()> wait;
};

// Answers with the stream (text/event-stream, never stored, never buffered by a proxy), a
// comment line every kEventKeepAlive while no event is sent; it stops once the client has gone
// (a write fails or the socket is no longer writable). The caller answers 404 before, for a
// resource that is not there.
void send_progress_events(httplib::Response& response, ProgressEvents events);

}  // namespace oer::server
