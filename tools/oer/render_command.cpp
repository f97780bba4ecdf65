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
#include "oer/default_product.hpp"
#include "oer/error.hpp"
#include "oer/frame_renderer.hpp"
#include "oer/image_encoding.hpp"
#include "oer/mesh_loading.hpp"
#include "oer/render_thread.hpp"
#include "oer/tonemap.hpp"

namespace oer::cli {

namespace {

glm::vec3 parse_vector(const std::string& flag, const std::string& text) {
    glm::vec3 v{0.0f};
    std::size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        const std::size_t end = i < 2 ? text.find(',', start) : text.size();
        if (end == std::string::npos) {
            throw UsageError("--" + flag + " expects X,Y,Z, got '" + text + "'");
        }
        try {
            std::size_t used = 0;
            const std::string part = text.substr(start, end - start);
            v[i] = std::stof(part, &used);
            if (used != part.size() || !std::isfinite(v[i])) {
                throw std::invalid_argument(part);
            }
        } catch (const std::exception&) {
            throw UsageError("--" + flag + " expects X,Y,Z as finite numbers, got '" + text + "'");
        }
        start = end + 1;
    }
    return v;
}

bool parse_on_off(const std::string& flag, const std::string& text) {
    if (text == "on" || text == "off") {
        return text == "on";
    }
    throw UsageError("--" + flag + " expects on or off, got '" + text + "'");
}

Background parse_background(const std::string& text) {
    Background background;
    if (text == "env") {
        return background;
    }
    if (text == "transparent") {
        background.kind = BackgroundKind::Transparent;
        return background;
    }
    if (text.size() == 7 && text[0] == '#' &&
        text.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
        background.kind = BackgroundKind::Colour;
        for (int i = 0; i < 3; ++i) {
            background.colour[i] =
                float(std::stoi(text.substr(1 + 2 * i, 2), nullptr, 16)) / 255.0f;
        }
        return background;
    }
    throw UsageError("--background expects env, transparent or #rrggbb, got '" + text + "'");
}

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
    request.environment = std::make_shared<const HdrImage>(input.loaded.image);
    for (const std::string& path : line.values.at("mesh")) {
        request.objects.push_back(
            {std::make_shared<const Mesh>(path == "default" ? make_default_product()
                                                            : load_mesh_file(path)),
             glm::mat4(1.0f), std::nullopt});
    }
    const auto [width, height] = parse_size("size", line.value("size").value_or("512x512"), 16384);
    request.width = width;
    request.height = height;
    if (line.value("eye") || line.value("target")) {
        Camera camera;
        camera.eye = parse_vector("eye", line.value("eye").value_or("0,0,3"));
        camera.target = parse_vector("target", line.value("target").value_or("0,0,0"));
        camera.up = parse_vector("up", line.value("up").value_or("0,1,0"));
        camera.fov_y_degrees = float(parse_double("fov", line.value("fov").value_or("45")));
        request.camera = camera;
    }
    const std::vector<double> switches =
        api::parse_light_switches(line.value("lights"), rig->lights.size());
    for (const double on : switches) {
        request.lights.push_back(on > 0.5);
    }
    request.ground = parse_on_off("ground", line.value("ground").value_or("on"));
    request.background = parse_background(line.value("background").value_or("env"));
    request.tone_mapper = tone_mapper_from_string(line.value("tonemap").value_or("neutral"));
    request.exposure_ev = parse_double("exposure", line.value("exposure").value_or("0"));
    request.shadows.enabled = parse_on_off("shadows", line.value("shadows").value_or("on"));
    request.shadows.resolution =
        parse_int("shadow-resolution", line.value("shadow-resolution").value_or("2048"), 16, 8192);
    const std::string filter = line.value("shadow-filter").value_or("pcf");
    if (filter != "pcf" && filter != "hard") {
        throw UsageError("--shadow-filter expects pcf or hard, got '" + filter + "'");
    }
    request.shadows.filter = filter == "pcf" ? ShadowFilter::Pcf : ShadowFilter::Hard;
    request.samples = parse_int("samples", line.value("samples").value_or("4"), 1, 16);
    request.yaw_degrees = parse_double("yaw", line.value("yaw").value_or("0"));
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
