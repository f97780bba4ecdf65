#pragma once
// A well-formed request member or command-line option with an invalid value; carries the
// member's name so the HTTP layer can answer 422 naming it and the CLI can name the flag.
#include <string>

#include "oer/core/error.hpp"
#include "oer/core/one_line.hpp"

namespace oer::api {

class InvalidParameter : public Error {
  public:
    // kind: LimitExceeded for a value past a configured limit (HTTP 413), else InvalidInput.
    // Both are made valid UTF-8 (oer::detail::valid_utf8), as the JSON of a problem body needs:
    // a parameter's name or value can quote any bytes a client sent.
    InvalidParameter(const std::string& parameter, const std::string& detail,
                     ErrorKind kind = ErrorKind::InvalidInput)
        : Error(kind, oer::detail::valid_utf8(parameter) + ": " + oer::detail::valid_utf8(detail)),
          parameter_(oer::detail::valid_utf8(parameter)),
          detail_(oer::detail::valid_utf8(detail)) {}
    const std::string& parameter() const { return parameter_; }
    const std::string& detail() const { return detail_; }

    // The same failure named from an enclosing document whose member `prefix` held the
    // request (a batch job's "frames/3/render"): "frames/3/render/width"; "body", the request
    // itself, becomes the prefix.
    InvalidParameter nested_in(const std::string& prefix) const {
        return InvalidParameter(parameter_ == "body" ? prefix : prefix + "/" + parameter_, detail_,
                                kind());
    }

  private:
    std::string parameter_;
    std::string detail_;
};

}  // namespace oer::api
