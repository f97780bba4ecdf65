// `oer reference`: the ground truth of a frame (renderer/reference), with `oer render`'s scene,
// camera, environment and light flags, as linear EXR in the same camera.
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>

#include <nlohmann/json.hpp>

#include "command_line.hpp"
#include "commands.hpp"
#include "oer/api/frame_encoding.hpp"
#include "oer/api/render_request.hpp"
#include "oer/core/error.hpp"
#include "oer/reference/reference_renderer.hpp"
#include "render_inputs.hpp"

namespace oer::cli {

namespace {

void write_file(const std::string& path, const std::string& what, const char* data,
                std::size_t size) {
    std::ofstream out(path, std::ios::binary);
    out.write(data, std::streamsize(size));
    if (!out) {
        throw Error(ErrorKind::Io, path + ": cannot write the " + what);
    }
}

nlohmann::json noise_json(double relative_rms, std::size_t pixels) {
    return {{"relative_rms", pixels > 0 ? nlohmann::json(relative_rms) : nlohmann::json()},
            {"pixels", pixels}};
}

}  // namespace

int reference_command(const std::vector<std::string>& arguments) {
    CLI::App app("Path traces the frame `oer render` draws: the ground truth.", "oer reference");
    RenderInputs inputs;
    std::string stats_path;
    int samples = 64;
    std::uint64_t sample_seed = 1;
    int threads = 0;
    app.add_option("-o", inputs.output, "the frame, OUT.exr (linear radiance)");
    // --samples is this command's own (Monte Carlo samples per pixel), not the rasteriser's;
    // --occlusion switches the rasteriser's approximation of what the reference traces.
    // --bounce is `oer render`'s: the reference of a frame traces the light that frame models.
    add_render_inputs(app, inputs, {"samples", "occlusion"});
    app.add_option("--samples", samples, "Monte Carlo samples per pixel, even, at least 2")
        ->check(CLI::Range(2, 1 << 20));
    // --seed is the light location's (every command's preprocessing flag).
    app.add_option("--sample-seed", sample_seed, "the Monte Carlo seed");
    app.add_option("--threads", threads, "threads, 0 for every core")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--stats", stats_path, "also write the noise estimate to FILE (JSON)");
    if (!parse_flags(app, arguments)) {
        return 0;
    }
    if (inputs.output.empty() || inputs.environment_path.empty() || inputs.mesh_paths.empty()) {
        throw UsageError(
            "reference takes --env MAP, at least one --mesh MESH (or 'default') and -o OUT.exr");
    }
    if (extension_of(inputs.output) != "exr") {
        throw UsageError("-o must end in .exr (the reference is linear radiance), got '" +
                         inputs.output + "'");
    }
    if (samples % 2 != 0) {
        throw UsageError("--samples must be even (two halves estimate the noise), got " +
                         std::to_string(samples));
    }
    const RenderScene scene = read_render_scene(inputs, "exr");
    // The reference shades glTF's core metallic-roughness BRDF, not the extensions' layers
    // (docs/glossy-reference.md): say so rather than let such a product's reference pass for
    // what oer render draws.
    for (const SceneObject& object : scene.request.objects) {
        for (const Material& material : object.mesh->materials) {
            if (material.layered()) {
                std::cerr << "reference: material '" << material.name
                          << "' has KHR_materials_* layers (ior, specular, clear coat, sheen or "
                             "transmission); the reference shades its core metallic-roughness "
                             "BRDF without them\n";
            }
        }
    }
    ReferenceOptions options;
    options.bounce = scene.request.bounce;
    options.samples = samples;
    options.seed = sample_seed;
    options.threads = threads;
    const ReferenceFrame reference = render_reference(scene.request, options);

    Frame frame;
    frame.width = reference.width;
    frame.height = reference.height;
    frame.linear = reference.linear;
    const std::vector<std::uint8_t> bytes = api::encode(frame, api::ImageFormat::Exr, 0);
    write_file(inputs.output, "frame", reinterpret_cast<const char*>(bytes.data()), bytes.size());

    const ReferenceNoise& noise = reference.noise;
    const nlohmann::json stats = {{"width", reference.width},
                                  {"height", reference.height},
                                  {"bounce", api::to_string(scene.spec.bounce)},
                                  {"samples", samples},
                                  {"sample_seed", sample_seed},
                                  {"render_ms", reference.render_ms},
                                  {"noise",
                                   {{"object", noise_json(noise.object, noise.object_pixels)},
                                    {"ground", noise_json(noise.ground, noise.ground_pixels)}}}};
    if (!stats_path.empty()) {
        const std::string text = stats.dump(2) + "\n";
        write_file(stats_path, "statistics", text.data(), text.size());
    }
    std::cerr << std::setprecision(3) << "reference: " << reference.width << "x" << reference.height
              << ", bounce " << api::to_string(scene.spec.bounce) << ", " << samples
              << " samples per pixel, " << std::fixed << std::setprecision(1) << reference.render_ms
              << " ms; relative RMS noise: object " << std::setprecision(4) << noise.object << " ("
              << noise.object_pixels << " pixels), ground " << noise.ground << " ("
              << noise.ground_pixels << " pixels)\n";
    return 0;
}

}  // namespace oer::cli
