#pragma once
// Failures as HTTP answers, mapped in one place: the exceptions of the renderer (oer::Error by
// kind), of the api (MalformedRequest, InvalidParameter), of the render pool (QueueFull,
// RendererUnavailable), of the asset store (StorageFull: 507) and the answers a route decides
// itself (HttpError: 401, 404, 405, 409, 413, 415, 503), each as a problem of one kind
// (problem_json.hpp), which sets its status and type.
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "oer/core/error.hpp"
#include "oer/server/problem_json.hpp"

namespace oer::server {

using HeaderList = std::vector<std::pair<std::string, std::string>>;

// A problem of this kind with this detail, every other member at its default.
Problem problem(ProblemKind kind, std::string detail);

// An answer a route decides: the problem and any headers it needs (Retry-After, Allow,
// WWW-Authenticate).
class HttpError : public std::runtime_error {
  public:
    HttpError(Problem problem, HeaderList headers = {})
        : std::runtime_error(problem.detail),
          problem_(std::move(problem)),
          headers_(std::move(headers)) {}
    const Problem& problem() const { return problem_; }
    const HeaderList& headers() const { return headers_; }

  private:
    Problem problem_;
    HeaderList headers_;
};

// 404 of a kind (UnknownId, MapNotStored, NotFound) naming the member or parameter that held
// the id (empty: the path's, or no id).
HttpError not_found(ProblemKind kind, const std::string& detail, const std::string& parameter = "");
// 503 (Unavailable) with Retry-After.
HttpError unavailable(const std::string& detail, int retry_after_seconds = 1);

// Seconds a client is told to wait after a 503.
inline constexpr int kRetryAfterSeconds = 1;
// Seconds between two attempts to start a renderer that could not start, which a client is
// told to wait after a render refused meanwhile.
inline constexpr int kRendererRetrySeconds = 5;

// The kind of problem an oer::Error of this kind is answered as.
ProblemKind problem_kind_of(ErrorKind kind);

struct ErrorAnswer {
    Problem problem;
    HeaderList headers;
    bool internal = false;  // a 500 or 507: the server's fault, logged with its cause
    std::string cause;      // the exception's own message, for the log
};

// The answer to the exception `error` (which must not be null).
ErrorAnswer error_answer(std::exception_ptr error);

}  // namespace oer::server
