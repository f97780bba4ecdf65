#pragma once
// What every fuzz target counts as an expected outcome and what as a finding (README.md):
// success and the documented refusals (oer::Error and the API's MalformedRequest and
// InvalidParameter, which derive from it) are expected; an Internal error (a bug: an invariant
// did not hold, oer/core/error.hpp), any other exception, a broken property a target checks,
// and whatever libFuzzer and the sanitizers catch (a crash, a sanitizer report, a timeout, an
// allocation over -malloc_limit_mb or a resident size over -rss_limit_mb) are findings.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <span>
#include <string>
#include <typeinfo>

#include <nlohmann/json.hpp>

#include "oer/core/error.hpp"
#include "oer/image/image_io.hpp"
#include "oer/server/service_config.hpp"
#include "process_memory.hpp"
#include "upload_budget.hpp"

namespace oer::fuzz {

// Prints what broke and aborts: libFuzzer saves the input as crash-<sha1> and stops.
[[noreturn]] inline void finding(const std::string& what) {
    std::fprintf(stderr, "\n==== FINDING: %s\n", what.c_str());
    std::abort();
}

// Text that the service puts in JSON (a problem body's detail, a mesh's warnings) must be
// UTF-8: nlohmann's writer throws on anything else, which the service answers with a 500.
inline void require_utf8(const std::string& text, const std::string& what) {
    try {
        (void)nlohmann::json(text).dump();
    } catch (const nlohmann::json::type_error& error) {
        finding(what + " is not UTF-8 (" + error.what() + "): " +
                nlohmann::json(text).dump(-1, ' ', true, nlohmann::json::error_handler_t::replace));
    }
}

// Runs body, the parsing of one input; its documented refusals are expected outcomes, and their
// messages, which the service answers with, must be UTF-8.
template <typename Body>
void parse_or_refuse(Body&& body) {
    try {
        body();
    } catch (const Error& error) {
        if (error.kind() == ErrorKind::Internal) {
            finding(std::string("an internal error (a broken invariant): ") + error.what());
        }
        require_utf8(error.what(), "a refusal's message");
    } catch (const std::exception& error) {
        finding(std::string("an undocumented exception, ") + typeid(error).name() + ": " +
                error.what());
    }
}

inline std::span<const std::byte> as_bytes(const std::uint8_t* data, std::size_t size) {
    return std::as_bytes(std::span(data, size));
}

// The limits the service reads maps with at its default configuration (server/src/service.cpp).
inline ImageLimits service_image_limits() {
    return ImageLimits{server::ServiceConfig{}.max_image_pixels, 32768};
}

// What the service lets one upload of `upload_bytes` bytes cost to decode
// (server/src/upload_budget.hpp, at the default expansion, ServiceConfig::max_upload_expansion):
// max(64 MiB, 200 x its size), the bound on the memory one upload may make the server hold.
inline std::uint64_t upload_expansion_bound(std::size_t upload_bytes) {
    return std::max<std::uint64_t>(server::kExpansionFloor,
                                   server::ServiceConfig{}.max_upload_expansion * upload_bytes);
}

// The growth of the resident set while it lives, its peak (VmHWM) over its level when made, KiB:
// the tests' measure of what an upload costs. Pages allocated and never touched do not count
// (OpenImageIO's read_scanlines allocates a 64 MiB conversion buffer for any image and touches
// a few rows of it). Without a writable /proc/self/clear_refs it measures nothing (zero).
class ResidentGrowth {
  public:
    ResidentGrowth() : measured_(testing::reset_peak_resident()), base_(testing::resident_kib()) {}

    std::uint64_t bytes() const {
        if (!measured_) {
            return 0;
        }
        const long growth = testing::peak_resident_kib() - base_;
        return growth > 0 ? std::uint64_t(growth) * 1024 : 0;
    }

  private:
    bool measured_;
    long base_;
};

}  // namespace oer::fuzz
