// A rig read back from the store, as server/src/environment_registry.cpp (load_stored) reads it
// after a restart: the stored text parsed within oer::api::stored_rig_bounds at the service's
// default pixel limit (oer::checked_json::parse_bounded), then oer::api::rig_from_json
// (api/include/oer/api/rig_from_json.hpp) on its "rig" and "masks". Text that is not JSON within
// the bounds (JsonParseError), or not an object with both members, is the store's refusal
// before the reader: the rig is dropped and recomputed.
//
// Property ("what the server writes it can read"): a rig the reader accepts is written
// by rig_to_json and light_masks_to_json, and that document reads back to a rig that writes the
// same document again.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "oer/api/rig_from_json.hpp"
#include "oer/api/rig_json.hpp"
#include "oer/core/checked_json.hpp"

namespace {

void read_stored(std::string_view text) {
    nlohmann::json stored;
    try {
        stored = oer::checked_json::parse_bounded(
            text, oer::api::stored_rig_bounds(oer::fuzz::service_image_limits().max_pixels));
    } catch (const oer::checked_json::JsonParseError&) {
        return;  // the store's refusal
    }
    if (!stored.is_object() || !stored.contains("rig") || !stored.contains("masks")) {
        return;  // the store's refusal
    }
    const oer::Rig rig = oer::api::rig_from_json(stored["rig"], stored["masks"]);
    // Accepted: the document holds a content id under "id" (the reader checks it).
    const std::string id = stored["rig"]["id"].get<std::string>();
    const nlohmann::json written = oer::api::rig_to_json(rig, id);
    const nlohmann::json masks = oer::api::light_masks_to_json(rig);
    oer::Rig reread;
    try {
        reread = oer::api::rig_from_json(written, masks);
    } catch (const oer::Error& error) {
        oer::fuzz::finding(std::string("a rig the reader accepted is written as a document it "
                                       "refuses: ") +
                           error.what());
    }
    if (oer::api::rig_to_json(reread, id) != written ||
        oer::api::light_masks_to_json(reread) != masks) {
        oer::fuzz::finding("a rig written, read back and written again changed: " + written.dump());
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    oer::fuzz::parse_or_refuse(
        [&] { read_stored(std::string_view(reinterpret_cast<const char*>(data), size)); });
    return 0;
}
