#include "http_errors.hpp"

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/malformed_request.hpp"
#include "render_pool.hpp"

namespace oer::server {

Problem problem(int status, std::string detail) {
    Problem result;
    result.status = status;
    result.detail = std::move(detail);
    return result;
}

HttpError not_found(const std::string& detail, const std::string& parameter) {
    Problem answer = problem(404, detail);
    if (!parameter.empty()) {
        answer.extensions["parameter"] = parameter;
    }
    return HttpError(std::move(answer));
}

HttpError unavailable(const std::string& detail, int retry_after_seconds) {
    return HttpError(problem(503, detail), {{"Retry-After", std::to_string(retry_after_seconds)}});
}

int status_of(ErrorKind kind) {
    switch (kind) {
        case ErrorKind::InvalidInput:
        case ErrorKind::Unsupported:  // a well-formed upload of a kind we do not handle
            return 422;
        case ErrorKind::LimitExceeded:
            return 413;
        case ErrorKind::Io:
        case ErrorKind::Internal:
            return 500;
    }
    return 500;
}

ErrorAnswer error_answer(std::exception_ptr error) {
    // Internal failures keep their message out of the answer (it may name files of the
    // server); the log has it.
    const auto internal = [](const std::string& cause) {
        return ErrorAnswer{
            problem(500, "internal error; the server log has the details"), {}, true, cause};
    };
    try {
        std::rethrow_exception(error);
    } catch (const HttpError& e) {
        return {e.problem(), e.headers(), false, e.what()};
    } catch (const RendererUnavailable& e) {
        return {problem(503, e.what()),
                {{"Retry-After", std::to_string(kRendererRetrySeconds)}},
                false,
                e.what()};
    } catch (const QueueFull& e) {
        return {problem(503, e.what()),
                {{"Retry-After", std::to_string(kRetryAfterSeconds)}},
                false,
                e.what()};
    } catch (const api::MalformedRequest& e) {
        return {problem(400, e.what()), {}, false, e.what()};
    } catch (const api::InvalidParameter& e) {
        Problem answer = problem(e.kind() == ErrorKind::LimitExceeded ? 413 : 422, e.what());
        answer.extensions["parameter"] = e.parameter();
        return {std::move(answer), {}, false, e.what()};
    } catch (const Error& e) {
        const int status = status_of(e.kind());
        if (status == 500) {
            return internal(e.what());
        }
        return {problem(status, e.what()), {}, false, e.what()};
    } catch (const std::exception& e) {
        return internal(e.what());
    } catch (...) {
        return internal("an exception of unknown type");
    }
}

}  // namespace oer::server
