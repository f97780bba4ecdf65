#pragma once
// The one error type of the renderer library: a message with context and a kind, so that
// callers (the CLI, the HTTP API) can map it to an exit status or an HTTP status.
#include <stdexcept>
#include <string>

namespace oer {

enum class ErrorKind {
    InvalidInput,   // malformed, truncated or semantically invalid input
    LimitExceeded,  // input larger than a configured limit
    Unsupported,    // well-formed input of a kind we do not handle
    Io,             // the file system or a device failed
    Internal,       // a bug: an invariant did not hold
    Cancelled,      // stopped on request: its deadline passed, or nobody waits for it
};

class Error : public std::runtime_error {
  public:
    Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
    ErrorKind kind() const { return kind_; }

  private:
    ErrorKind kind_;
};

}  // namespace oer
