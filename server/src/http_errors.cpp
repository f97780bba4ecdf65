#include "http_errors.hpp"

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/malformed_request.hpp"
#include "oer/server/asset_store.hpp"
#include "render_pool.hpp"

namespace oer::server {

Problem problem(ProblemKind kind, std::string detail) {
    Problem result;
    result.kind = kind;
    result.detail = std::move(detail);
    return result;
}

HttpError not_found(ProblemKind kind, const std::string& detail, const std::string& parameter) {
    Problem answer = problem(kind, detail);
    if (!parameter.empty()) {
        answer.extensions["parameter"] = parameter;
    }
    return HttpError(std::move(answer));
}

HttpError unavailable(const std::string& detail, int retry_after_seconds) {
    return HttpError(problem(ProblemKind::Unavailable, detail),
                     {{"Retry-After", std::to_string(retry_after_seconds)}});
}

ProblemKind problem_kind_of(ErrorKind kind) {
    switch (kind) {
        case ErrorKind::InvalidInput:
        case ErrorKind::Unsupported:  // a well-formed upload of a kind we do not handle
            return ProblemKind::InvalidContent;
        case ErrorKind::LimitExceeded:
            return ProblemKind::LimitExceeded;
        case ErrorKind::Cancelled:  // work stopped at its deadline: try again
            return ProblemKind::Unavailable;
        case ErrorKind::Io:
        case ErrorKind::Internal:
            return ProblemKind::Internal;
    }
    return ProblemKind::Internal;
}

ErrorAnswer error_answer(std::exception_ptr error) {
    // Internal failures keep their message out of the answer (it may name files of the
    // server); the log has it.
    const auto internal = [](const std::string& cause) {
        return ErrorAnswer{
            problem(ProblemKind::Internal, "internal error; the server log has the details"),
            {},
            true,
            cause};
    };
    try {
        std::rethrow_exception(error);
    } catch (const HttpError& e) {
        return {e.problem(), e.headers(), false, e.what()};
    } catch (const RendererUnavailable& e) {
        return {problem(ProblemKind::Unavailable, e.what()),
                {{"Retry-After", std::to_string(kRendererRetrySeconds)}},
                false,
                e.what()};
    } catch (const QueueFull& e) {
        return {problem(ProblemKind::Unavailable, e.what()),
                {{"Retry-After", std::to_string(kRetryAfterSeconds)}},
                false,
                e.what()};
    } catch (const StorageFull& e) {
        // RFC 4918 section 11.5: the server cannot store what the request needs stored. The
        // detail says what and why, never where (the log has the path).
        return {problem(ProblemKind::InsufficientStorage,
                        e.entry() + " could not be stored: " + e.reason() +
                            "; the server's storage is full, so nothing of this request "
                            "was kept; send it again once space is freed"),
                {},
                true,
                e.what()};
    } catch (const api::MalformedRequest& e) {
        return {problem(ProblemKind::MalformedRequest, e.what()), {}, false, e.what()};
    } catch (const api::InvalidParameter& e) {
        Problem answer =
            problem(e.kind() == ErrorKind::LimitExceeded ? ProblemKind::LimitExceeded
                                                         : ProblemKind::InvalidParameter,
                    e.what());
        answer.extensions["parameter"] = e.parameter();
        return {std::move(answer), {}, false, e.what()};
    } catch (const Error& e) {
        const ProblemKind kind = problem_kind_of(e.kind());
        if (kind == ProblemKind::Internal) {
            return internal(e.what());
        }
        if (kind == ProblemKind::Unavailable) {
            return {problem(kind, e.what()),
                    {{"Retry-After", std::to_string(kRetryAfterSeconds)}},
                    false,
                    e.what()};
        }
        return {problem(kind, e.what()), {}, false, e.what()};
    } catch (const std::exception& e) {
        return internal(e.what());
    } catch (...) {
        return internal("an exception of unknown type");
    }
}

}  // namespace oer::server
