#pragma once
// The version of the service and of its published API, reported by the CLI and the server.
namespace oer::api {
inline constexpr const char* kVersion = "0.1.0";
}  // namespace oer::api
