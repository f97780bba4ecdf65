#pragma once
// The render request parsers' verdicts, for tests that check which parameter a request is
// rejected for: the parameter's name, or "" when the request is accepted.
#include <map>
#include <string>

#include "oer/api/invalid_parameter.hpp"
#include "oer/api/render_request.hpp"

namespace oer::testing {

// The member a JSON body is rejected for.
inline std::string rejected_member(const std::string& body) {
    try {
        api::parse_render_json(body);
    } catch (const api::InvalidParameter& error) {
        return error.parameter();
    }
    return "";
}

// The GET parameter a query is rejected for.
inline std::string rejected_parameter(const std::multimap<std::string, std::string>& query) {
    try {
        api::parse_render_query(query);
    } catch (const api::InvalidParameter& error) {
        return error.parameter();
    }
    return "";
}

}  // namespace oer::testing
