// GET / and GET /web/{file}: the browser client, and GET /v1/openapi.yaml: the API's contract,
// from the files embedded at build time
#include <map>
#include <string>

#include "http_errors.hpp"
#include "http_exchange.hpp"
#include "oer/api/content_id.hpp"
#include "oer/core/error.hpp"
#include "service_context.hpp"
#include "web_files.hpp"

namespace oer::server {

namespace {

// Always revalidated (the files change with the server's version), and cheap to: a 304.
constexpr const char* kWebCacheControl = "no-cache";

struct ServedFile {
    std::string_view text;
    std::string content_type;
    std::string etag;
};

std::string content_type(std::string_view name) {
    const std::map<std::string_view, std::string> types = {
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".yaml", "application/yaml"},  // RFC 9512
    };
    const std::size_t dot = name.rfind('.');
    const auto type = dot == std::string_view::npos ? types.end() : types.find(name.substr(dot));
    if (type == types.end()) {
        throw Error(ErrorKind::Internal,
                    "web file " + std::string(name) + ": no Content-Type for its extension");
    }
    return type->second;
}

// The embedded files by name, each with its Content-Type and a strong ETag (the SHA-256 of its
// text), computed once.
std::map<std::string, ServedFile, std::less<>> served_files(std::span<const WebFile> embedded) {
    std::map<std::string, ServedFile, std::less<>> files;
    for (const WebFile& file : embedded) {
        // Appended rather than "\"" + hex: GCC 12 warns (-Wrestrict) on the inlined operator+.
        std::string etag = "\"";
        etag.append(api::sha256_hex(file.text)).append("\"");
        files.emplace(std::string(file.name),
                      ServedFile{file.text, content_type(file.name), std::move(etag)});
    }
    return files;
}

void answer_file(const ServedFile& file, const httplib::Request& request,
                 httplib::Response& response) {
    response.set_header("Cache-Control", kWebCacheControl);
    response.set_header("ETag", file.etag);
    if (etag_matches(request, file.etag)) {
        response.status = 304;
        return;
    }
    response.status = 200;
    response.set_content(std::string(file.text), file.content_type);
}

}  // namespace

void add_web_routes(Router& router) {
    // Shared by the handlers, which outlive this call.
    auto files = std::make_shared<const std::map<std::string, ServedFile, std::less<>>>(
        served_files(web_files()));
    const auto index = files->find("index.html");
    if (index == files->end()) {
        throw Error(ErrorKind::Internal, "the web files embedded have no index.html");
    }
    // The page's query is its view state (web/README.md), read by the page, not here.
    router.get("/", [files, &page = index->second](const httplib::Request& request,
                                                   httplib::Response& response) {
        answer_file(page, request, response);
    });
    // Only the embedded names: the path never reaches the file system.
    router.get("/web/{file}",
               [files](const httplib::Request& request, httplib::Response& response) {
                   single_query(request, {});
                   const auto file = files->find(request.matches[1].str());
                   if (file == files->end()) {
                       throw not_found(ProblemKind::NotFound,
                                       "no web file is named " + request.matches[1].str());
                   }
                   answer_file(file->second, request, response);
                   // Public code, readable from any origin: a shop's page loads the element's
                   // module (a CORS request) even when --cors-origins does not list it, so that
                   // the element can say in the view why its frames are refused instead of
                   // never appearing. The API's answers stay under --cors-origins.
                   if (!response.has_header("Access-Control-Allow-Origin")) {
                       response.set_header("Access-Control-Allow-Origin", "*");
                   }
               });
    auto spec =
        std::make_shared<const ServedFile>(served_files(api_spec_files()).at("openapi.yaml"));
    router.get("/v1/openapi.yaml",
               [spec](const httplib::Request& request, httplib::Response& response) {
                   single_query(request, {});
                   answer_file(*spec, request, response);
               });
}

}  // namespace oer::server
