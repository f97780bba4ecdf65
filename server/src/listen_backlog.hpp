#pragma once
// cpp-httplib 0.11.4 (Debian's compiled library) listens with a backlog of 5 and gives no
// access to its socket: under load a sixth simultaneous connection loses its SYN and the
// client retries a second later, so an over-capacity request is answered 503 only after 1 s.

namespace oer::server {

// Finds this process's listening TCP socket bound to port and raises its backlog to SOMAXCONN
// (Linux takes a second listen() on a listening socket as a new backlog). Returns whether it
// was found.
bool widen_listen_backlog(int port);

}  // namespace oer::server
