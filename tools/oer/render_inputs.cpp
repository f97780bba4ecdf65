#include "render_inputs.hpp"

#include <cctype>
#include <string_view>
#include <utility>

#include "command_line.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/render_parameters.hpp"
#include "oer/mesh/default_product.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::cli {

namespace {

// The flags that are query parameters of GET /v1/render (api::render_parameters(), the rows
// with a flag): their values go through the service's parser, so that the CLI accepts, rejects
// and defaults exactly as the service does. --size WxH gives two of them, width and height.
std::vector<const api::RenderParameter*> query_flags() {
    std::vector<const api::RenderParameter*> flags;
    for (const api::RenderParameter& row : api::render_parameters()) {
        if (!row.flag.empty()) {
            flags.push_back(&row);
        }
    }
    return flags;
}

// The flag that gave a query parameter.
std::string flag_of(const std::string& parameter) {
    if (parameter == "width" || parameter == "height") {
        return "size";
    }
    for (const api::RenderParameter* row : query_flags()) {
        if (row->query == parameter) {
            return std::string(row->flag);
        }
    }
    return parameter;
}

// The render flags as a GET /v1/render query. The environment and the meshes are files the CLI
// reads itself, so the query names them by the placeholder id "default" (one mesh per --mesh);
// they are resolved from the files afterwards.
std::multimap<std::string, std::string> render_query(std::map<std::string, std::string> flags,
                                                     std::size_t mesh_count,
                                                     const std::string& format) {
    std::multimap<std::string, std::string> query{
        {"environment", std::string(api::kDefaultPresetId)}, {"format", format}};
    for (std::size_t i = 0; i < mesh_count; ++i) {
        query.emplace("mesh", api::kDefaultPresetId);
    }
    if (const auto size = flags.find("size"); size != flags.end()) {
        const std::size_t x = size->second.find('x');
        if (x == std::string::npos) {
            throw UsageError("--size expects WIDTHxHEIGHT, got '" + size->second + "'");
        }
        query.emplace("width", size->second.substr(0, x));
        query.emplace("height", size->second.substr(x + 1));
    }
    // The CLI's look-at camera needs only one of --eye and --target: the other keeps its
    // documented default (eye 0,0,3, target the origin).
    if (flags.contains("eye") || flags.contains("target")) {
        flags.try_emplace("eye", "0,0,3");
        flags.try_emplace("target", "0,0,0");
    }
    for (const api::RenderParameter* row : query_flags()) {
        if (const auto value = flags.find(std::string(row->flag)); value != flags.end()) {
            query.emplace(row->query, value->second);
        }
    }
    return query;
}

}  // namespace

void add_render_inputs(CLI::App& app, RenderInputs& inputs, const std::set<std::string>& omitted) {
    app.add_option("--env", inputs.environment_path, "an .hdr or .exr file, or 'default'");
    app.add_option("--mesh", inputs.mesh_paths,
                   "a .glb, .gltf or .obj file, or 'default' (repeatable)");
    add_value_flag(app, "size", "WxH",
                   [&inputs](const std::string& text) { inputs.flags["size"] = text; });
    for (const api::RenderParameter* row : query_flags()) {
        const std::string flag(row->flag);
        if (omitted.contains(flag)) {
            continue;
        }
        add_value_flag(app, flag, row->value_name, [&inputs, flag](const std::string& text) {
            inputs.flags[flag] = text;
        })->description(row->help);
    }
    add_environment_flags(app, inputs.environment);
}

RenderScene read_render_scene(const RenderInputs& inputs, const std::string& format) {
    RenderScene scene;
    try {
        scene.spec =
            api::parse_render_query(render_query(inputs.flags, inputs.mesh_paths.size(), format));
    } catch (const api::InvalidParameter& error) {
        throw usage_error(error, flag_of(error.parameter()));
    }
    const RigOptions rig_options = rig_options_from(inputs.environment);
    const EnvironmentInput input = read_environment(inputs.environment_path, inputs.environment);
    scene.rig = std::make_shared<const Rig>(build_rig(input.loaded, rig_options));
    std::vector<std::shared_ptr<const Mesh>> meshes;
    for (const std::string& path : inputs.mesh_paths) {
        meshes.push_back(std::make_shared<const Mesh>(path == "default" ? make_default_product()
                                                                        : load_mesh_file(path)));
    }
    try {
        scene.request = api::to_frame_request(
            scene.spec, scene.rig, std::make_shared<const HdrImage>(input.loaded.image), meshes);
    } catch (const api::InvalidParameter& error) {
        throw usage_error(error, flag_of(error.parameter()));
    }
    return scene;
}

std::string extension_of(const std::string& path) {
    const std::size_t dot = path.rfind('.');
    std::string extension = dot == std::string::npos ? "" : path.substr(dot + 1);
    for (char& c : extension) {
        c = char(std::tolower(static_cast<unsigned char>(c)));
    }
    return extension;
}

}  // namespace oer::cli
