#pragma once
// The HTTP service: api/openapi.yaml over cpp-httplib, the asset store, caches, the
// render workers and metrics. One object owns all of it, so that tests run a real server on a
// loopback port in-process, stop it and start another on the same data folder.
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "oer/server/log_line.hpp"
#include "oer/server/service_config.hpp"

namespace oer::server {

class Service {
  public:
    // Opens (creates) the data folder; nothing listens yet. Throws oer::Error (Io) when the
    // folder cannot be used.
    explicit Service(ServiceConfig config, std::function<void(std::string_view)> log = log_line);
    ~Service();  // stop()
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // Starts the render workers (a GL context each, a test frame rendered), binds host:port
    // (port 0: a free port) and the admin port if configured, and serves from background
    // threads; returns once the sockets listen. Throws oer::Error when a socket cannot listen.
    // A renderer that cannot start does not stop the service: it logs why, answers renders
    // 503 and /readyz false, and tries again every few seconds.
    void start();
    // Stops listening and the workers; idempotent.
    void stop();

    int port() const;         // the bound port, after start()
    int admin_port() const;   // the admin listener's bound port; -1 when there is none
    std::string url() const;  // "http://host:port"
    // The start-up banner: URL, GL vendor and renderer, data folder, limits; several lines.
    std::string banner() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace oer::server
