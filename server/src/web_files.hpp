#pragma once
// The browser client's files (web/), embedded in the binary at build time: the build runs
// cmake/embed_files.cmake, which writes web_files.cpp with one raw string per file listed in
// server/CMakeLists.txt, so that oer-server serves the page at / with no configuration.
#include <span>
#include <string_view>

namespace oer::server {

struct WebFile {
    std::string_view name;  // as in web/: "index.html", "oer-viewer.js"
    std::string_view text;
};

// Every embedded file, in the order server/CMakeLists.txt lists them.
std::span<const WebFile> web_files();

// api/openapi.yaml, embedded the same way and served at /v1/openapi.yaml.
std::span<const WebFile> api_spec_files();

}  // namespace oer::server
