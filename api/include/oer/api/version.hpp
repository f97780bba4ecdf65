#pragma once
// The version of the service and its published API, reported by the CLI and the server.
namespace oer::api {
inline constexpr const char* kVersion = "0.1.0";
const char* version();
}  // namespace oer::api
