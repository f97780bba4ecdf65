#include "stored_asset_routes.hpp"

#include "oer/api/content_id.hpp"
#include "oer/api/parameter_text.hpp"

namespace oer::server {

HttpError unknown_asset(const StoredAssetKind& kind, const std::string& id) {
    return not_found(ProblemKind::UnknownId,
                     "no " + kind.singular + " with id '" + api::excerpt(id) + "'");
}

void send_asset_listing(httplib::Response& response, const StoredAssetKind& kind,
                        const ListedPage& page, std::size_t limit, const ListedMembers& members) {
    nlohmann::json entries = nlohmann::json::array();
    for (const ListedAsset& entry : page.entries) {
        nlohmann::json listed = members(entry);
        listed["id"] = entry.id;
        listed["url"] = kind.collection + "/" + entry.id;
        listed["created"] = rfc3339(entry.stored);
        entries.push_back(std::move(listed));
    }
    send_listing(response, kind.collection, kind.plural, std::move(entries), page.next_after,
                 limit);
}

void refuse_preset_removal(const StoredAssetKind& kind, const std::string& id) {
    if (id == api::kDefaultPresetId) {
        throw HttpError(problem(ProblemKind::PresetNotDeletable,
                                "'" + id + "' is " + kind.preset +
                                    ": it is part of the server, not of its store, and cannot "
                                    "be deleted"));
    }
}

}  // namespace oer::server
