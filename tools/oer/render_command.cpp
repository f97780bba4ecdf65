#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include "command_line.hpp"
#include "commands.hpp"
#include "oer/api/frame_encoding.hpp"
#include "oer/api/render_request.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "oer/scene/scene_rules.hpp"
#include "oer/transfer/transfer_bake.hpp"
#include "render_inputs.hpp"

namespace oer::cli {

int render_command(const std::vector<std::string>& arguments) {
    CLI::App app("Renders meshes lit by an environment's rig.", "oer render");
    RenderInputs inputs;
    app.add_option("-o", inputs.output, "the frame, OUT.(jpg|png|exr)");
    add_render_inputs(app, inputs);
    if (!parse_flags(app, arguments)) {
        return 0;
    }
    if (inputs.output.empty() || inputs.environment_path.empty() || inputs.mesh_paths.empty()) {
        throw UsageError(
            "render takes --env MAP, at least one --mesh MESH (or 'default') and -o OUT");
    }
    const std::string extension = extension_of(inputs.output);
    if (extension != "jpg" && extension != "jpeg" && extension != "png" && extension != "exr") {
        throw UsageError("-o must end in .jpg, .png or .exr, got '" + inputs.output + "'");
    }

    const auto total_start = std::chrono::steady_clock::now();
    RenderScene scene =
        read_render_scene(inputs, extension == "jpg" ? std::string("jpeg") : extension);
    const api::RenderSpec& spec = scene.spec;
    const std::shared_ptr<const Rig>& rig = scene.rig;
    FrameRequest& request = scene.request;
    double specular_ms = -1.0;
    if (needs_specular(request)) {
        const auto specular_start = std::chrono::steady_clock::now();
        request.specular = std::make_shared<const SpecularEnvironment>(
            prefilter_specular(*request.environment_map, *rig));
        specular_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                                specular_start)
                          .count();
    }
    // Baked here, off the render thread, as the service bakes it before it queues the frame.
    if (request.occlusion) {
        TransferBakeOptions options;
        options.bounce = request.bounce;
        request.transfer = std::make_shared<const SceneTransfer>(bake_transfer(request, options));
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
    std::ofstream out(inputs.output, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) {
        throw Error(ErrorKind::Io, inputs.output + ": cannot write the frame");
    }
    std::cerr << std::fixed << std::setprecision(1) << "render: " << thread.info().renderer << ", "
              << frame.width << "x" << frame.height << ", " << rig->lights.size()
              << " light(s), SH order " << rig->order << "\n";
    std::cerr << "  preprocess " << rig->timings_ms.at("total") << " ms";
    if (specular_ms >= 0.0) {
        std::cerr << ", specular cube " << specular_ms << " ms (" << request.specular->byte_size()
                  << " bytes)";
    }
    if (request.transfer) {
        std::cerr << ", transfer " << request.transfer->bake_ms << " ms (" << request.transfer->rays
                  << " rays per point)";
    }
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
