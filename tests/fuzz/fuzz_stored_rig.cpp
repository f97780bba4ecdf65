// A rig read back from the store: oer::api::rig_from_json
// (api/include/oer/api/rig_from_json.hpp) on the stored document {"rig": ..., "masks": ...}, as
// server/src/environment_registry.cpp (load_stored) reads it after a restart. Text that is not a
// JSON object with both members is the store's refusal, before the reader.
//
// Property (issue 14, "what the server writes it can read"): a rig the reader accepts is written
// by rig_to_json and light_masks_to_json, and that document reads back to a rig that writes the
// same document again.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "oer/api/rig_from_json.hpp"
#include "oer/api/rig_json.hpp"

namespace {

void read_stored(std::string_view text) {
    const nlohmann::json stored = nlohmann::json::parse(text, nullptr, false);
    if (stored.is_discarded() || !stored.is_object() || !stored.contains("rig") ||
        !stored.contains("masks")) {
        return;  // the store's own refusal: the rig is dropped and recomputed
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
