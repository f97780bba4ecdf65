#include "environment_registry.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <span>

#include "oer/api/content_id.hpp"
#include "oer/api/rig_from_json.hpp"
#include "oer/api/rig_json.hpp"
#include "oer/api/rig_options.hpp"
#include "oer/core/checked_json.hpp"
#include "oer/core/error.hpp"
#include "oer/lighting/default_environment.hpp"

namespace oer::server {

namespace {

std::size_t charge_of(const Environment& environment) {
    std::size_t pixels = 0;
    for (const Light& light : environment.rig->lights) {
        pixels += light.pixels.size();
    }
    return environment.json.dump().size() + pixels * sizeof(std::uint32_t);
}

// Memory that preprocessing a decoded map holds beside it, per pixel: measured 9 (a 4096x2048
// half-float EXR: +171 MiB peak resident beyond its 40 MiB body, 21 bytes a pixel, of which the
// decoded map is 12): the luminance, masks and blurred copies of light detection, and the rig.
constexpr std::uint64_t kPreprocessBytesPerPixel = 12;

std::size_t charge_of(const HdrImage& image) {
    return image.pixels.size() * sizeof(float);
}

// A rig's record of provenance (DerivedKind::RigSource): the content id of its map and the
// options it was made with.
struct Provenance {
    std::string source_id;
    nlohmann::json options;
};

std::string provenance_json(const std::string& source_id, const RigOptions& options) {
    return nlohmann::json{{"source", source_id}, {"options", api::rig_options_to_json(options)}}
        .dump();
}

// nullopt when the record is not one provenance_json wrote.
std::optional<Provenance> read_provenance(const std::string& text) {
    // The record of where a rig came from: its source's id and the options (a few dozen
    // values).
    constexpr checked_json::JsonBounds kProvenanceBounds{1024, 8};
    nlohmann::json record;
    try {
        record = checked_json::parse_bounded(text, kProvenanceBounds);
    } catch (const checked_json::JsonParseError&) {
        return std::nullopt;
    }
    if (!record.is_object() || !record.contains("source") || !record["source"].is_string() ||
        !record.contains("options")) {
        return std::nullopt;
    }
    return Provenance{record["source"].get<std::string>(), record["options"]};
}

// Rig ids are read from the store this many at a time when every record must be read.
constexpr std::size_t kRecordBatch = 256;

}  // namespace

EnvironmentRegistry::EnvironmentRegistry(AssetStore& store, ServiceMetrics& metrics,
                                         UploadBudget& budget, Log log, const ImageLimits& limits,
                                         std::size_t cache_bytes)
    : store_(store),
      metrics_(metrics),
      budget_(budget),
      log_(std::move(log)),
      limits_(limits),
      // The decoded maps are the large objects (12 bytes a pixel); rigs are small.
      rigs_(metrics, CacheName::Rig, cache_bytes / 8),
      images_(cache_bytes),
      // At the default options 3.1 MB the residual's cube and 0.8 MB each light's.
      specular_(metrics, CacheName::Specular, cache_bytes / 8) {
    auto image = std::make_shared<const HdrImage>(make_default_environment());
    auto rig = std::make_shared<const Rig>(build_rig(*image, {}, RigOptions{}));
    const std::string id(api::kDefaultPresetId);
    rigs_.set_preset(
        std::make_shared<const Environment>(Environment{id, rig, api::rig_to_json(*rig, id), ""}));
    preset_image_ = std::move(image);
}

EnvironmentRegistry::Upload EnvironmentRegistry::upload(std::string_view bytes,
                                                        const std::string& extension,
                                                        const RigOptions& options,
                                                        const std::string& file_name) {
    const std::string source_id = api::sha256_hex(bytes);
    const std::string rig_id = api::rig_id(source_id, options);
    return rigs_.upload(
        rig_id,
        [&] {
            auto known = find(rig_id);
            if (known) {
                // The map again if it was lost, unless the rig was removed since find().
                rigs_.guarded([&] {
                    if (store_.contains(DerivedKind::RigSource, rig_id) &&
                        !store_.contains(SourceKind::Environment, source_id)) {
                        store_.put_source(SourceKind::Environment, bytes, extension);
                    }
                });
            }
            return known;
        },
        [&] { return preprocess(bytes, extension, options, source_id, rig_id, file_name); });
}

std::shared_ptr<const Environment> EnvironmentRegistry::preprocess(
    std::string_view bytes, const std::string& extension, const RigOptions& options,
    const std::string& source_id, const std::string& rig_id, const std::string& name) {
    // Decoded before it is stored, so that bytes that are not a map never enter the store; its
    // memory reserved first, from its header.
    const ImageHeader header = probe_image_memory(as_bytes(bytes), name, limits_);
    const auto lease = budget_.acquire(
        header.decode_bytes +
            kPreprocessBytesPerPixel * std::uint64_t(header.width) * std::uint64_t(header.height),
        bytes.size(),
        "a " + std::to_string(header.width) + "x" + std::to_string(header.height) + " map");
    const InProgress in_progress(metrics_.rigs_in_progress);
    const auto start = std::chrono::steady_clock::now();
    LoadedImage loaded = load_image_memory(as_bytes(bytes), name, limits_);
    store_.put_source(SourceKind::Environment, bytes, extension);
    // A 201 promises that the rig is stored: without room for it the upload is refused (507).
    auto environment = compute(loaded, options, source_id, rig_id, Storing::Required);
    metrics_.preprocess_seconds.observe(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    auto image = std::make_shared<const HdrImage>(std::move(loaded.image));
    images_.put(source_id, image, charge_of(*image));
    return environment;
}

std::shared_ptr<const Environment> EnvironmentRegistry::find(const std::string& id) {
    return rigs_.find(id, [&] { return load_stored(id); });
}

std::shared_ptr<const Environment> EnvironmentRegistry::load_stored(const std::string& id) {
    const auto provenance_text = store_.get_derived(DerivedKind::RigSource, id);
    if (!provenance_text) {
        return nullptr;  // never preprocessed here (or its record is gone: so is the way back)
    }
    const auto provenance = read_provenance(*provenance_text);
    if (!provenance) {
        log_("environments: record of rig " + id + " is unreadable; dropped");
        store_.remove(DerivedKind::RigSource, id);
        return nullptr;
    }
    const std::string& source_id = provenance->source_id;
    if (const auto stored = store_.get_derived(DerivedKind::Rig, id)) {
        try {
            const auto document =
                checked_json::parse_bounded(*stored, api::stored_rig_bounds(limits_.max_pixels));
            auto rig = std::make_shared<const Rig>(
                api::rig_from_json(document.at("rig"), document.at("masks")));
            auto environment = std::make_shared<const Environment>(
                Environment{id, std::move(rig), document.at("rig"), source_id});
            remember(environment);
            return environment;
        } catch (const std::exception& error) {
            // Sealed yet unreadable: written by another version, or a bug. Recompute below.
            log_("environments: stored rig " + id + " is unreadable (" + error.what() +
                 "); dropped");
            store_.remove(DerivedKind::Rig, id);
        }
    }
    const auto source = api::is_content_id(source_id)
                            ? store_.get_source(SourceKind::Environment, source_id)
                            : std::nullopt;
    if (!source) {
        log_("environments: rig " + id + " is missing and its source " + source_id +
             " is gone; cannot recompute");
        return nullptr;
    }
    log_("environments: rig " + id + " is missing or was damaged; recomputing it from source " +
         source_id);
    const InProgress in_progress(metrics_.rigs_in_progress);
    const auto start = std::chrono::steady_clock::now();
    LoadedImage loaded =
        load_image_memory(as_bytes(source->bytes), "stored." + source->extension, limits_);
    // Its upload was answered already: a rig the disk has no room for is served from memory.
    auto environment = compute(loaded, api::rig_options_from_json(provenance->options), source_id,
                               id, Storing::IfRoom);
    metrics_.preprocess_seconds.observe(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return environment;
}

std::shared_ptr<const Environment> EnvironmentRegistry::compute(const LoadedImage& loaded,
                                                                const RigOptions& options,
                                                                const std::string& source_id,
                                                                const std::string& rig_id,
                                                                Storing storing) {
    auto rig = std::make_shared<const Rig>(build_rig(loaded, options));
    metrics_.rigs_computed.increment();
    nlohmann::json json = api::rig_to_json(*rig, rig_id);
    // The record of provenance first: a crash between the two writes leaves a rig that can be
    // recomputed, never a rig whose source is unknown.
    const std::string record = provenance_json(source_id, options);
    const std::string stored =
        nlohmann::json{{"rig", json}, {"masks", api::light_masks_to_json(*rig)}}.dump();
    if (storing == Storing::IfRoom) {
        if (store_.put_derived_if_room(DerivedKind::RigSource, rig_id, record)) {
            store_.put_derived_if_room(DerivedKind::Rig, rig_id, stored);
        }
    } else {
        store_.put_derived(DerivedKind::RigSource, rig_id, record);
        try {
            store_.put_derived(DerivedKind::Rig, rig_id, stored);
        } catch (const StorageFull&) {
            // The upload is refused: its record goes too, so that the id stays unknown (404)
            // rather than recomputed on every lookup until the upload is made again.
            store_.remove(DerivedKind::RigSource, rig_id);
            throw;
        }
    }
    auto environment = std::make_shared<const Environment>(
        Environment{rig_id, std::move(rig), std::move(json), source_id});
    remember(environment);
    return environment;
}

void EnvironmentRegistry::remember(const std::shared_ptr<const Environment>& environment) {
    rigs_.remember(environment->id, environment, charge_of(*environment));
}

std::shared_ptr<const HdrImage> EnvironmentRegistry::source_image(const Environment& environment) {
    if (environment.source_id.empty()) {
        return preset_image_;
    }
    if (auto image = images_.get(environment.source_id)) {
        metrics_.cache(CacheName::Environment, true);
        return image;
    }
    metrics_.cache(CacheName::Environment, false);
    const auto source = store_.get_source(SourceKind::Environment, environment.source_id);
    if (!source) {
        return nullptr;
    }
    auto image = std::make_shared<const HdrImage>(
        load_image_memory(as_bytes(source->bytes), "stored." + source->extension, limits_).image);
    images_.put(environment.source_id, image, charge_of(*image));
    return image;
}

std::shared_ptr<const SpecularEnvironment> EnvironmentRegistry::specular(
    const Environment& environment) {
    if (environment.rig->model != LightingModel::Hdr) {
        return nullptr;
    }
    const std::string& id = environment.id;
    if (id == api::kDefaultPresetId) {
        // Prefiltered at its first glossy frame, not at start: a server (or a test) that draws
        // only matte frames never pays for it (0.5 s optimised, several under AddressSanitizer).
        // An exception leaves the flag unset, so that the next frame tries again.
        std::call_once(preset_specular_once_,
                       [&] { preset_specular_ = prefilter_timed(*preset_image_, environment); });
        return preset_specular_;
    }
    return specular_
        .upload(
            id,
            [&]() -> std::shared_ptr<const SpecularEnvironment> {
                if (auto cached = specular_.cached(id)) {
                    return cached;
                }
                return specular_.guarded([&] { return load_stored_specular(id); });
            },
            [&] { return compute_specular(environment); })
        .asset;
}

std::shared_ptr<const SpecularEnvironment> EnvironmentRegistry::load_stored_specular(
    const std::string& id) {
    const auto stored = store_.get_derived(DerivedKind::Specular, id);
    if (!stored) {
        return nullptr;
    }
    try {
        auto cube =
            std::make_shared<const SpecularEnvironment>(decode_specular_environment(*stored));
        specular_.remember(id, cube, cube->byte_size());
        return cube;
    } catch (const Error& error) {
        // Sealed yet undecodable: written by another version, or a bug. Recomputed by the caller.
        log_("environments: stored specular cube of rig " + id + " is unreadable (" + error.what() +
             "); dropped");
        store_.remove(DerivedKind::Specular, id);
        return nullptr;
    }
}

std::shared_ptr<const SpecularEnvironment> EnvironmentRegistry::compute_specular(
    const Environment& environment) {
    const InProgress in_progress(metrics_.specular_in_progress);
    const auto image = source_image(environment);
    if (!image) {
        log_("environments: specular cube of rig " + environment.id +
             " cannot be computed: its source " + environment.source_id + " is no longer stored");
        return nullptr;
    }
    auto cube = prefilter_timed(*image, environment);
    // Kept only while the rig is: a frame of an environment removed meanwhile still gets its
    // cube, which the store and memory then no longer hold (remove() waits for this
    // computation, under specular_'s lock, and removes what it stored).
    if (store_.contains(DerivedKind::RigSource, environment.id)) {
        store_.put_derived_if_room(DerivedKind::Specular, environment.id,
                                   encode_specular_environment(*cube));
        specular_.remember(environment.id, cube, cube->byte_size());
    }
    return cube;
}

std::shared_ptr<const SpecularEnvironment> EnvironmentRegistry::prefilter_timed(
    const HdrImage& image, const Environment& environment) {
    const auto start = std::chrono::steady_clock::now();
    auto cube =
        std::make_shared<const SpecularEnvironment>(prefilter_specular(image, *environment.rig));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    metrics_.specular_computed.increment();
    metrics_.specular_seconds.observe(seconds);
    log_("environments: specular cube of rig " + environment.id + " computed in " +
         std::to_string(int(std::lround(seconds * 1000.0))) + " ms, " +
         std::to_string(cube->byte_size()) + " bytes");
    return cube;
}

ListedPage EnvironmentRegistry::list(std::string_view after, std::size_t limit) {
    return rigs_.guarded([&] {
        return listed_page(
            store_.list(DerivedKind::RigSource, after, limit + 1), limit,
            [&](const std::string& id) -> std::optional<ListedAsset> {
                const auto record = store_.get_derived(DerivedKind::RigSource, id);
                const auto provenance = record ? read_provenance(*record) : std::nullopt;
                const auto written = store_.info(DerivedKind::RigSource, id);
                if (!provenance || !written || !api::is_content_id(provenance->source_id)) {
                    return std::nullopt;  // damaged: find() drops it and says so
                }
                return ListedAsset{id, provenance->source_id,
                                   store_.info(SourceKind::Environment, provenance->source_id),
                                   written->written};
            });
    });
}

bool EnvironmentRegistry::map_used_by_another_rig(const std::string& source_id,
                                                  const std::string& rig_id) {
    for (std::string after;;) {
        const std::vector<std::string> ids =
            store_.list(DerivedKind::RigSource, after, kRecordBatch);
        for (const std::string& id : ids) {
            if (id == rig_id) {
                continue;
            }
            const auto record = store_.get_derived(DerivedKind::RigSource, id);
            const auto provenance = record ? read_provenance(*record) : std::nullopt;
            if (provenance && provenance->source_id == source_id) {
                return true;
            }
        }
        if (ids.size() < kRecordBatch) {
            return false;
        }
        after = ids.back();
    }
}

bool EnvironmentRegistry::remove(const std::string& id) {
    if (!api::is_content_id(id)) {
        return false;
    }
    std::string removed_map;
    const bool removed = rigs_.remove(id, [&] {
        const auto record = store_.get_derived(DerivedKind::RigSource, id);
        const auto provenance = record ? read_provenance(*record) : std::nullopt;
        // The cube and the rig first: until the record goes, they can be recomputed from it and
        // the map, so a crash here leaves the environment whole. The record is the commit:
        // without it neither find() nor list() knows the rig. The map last, when no other rig
        // was made from it.
        store_.remove(DerivedKind::Specular, id);
        store_.remove(DerivedKind::Rig, id);
        if (!store_.remove(DerivedKind::RigSource, id)) {
            return false;
        }
        if (provenance && api::is_content_id(provenance->source_id) &&
            !map_used_by_another_rig(provenance->source_id, id)) {
            store_.remove(SourceKind::Environment, provenance->source_id);
            removed_map = provenance->source_id;
        }
        return true;
    });
    // A cube computed for a frame under way is stored only while the record is there: waiting
    // for such computations and removing what they stored leaves no cube behind.
    specular_.remove(id, [&] { return store_.remove(DerivedKind::Specular, id); });
    if (!removed_map.empty()) {
        images_.erase(removed_map);
    }
    return removed;
}

}  // namespace oer::server
