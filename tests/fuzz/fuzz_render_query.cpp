// The query of GET /v1/render: the query string split and percent-decoded by the server's HTTP
// library (cpp-httplib's parse_query_text, as it fills Request::params), then
// oer::api::parse_render_query (api/include/oer/api/render_request.hpp) at the service's
// default limits, and what the service does with an accepted request (render_spec_checks.hpp).
// An input is the query string alone, what follows the '?'.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

#include <httplib.h>

#include "render_spec_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::multimap<std::string, std::string> query;
    httplib::detail::parse_query_text(text, query);
    const oer::api::RenderLimits limits = oer::fuzz::service_render_limits();
    oer::fuzz::parse_or_refuse([&] {
        oer::fuzz::check_accepted_or_refused(
            [&] { return oer::api::parse_render_query(query, limits); }, limits);
    });
    return 0;
}
