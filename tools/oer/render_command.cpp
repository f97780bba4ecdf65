#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "commands.hpp"
#include "environment_input.hpp"
#include "oer/api/light_switches.hpp"
#include "oer/api/parameter_text.hpp"
#include "oer/api/render_request.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/lighting/tonemap.hpp"
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

}  // namespace

int render_command(const std::vector<std::string>& arguments) {
    std::set<std::string> valued = rig_option_flags();
    valued.insert({"o", "env", "mesh", "eye", "target", "up", "fov", "lights", "size", "ground",
                   "background", "tonemap", "exposure", "quality", "shadows", "shadow-resolution",
                   "shadow-filter", "samples", "yaw"});
    const CommandLine line = parse_command_line(arguments, valued, {});
    if (!line.positional.empty() || !line.value("o") || !line.value("env") ||
        !line.values.contains("mesh")) {
        throw UsageError(
            "render takes --env MAP, at least one --mesh MESH (or 'default') and -o OUT");
    }
    const std::string output = *line.value("o");
    const std::string format = extension_of(output);
    if (format != "jpg" && format != "jpeg" && format != "png" && format != "exr") {
        throw UsageError("-o must end in .jpg, .png or .exr, got '" + output + "'");
    }

    const auto total_start = std::chrono::steady_clock::now();
    const EnvironmentInput input = read_environment(*line.value("env"), line);
    auto rig = std::make_shared<const Rig>(
        build_rig(input.loaded.image, input.loaded.repaired, rig_options_from(line)));

    FrameRequest request;
    request.rig = rig;
    request.environment_map = std::make_shared<const HdrImage>(input.loaded.image);
    for (const std::string& path : line.values.at("mesh")) {
        request.objects.push_back(
            {std::make_shared<const Mesh>(path == "default" ? make_default_product()
                                                            : load_mesh_file(path)),
             glm::mat4(1.0f), std::nullopt});
    }
    const auto [width, height] = parse_size("size", line.value("size").value_or("512x512"), 16384);
    request.width = width;
    request.height = height;
    const std::vector<double> switches =
        api::parse_light_switches(line.value("lights"), rig->lights.size());
    for (const double on : switches) {
        request.lights.push_back(on > 0.5);
    }
    // Values in the API's vocabulary go through its parsers, so the CLI and the service accept
    // the same text.
    try {
        if (line.value("eye") || line.value("target")) {
            const auto vector = [&line](const std::string& flag, const std::string& fallback) {
                return glm::vec3(api::parse_vector3(flag, line.value(flag).value_or(fallback),
                                                    -api::kMaxCoordinate, api::kMaxCoordinate));
            };
            Camera camera;
            camera.eye = vector("eye", "0,0,3");
            camera.target = vector("target", "0,0,0");
            camera.up = vector("up", "0,1,0");
            camera.fov_y = float(parse_double("fov", line.value("fov").value_or("45")));
            request.camera = camera;
        }
        request.ground = api::parse_on_off("ground", line.value("ground").value_or("on"));
        request.background =
            api::parse_background("background", line.value("background").value_or("env"));
        request.shadows.enabled =
            api::parse_on_off("shadows", line.value("shadows").value_or("on"));
        request.shadows.filter =
            api::parse_enum("shadow_filter", line.value("shadow-filter").value_or("pcf"),
                            api::shadow_filter_from_string);
    } catch (const api::InvalidParameter& error) {
        throw usage_error(error);
    }
    request.tonemap = tone_mapper_from_string(line.value("tonemap").value_or("neutral"));
    request.exposure = parse_double("exposure", line.value("exposure").value_or("0"));
    request.shadows.resolution =
        parse_int("shadow-resolution", line.value("shadow-resolution").value_or("2048"), 16, 8192);
    request.samples = parse_int("samples", line.value("samples").value_or("4"), 1, 16);
    request.environment_yaw = parse_double("yaw", line.value("yaw").value_or("0"));
    request.linear = format == "exr";
    const int quality = parse_int("quality", line.value("quality").value_or("90"), 1, 100);

    RenderThread thread;
    const Frame frame = thread
                            .submit([&request] {
                                FrameRenderer renderer;
                                return renderer.render(request);
                            })
                            .get();
    const auto encode_start = std::chrono::steady_clock::now();
    const std::vector<std::uint8_t> bytes =
        format == "exr"   ? encode_exr(frame.width, frame.height, frame.linear)
        : format == "png" ? encode_png(frame.display)
                          : encode_jpeg(frame.display, quality);
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
