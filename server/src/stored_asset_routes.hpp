#pragma once
// The routes every kind of stored asset (environments, meshes) shares: GET <collection> (a
// page of the listing), GET <collection>/{id} (the asset's JSON) and DELETE <collection>/{id}
// (the API key's when the service has one). Each is added on its own, so that a kind keeps its
// routes in the order it registers them (the order Allow lists their methods in).
#include <functional>
#include <memory>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "asset_registry.hpp"
#include "http_errors.hpp"
#include "http_exchange.hpp"
#include "oer/api/content_id.hpp"
#include "router.hpp"

namespace oer::server {

// What the answers of a kind's routes call it.
struct StoredAssetKind {
    std::string collection;  // "/v1/meshes": the listing's path, and its assets' prefix
    std::string plural;      // "meshes": the listing's member
    std::string singular;    // "mesh": as an answer names one
    std::string preset;      // what the built-in preset is: "the built-in product"
};

// A listing's entry beyond its id, url and created: the kind's own members.
using ListedMembers = std::function<nlohmann::json(const ListedAsset&)>;
// Run once an asset is removed from the store, with its id (what else held it: a preview).
using AfterRemoval = std::function<void(const std::string& id)>;

// 404 naming the kind and the id no asset has.
HttpError unknown_asset(const StoredAssetKind& kind, const std::string& id);

// The asset the request's {id} names (404 unless one has it), from registry.find.
template <typename Registry>
auto requested_asset(Registry& registry, const StoredAssetKind& kind,
                     const httplib::Request& request) {
    const std::string& id = request.matches[1];
    auto asset = registry.find(id);
    if (!asset) {
        throw unknown_asset(kind, id);
    }
    return asset;
}

// The listing's answer to request, one entry per asset of the page.
void send_asset_listing(httplib::Response& response, const StoredAssetKind& kind,
                        const ListedPage& page, std::size_t limit, const ListedMembers& members);

// Throws 409 when id is the built-in preset's, which is the server's and not its store's.
void refuse_preset_removal(const StoredAssetKind& kind, const std::string& id);

template <typename Registry>
void add_asset_listing_route(Router& router, Registry& registry, StoredAssetKind kind,
                             ListedMembers members) {
    const std::string route = kind.collection;
    router.get(route, [&registry, kind = std::move(kind), members = std::move(members)](
                          const httplib::Request& request, httplib::Response& response) {
        const ListingQuery query =
            listing_query(request, {api::is_content_id, "64 lowercase hexadecimal digits"});
        send_asset_listing(response, kind, registry.list(query.after, query.limit), query.limit,
                           members);
    });
}

template <typename Registry>
void add_asset_reading_route(Router& router, Registry& registry, StoredAssetKind kind) {
    const std::string route = kind.collection + "/{id}";
    router.get(route, [&registry, kind = std::move(kind)](const httplib::Request& request,
                                                          httplib::Response& response) {
        single_query(request, {});
        send_json(response, 200, requested_asset(registry, kind, request)->json);
    });
}

template <typename Registry>
void add_asset_removal_route(Router& router, Registry& registry, StoredAssetKind kind,
                             AfterRemoval after_removal = {}) {
    const std::string route = kind.collection + "/{id}";
    router.del(
        route,
        [&registry, kind = std::move(kind), after_removal = std::move(after_removal)](
            const httplib::Request& request, httplib::Response& response) {
            single_query(request, {});
            const std::string& id = request.matches[1];
            refuse_preset_removal(kind, id);
            if (!registry.remove(id)) {
                throw unknown_asset(kind, id);
            }
            if (after_removal) {
                after_removal(id);
            }
            response.status = 204;
        },
        RoutePolicy{.needs_api_key = true});
}

}  // namespace oer::server
