#pragma once
// A request body that cannot be read at all (not JSON, a number JSON cannot hold, nesting far
// beyond any valid request): HTTP 400, where a well-formed body with a bad member is an
// InvalidParameter (422). The message says where the reading stopped when the parser knows.
#include <string>

#include "oer/core/error.hpp"

namespace oer::api {

class MalformedRequest : public Error {
  public:
    explicit MalformedRequest(const std::string& detail)
        : Error(ErrorKind::InvalidInput, "malformed request body: " + detail) {}
};

}  // namespace oer::api
