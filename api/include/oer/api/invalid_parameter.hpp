#pragma once
// A well-formed request member or command-line option with an invalid value; carries the
// member's name so the HTTP layer can answer 422 naming it and the CLI can name the flag.
#include <string>

#include "oer/error.hpp"

namespace oer::api {

class InvalidParameter : public Error {
  public:
    InvalidParameter(std::string parameter, const std::string& detail)
        : Error(ErrorKind::InvalidInput, parameter + ": " + detail),
          parameter_(std::move(parameter)) {}
    const std::string& parameter() const { return parameter_; }

  private:
    std::string parameter_;
};

}  // namespace oer::api
