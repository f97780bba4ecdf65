#pragma once
// The HTTP service (issue 4): api/openapi.yaml over cpp-httplib, the asset store, caches, the
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
    // (port 0: a free port) and serves from a background thread; returns once the socket
    // listens. Throws oer::Error when a worker or the socket cannot start.
    void start();
    // Stops listening and the workers; idempotent.
    void stop();

    int port() const;         // the bound port, after start()
    std::string url() const;  // "http://host:port"
    // The start-up banner: URL, GL vendor and renderer, data folder, limits; several lines.
    std::string banner() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace oer::server
