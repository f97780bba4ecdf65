// The body of POST /v1/render: oer::api::parse_render_json
// (api/include/oer/api/render_request.hpp, reading through oer/core/checked_json.hpp) at the
// service's default limits, then what the service does with an accepted request
// (render_spec_checks.hpp: its ETag, the canonical document parsed back, the frame request).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "render_spec_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view body(reinterpret_cast<const char*>(data), size);
    const oer::api::RenderLimits limits = oer::fuzz::service_render_limits();
    oer::fuzz::parse_or_refuse([&] {
        oer::fuzz::check_accepted_or_refused(
            [&] { return oer::api::parse_render_json(body, limits); }, limits);
    });
    return 0;
}
