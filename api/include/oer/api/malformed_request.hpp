#pragma once
// A request body that cannot be read at all (not JSON, a number JSON cannot hold, nesting far
// beyond any valid request): HTTP 400, where a well-formed body with a bad member is an
// InvalidParameter (422). The message says where the reading stopped when the parser knows.
#include <string>

#include "oer/core/error.hpp"
#include "oer/core/one_line.hpp"

namespace oer::api {

class MalformedRequest : public Error {
  public:
    // The detail is made valid UTF-8 (oer::detail::valid_utf8): the JSON parser's message quotes
    // the bytes where it stopped, which a problem body could not hold otherwise.
    explicit MalformedRequest(const std::string& detail)
        : Error(ErrorKind::InvalidInput,
                "malformed request body: " + oer::detail::valid_utf8(detail)) {}
};

}  // namespace oer::api
