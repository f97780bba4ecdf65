// The material gallery (the Materials section of docs/accuracy.md): tone-mapped frames
// of the Stanford bunny (Lambertian, as the accuracy report renders it, and as a glossy gold metal)
// and of the material spheres (material_spheres.hpp, a glTF read through the loader) under every
// Blender world, with the spheres also shown with the world's brightest light switched off: their
// reflection of it goes with its diffuse light and its shadow. Beside each frame, its colour
// pass time (geometry + shading + readback); per world, the prefiltering time and the cube's
// memory.
//
//     material_gallery --out DIR     writes DIR/materials.md and DIR/materials/*.png
//
// scripts/accuracy-report.sh runs it and shows its page in docs/accuracy.md (make_report.py).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench_renderer.hpp"
#include "bench_support.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "oer/mesh/camera.hpp"
#include "oer/mesh/material_spheres.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "sweep_support.hpp"

namespace fs = std::filesystem;

namespace {

constexpr const char* kBunny = "/usr/share/glmark2/models/bunny.obj";
constexpr int kSize = 512;

struct GalleryScene {
    std::string name;   // file stem
    std::string title;  // column heading
    std::shared_ptr<const oer::Mesh> mesh;
    bool brightest_off = false;
};

// The bunny with every material a gold metal of roughness 0.3: the same geometry, glossy.
std::shared_ptr<const oer::Mesh> gold(const oer::Mesh& mesh) {
    auto glossy = std::make_shared<oer::Mesh>(mesh);
    for (oer::Material& material : glossy->materials) {
        material.model = oer::ShadingModel::MetallicRoughness;
        material.base_color = {1.0f, 0.78f, 0.34f, 1.0f};
        material.metallic = 1.0f;
        material.roughness = 0.3f;
    }
    return glossy;
}

double color_pass_ms(const oer::Frame& frame) {
    double sum = 0.0;
    for (const char* pass : {"geometry_pass", "shading_pass", "readback"}) {
        const auto found = frame.timings_ms.find(pass);
        sum += found == frame.timings_ms.end() ? 0.0 : found->second;
    }
    return sum;
}

int run(const fs::path& out) {
    if (!fs::exists(kBunny)) {
        std::fprintf(stderr, "material gallery: %s is missing (Debian package glmark2-data)\n",
                     kBunny);
        return 1;
    }
    const auto bunny = std::make_shared<const oer::Mesh>(oer::load_mesh_file(kBunny));
    const std::vector<std::byte> spheres_glb = oer::material_spheres_glb();
    const auto spheres = std::make_shared<const oer::Mesh>(
        oer::load_mesh_memory(spheres_glb, "material-spheres.glb", oer::MeshFormat::Glb));
    const std::vector<GalleryScene> scenes = {
        {"bunny", "bunny (Lambertian)", bunny, false},
        {"bunny-gold", "bunny, gold metal, roughness 0.3", gold(*bunny), false},
        {"spheres", "spheres: dielectric over metal, roughness 0 to 1", spheres, false},
        {"spheres-brightest-off", "spheres, brightest light off", spheres, true},
    };
    const fs::path images = out / "materials";
    fs::create_directories(images);
    oer::bench::BenchRenderer renderer;
    std::ostringstream page;
    page << "# Materials: glTF PBR under every Blender world\n\n"
         << "Made by bench/material_gallery.cpp (run by `scripts/accuracy-report.sh`); do not edit "
            "by hand. Renderer: "
         << renderer.info().renderer << ". " << kSize << "x" << kSize
         << ", 4 samples per pixel, soft shadows, Khronos PBR Neutral tone map, exposure 0. "
            "Under each frame: its colour pass (geometry, shading, readback) in ms, shadow "
            "maps cached. The spheres are a glTF made by code in the manner of Khronos's "
            "MetalRoughSpheres (renderer/mesh/include/oer/mesh/material_spheres.hpp): "
            "dielectrics above metals, roughness 0 on the left to 1 on the right. In the last "
            "column the world's brightest light is switched off: its reflections go with its "
            "diffuse light and its shadow.\n\n";
    page << "| world | prefilter ms | cube MB |";
    for (const GalleryScene& scene : scenes) {
        page << " " << scene.title << " |";
    }
    page << "\n|---|---|---|";
    for (std::size_t i = 0; i < scenes.size(); ++i) {
        page << "---|";
    }
    page << "\n";
    for (const fs::path& world_path : oer::bench::blender_worlds()) {
        const std::string world = world_path.stem().string();
        oer::LoadedImage loaded = oer::load_image_file(world_path.string());
        const auto map = std::make_shared<const oer::HdrImage>(std::move(loaded.image));
        const auto rig =
            std::make_shared<const oer::Rig>(oer::build_rig(*map, loaded.repaired, {}));
        const auto start = oer::bench::Clock::now();
        const auto cube =
            std::make_shared<const oer::PrefilteredCube>(oer::prefilter_residual(*map, *rig));
        const double prefilter_ms = oer::bench::ms_since(start);
        char head[128];
        std::snprintf(head, sizeof head, "| %s (%zu lights) | %.0f | %.2f |", world.c_str(),
                      rig->lights.size(), prefilter_ms, double(cube->byte_size()) / 1e6);
        page << head;
        for (const GalleryScene& scene : scenes) {
            oer::FrameRequest request;
            request.rig = rig;
            request.environment_map = map;
            request.specular = cube;
            request.objects.push_back({scene.mesh, glm::mat4(1.0f), std::nullopt});
            request.width = kSize;
            request.height = kSize;
            request.camera = oer::frame_bounds(scene.mesh->bounds, 45.0f, 1.0f);
            if (scene.brightest_off && !rig->lights.empty()) {
                request.lights.assign(rig->lights.size(), 1.0f);
                request.lights[0] = 0.0f;  // light location's first light is the brightest
            }
            renderer.render(request);  // warm: programs, textures, shadow maps
            const oer::Frame frame = renderer.render(request);
            const std::string name = scene.name + "-" + world + ".png";
            const std::vector<std::uint8_t> png = oer::encode_png(frame.display);
            oer::bench::write_text_file((images / name).string(),
                                        std::string(png.begin(), png.end()));
            char cell[256];
            std::snprintf(cell, sizeof cell, " ![%s, %s](materials/%s)<br>%.1f ms |",
                          scene.title.c_str(), world.c_str(), name.c_str(), color_pass_ms(frame));
            page << cell;
            std::printf("%-12s %-24s %6.1f ms\n", world.c_str(), scene.name.c_str(),
                        color_pass_ms(frame));
        }
        page << "\n";
    }
    oer::bench::write_text_file((out / "materials.md").string(), page.str());
    std::printf("wrote %s\n", (out / "materials.md").c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3 || std::string(argv[1]) != "--out") {
        std::fprintf(stderr, "usage: %s --out DIR\n", argv[0]);
        return 2;
    }
    try {
        return run(argv[2]);
    } catch (const oer::Error& error) {
        std::fprintf(stderr, "material gallery: %s\n", error.what());
        return 1;
    }
}
