#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <string_view>

#include "commands.hpp"
#include "environment_input.hpp"
#include "oer/api/content_id.hpp"
#include "oer/api/frame_encoding.hpp"
#include "oer/api/invalid_parameter.hpp"
#include "oer/api/render_request.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/mesh/default_product.hpp"
#include "oer/mesh/mesh_loading.hpp"

namespace oer::cli {

namespace {

std::string extension_of(const std::string& path) {
    const std::size_t dot = path.rfind('.');
    std::string extension = dot == std::string::npos ? "" : path.substr(dot + 1);
    for (char& c : extension) {
        c = char(std::tolower(static_cast<unsigned char>(c)));
    }
    return extension;
}

// The flags that are query parameters of GET /v1/render, as (flag, parameter): their values go
// through the service's parser, so that the CLI accepts, rejects and defaults exactly as the
// service does. --size WxH gives two of them, width and height.
constexpr std::array<std::pair<std::string_view, std::string_view>, 16> kQueryFlags{{
    {"base-color", "base_color"},
    {"eye", "eye"},
    {"target", "target"},
    {"up", "up"},
    {"fov", "fov_y"},
    {"lights", "lights"},
    {"ground", "ground"},
    {"background", "background"},
    {"tonemap", "tonemap"},
    {"exposure", "exposure"},
    {"shadows", "shadows"},
    {"shadow-resolution", "shadow_resolution"},
    {"shadow-filter", "shadow_filter"},
    {"samples", "samples"},
    {"yaw", "environment_yaw"},
    {"quality", "quality"},
}};

// The flag that gave a query parameter.
std::string flag_of(const std::string& parameter) {
    if (parameter == "width" || parameter == "height") {
        return "size";
    }
    for (const auto& [flag, name] : kQueryFlags) {
        if (name == parameter) {
            return std::string(flag);
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
    for (const auto& [flag, parameter] : kQueryFlags) {
        if (const auto value = flags.find(std::string(flag)); value != flags.end()) {
            query.emplace(parameter, value->second);
        }
    }
    return query;
}

api::RenderSpec parse_render_flags(const std::map<std::string, std::string>& flags,
                                   std::size_t mesh_count, const std::string& format) {
    try {
        return api::parse_render_query(render_query(flags, mesh_count, format));
    } catch (const api::InvalidParameter& error) {
        throw usage_error(error, flag_of(error.parameter()));
    }
}

}  // namespace

int render_command(const std::vector<std::string>& arguments) {
    CLI::App app("Renders meshes lit by an environment's rig.", "oer render");
    std::string output, environment_path;
    std::vector<std::string> mesh_paths;
    std::map<std::string, std::string> flags;  // the query flags given, and --size
    app.add_option("-o", output, "the frame, OUT.(jpg|png|exr)");
    app.add_option("--env", environment_path, "an .hdr or .exr file, or 'default'");
    app.add_option("--mesh", mesh_paths, "a .glb, .gltf or .obj file, or 'default' (repeatable)");
    add_value_flag(app, "size", "WxH", [&flags](const std::string& text) { flags["size"] = text; });
    for (const auto& [flag, parameter] : kQueryFlags) {
        add_value_flag(
            app, std::string(flag), "VALUE",
            [&flags, flag = std::string(flag)](const std::string& text) { flags[flag] = text; });
    }
    EnvironmentFlags environment;
    add_environment_flags(app, environment);
    if (!parse_flags(app, arguments)) {
        return 0;
    }
    if (output.empty() || environment_path.empty() || mesh_paths.empty()) {
        throw UsageError(
            "render takes --env MAP, at least one --mesh MESH (or 'default') and -o OUT");
    }
    const std::string extension = extension_of(output);
    if (extension != "jpg" && extension != "jpeg" && extension != "png" && extension != "exr") {
        throw UsageError("-o must end in .jpg, .png or .exr, got '" + output + "'");
    }
    const api::RenderSpec spec = parse_render_flags(
        flags, mesh_paths.size(), extension == "jpg" ? std::string("jpeg") : extension);
    const RigOptions rig_options = rig_options_from(environment);

    const auto total_start = std::chrono::steady_clock::now();
    const EnvironmentInput input = read_environment(environment_path, environment);
    auto rig = std::make_shared<const Rig>(
        build_rig(input.loaded.image, input.loaded.repaired, rig_options));
    std::vector<std::shared_ptr<const Mesh>> meshes;
    for (const std::string& path : mesh_paths) {
        meshes.push_back(std::make_shared<const Mesh>(path == "default" ? make_default_product()
                                                                        : load_mesh_file(path)));
    }
    FrameRequest request;
    try {
        request = api::to_frame_request(
            spec, rig, std::make_shared<const HdrImage>(input.loaded.image), meshes);
    } catch (const api::InvalidParameter& error) {
        throw usage_error(error, flag_of(error.parameter()));
    }

    RenderThread thread;
    const Frame frame = thread
                            .submit([&request] {
                                FrameRenderer renderer;
                                return renderer.render(request);
                            })
                            .get();
    const auto encode_start = std::chrono::steady_clock::now();
    const std::vector<std::uint8_t> bytes = api::encode(frame, spec.format, spec.quality);
    const double encode_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - encode_start)
            .count();
    std::ofstream out(output, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) {
        throw Error(ErrorKind::Io, output + ": cannot write the frame");
    }
    std::cerr << std::fixed << std::setprecision(1) << "render: " << thread.info().renderer << ", "
              << frame.width << "x" << frame.height << ", " << rig->lights.size()
              << " light(s), SH order " << rig->order << "\n";
    std::cerr << "  preprocess " << rig->timings_ms.at("total") << " ms";
    for (const auto& [pass, ms] : frame.timings_ms) {
        std::cerr << ", " << pass << " " << ms << " ms";
    }
    std::cerr << ", encode " << encode_ms << " ms (" << bytes.size() << " bytes), all "
              << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                           total_start)
                     .count()
              << " ms\n";
    return 0;
}

}  // namespace oer::cli
