// oer-server: the HTTP service (README.md, server/README.md). Serves until SIGINT or SIGTERM,
// then stops cleanly: the listener closes, requests in progress finish, the workers stop.
#include <sys/resource.h>

#include <csignal>
#include <iostream>
#include <string>
#include <vector>

#include "oer/api/invalid_parameter.hpp"
#include "oer/core/error.hpp"
#include "oer/server/service.hpp"
#include "oer/server/service_config.hpp"

int main(int argc, char** argv) {
    using namespace oer::server;
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    ServiceCommandLine command_line;
    try {
        command_line = parse_service_command_line(arguments, process_environment);
    } catch (const oer::api::InvalidParameter& error) {
        std::cerr << "oer-server: " << error.what() << "\n(oer-server --help lists the options)\n";
        return 2;
    }
    if (command_line.help) {
        std::cout << service_help_text();
        return 0;
    }
    // Blocked before any thread starts, so every thread inherits the mask and the signals
    // wait for sigwait below instead of interrupting a worker.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
    std::signal(SIGPIPE, SIG_IGN);  // a client that hangs up is an error on its socket only
    // Every connection is a descriptor: the soft limit (often 1024) up to the hard one, as Go
    // and nginx's worker_rlimit_nofile do, so that a crowd of clients is answered, not refused
    // by accept().
    rlimit files{};
    if (::getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < files.rlim_max) {
        files.rlim_cur = files.rlim_max;
        ::setrlimit(RLIMIT_NOFILE, &files);
    }

    try {
        Service service(command_line.config);
        service.start();
        std::cout << service.banner() << std::endl;
        int received = 0;
        sigwait(&stop_signals, &received);
        log_line(std::string("stopping on ") + (received == SIGINT ? "SIGINT" : "SIGTERM"));
        service.stop();
    } catch (const oer::Error& error) {
        std::cerr << "oer-server: " << error.what() << "\n";
        return 1;
    }
    return 0;
}
