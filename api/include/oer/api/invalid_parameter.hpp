#pragma once
// A well-formed request member or command-line option with an invalid value; carries the
// member's name so the HTTP layer can answer 422 naming it and the CLI can name the flag.
#include <string>

#include "oer/core/error.hpp"

namespace oer::api {

class InvalidParameter : public Error {
  public:
    // kind: LimitExceeded for a value past a configured limit (HTTP 413), else InvalidInput.
    InvalidParameter(std::string parameter, const std::string& detail,
                     ErrorKind kind = ErrorKind::InvalidInput)
        : Error(kind, parameter + ": " + detail), parameter_(std::move(parameter)) {}
    const std::string& parameter() const { return parameter_; }

  private:
    std::string parameter_;
};

}  // namespace oer::api
