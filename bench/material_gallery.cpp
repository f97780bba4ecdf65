// The material gallery (the Materials section of docs/accuracy.md): tone-mapped frames
// of the Stanford bunny (Lambertian, as the accuracy report renders it, and as a glossy gold metal)
// and of the material spheres (material_spheres.hpp, a glTF read through the loader) under every
// Blender world, with the spheres also shown with the world's brightest light switched off: their
// reflection of it goes with its diffuse light and its shadow. Beside each frame, its colour
// pass time (geometry + shading + readback); per world, the prefiltering time and the cube's
// memory.
//
// Then the error of glossy frames against the reference renderer, which shades the same glTF
// BRDF (renderer/reference/include/oer/reference/metallic_roughness_brdf.hpp) with one bounce:
// per sphere of a dielectric row and a metal row at the roughness of the targets (docs/design.md
// section 8: mirror 0.05, metal 0.3, plastic 0.5) the relative RMS of luminance over its whole
// pixels, and for the gold bunny and the dress form (fabric and a lacquered stand on its floor)
// over 4 x 4 blocks (bench/support/frame_metrics.hpp), each frame as the service renders it:
// occlusion and one bounce through the scene's baked transfer, on the floor.
//
//     material_gallery --out DIR [--samples N] [--size N] [--worlds NAME,NAME]
//         writes DIR/materials.md and DIR/materials/*.png; the error frames are N x N (256)
//         against N samples per pixel (128)
//
// scripts/accuracy-report.sh runs it and shows its page in docs/accuracy.md (make_report.py).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "bench_renderer.hpp"
#include "bench_support.hpp"
#include "frame_metrics.hpp"
#include "oer/core/error.hpp"
#include "oer/gl/frame_renderer.hpp"
#include "oer/gl/render_thread.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/image/image_io.hpp"
#include "oer/lighting/rig.hpp"
#include "oer/lighting/specular_environment.hpp"
#include "oer/mesh/camera.hpp"
#include "oer/mesh/default_product.hpp"
#include "oer/mesh/material_spheres.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "oer/reference/reference_renderer.hpp"
#include "oer/transfer/transfer_bake.hpp"
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

struct Arguments {
    std::string out;
    int samples = 128;
    int size = 256;
    std::vector<std::string> worlds;  // empty: every Blender world
};

Arguments parse_arguments(int argc, const char* const* argv) {
    Arguments arguments;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (flag == "--out") {
            arguments.out = oer::bench::flag_value(argc, argv, i);
        } else if (flag == "--samples") {
            arguments.samples =
                oer::bench::reference_samples(flag, oer::bench::flag_value(argc, argv, i));
        } else if (flag == "--size") {
            const std::string value = oer::bench::flag_value(argc, argv, i);
            arguments.size = std::atoi(value.c_str());
            if (arguments.size < 16 || arguments.size > 2048) {
                throw oer::Error(oer::ErrorKind::InvalidInput,
                                 "--size takes 16 to 2048 pixels, not '" + value + "'");
            }
        } else if (flag == "--worlds") {
            arguments.worlds = oer::bench::split_names(oer::bench::flag_value(argc, argv, i));
        } else {
            throw oer::Error(oer::ErrorKind::InvalidInput,
                             "unknown flag '" + flag +
                                 "' (takes --out DIR, --samples N, --size N, --worlds NAME,NAME)");
        }
    }
    if (arguments.out.empty()) {
        throw oer::Error(oer::ErrorKind::InvalidInput, "--out DIR is required");
    }
    return arguments;
}

double color_pass_ms(const oer::Frame& frame) {
    double sum = 0.0;
    for (const char* pass : {"geometry_pass", "shading_pass", "readback"}) {
        const auto found = frame.timings_ms.find(pass);
        sum += found == frame.timings_ms.end() ? 0.0 : found->second;
    }
    return sum;
}

// The worlds the arguments name (every Blender world when they name none).
std::vector<fs::path> chosen_worlds(const Arguments& arguments) {
    std::vector<fs::path> chosen;
    for (const fs::path& path : oer::bench::blender_worlds()) {
        const std::string stem = path.stem().string();
        if (arguments.worlds.empty() || std::find(arguments.worlds.begin(), arguments.worlds.end(),
                                                  stem) != arguments.worlds.end()) {
            chosen.push_back(path);
        }
    }
    if (chosen.empty()) {
        throw oer::Error(oer::ErrorKind::InvalidInput, "--worlds names no Blender world");
    }
    return chosen;
}

struct World {
    std::string name;
    std::shared_ptr<const oer::HdrImage> map;
    std::shared_ptr<const oer::Rig> rig;
    std::shared_ptr<const oer::SpecularEnvironment> cube;
};

// A scene of the error tables: its mesh, baked once for every world (a transfer depends on the
// objects and the ground, not on the light).
struct ErrorScene {
    std::string title;
    std::shared_ptr<const oer::Mesh> mesh;
    std::shared_ptr<const oer::SceneTransfer> transfer;
    bool per_sphere = false;  // one figure per primitive (a sphere), else 4 x 4 blocks
};

oer::FrameRequest error_request(const ErrorScene& scene, const World& world, int size) {
    oer::FrameRequest request;
    request.rig = world.rig;
    request.environment_map = world.map;
    request.specular = world.cube;
    request.objects.push_back({scene.mesh, glm::mat4(1.0f), std::nullopt});
    request.width = size;
    request.height = size;
    request.camera = oer::frame_bounds(scene.mesh->bounds, 45.0f, 1.0f);
    request.linear = true;
    request.occlusion = true;
    request.bounce = oer::Bounce::One;
    request.transfer = scene.transfer;
    return request;
}

// The ray through the point (x, y) of a square frame, in pixels from its top left corner (a
// pixel's centre is at its index plus 0.5), as the reference casts it.
glm::dvec3 pixel_ray(const oer::Camera& camera, int size, double x, double y) {
    const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target - camera.eye));
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double t = std::tan(glm::radians(double(camera.fov_y)) / 2.0);
    return glm::normalize(forward + (2.0 * x / size - 1.0) * t * right +
                          (1.0 - 2.0 * y / size) * t * up);
}

// Per primitive (a sphere about its bounds' centre), the pixels wholly on it: the rays through
// the four corners of the pixel meet the sphere shrunk by 1 % (its facets lie inside the round
// one), and both frames show the object there. A pixel across the silhouette averages the
// sphere with what lies behind it, by 4 samples here and 256 in the reference: against a
// bright light behind (the studio's soft boxes, night's lamps) that coverage's difference was
// 90 to 99 % of a dielectric sphere's squared error, which is the edge's antialiasing and not
// the material's.
std::vector<std::vector<std::uint8_t>> sphere_masks(const oer::Mesh& mesh,
                                                    const oer::Camera& camera, int size,
                                                    const std::vector<float>& ours,
                                                    const oer::ReferenceFrame& reference) {
    std::vector<std::vector<std::uint8_t>> masks;
    const glm::dvec3 eye(camera.eye);
    for (const oer::Primitive& primitive : mesh.primitives) {
        glm::dvec3 low(1e30), high(-1e30);
        for (const glm::vec3& p : primitive.positions) {
            low = glm::min(low, glm::dvec3(p));
            high = glm::max(high, glm::dvec3(p));
        }
        const glm::dvec3 centre = 0.5 * (low + high);
        const double radius = 0.5 * (high.x - low.x);
        std::vector<std::uint8_t> mask(std::size_t(size) * std::size_t(size), 0);
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(size) + std::size_t(x);
                const glm::dvec3 oc = eye - centre;
                const double c = glm::dot(oc, oc) - 0.99 * 0.99 * radius * radius;
                bool inside = true;
                for (const double corner_y : {0.0, 1.0}) {
                    for (const double corner_x : {0.0, 1.0}) {
                        const double b =
                            glm::dot(oc, pixel_ray(camera, size, x + corner_x, y + corner_y));
                        inside = inside && b * b - c > 0.0;
                    }
                }
                mask[i] = inside && reference.surfaces[i] == oer::ReferenceSurface::Object &&
                          ours[i * 4 + 3] >= 0.999f && reference.linear[i * 4 + 3] >= 0.999f;
            }
        }
        masks.push_back(std::move(mask));
    }
    return masks;
}

// The pixels wholly on the object in both frames.
std::vector<std::uint8_t> object_mask(const oer::ReferenceFrame& frame,
                                      const std::vector<float>& ours_rgba) {
    std::vector<std::uint8_t> mask(ours_rgba.size() / 4, 0);
    for (std::size_t i = 0; i < mask.size(); ++i) {
        mask[i] = frame.surfaces[i] == oer::ReferenceSurface::Object &&
                  ours_rgba[i * 4 + 3] >= 0.999f && frame.linear[i * 4 + 3] >= 0.999f;
    }
    return mask;
}

// The relative RMS of luminance of ours against the reference over 4 x 4 blocks wholly on the
// object in both frames, and the reference's own noise there.
std::pair<double, double> block_error(const std::vector<double>& ours,
                                      const std::vector<double>& reference,
                                      const oer::ReferenceFrame& frame,
                                      const std::vector<float>& ours_rgba) {
    const std::vector<std::uint8_t> mask = object_mask(frame, ours_rgba);
    const oer::bench::BlockGrid grid{frame.width, frame.height, 4};
    const std::vector<std::uint8_t> blocks = oer::bench::whole_blocks(mask, grid);
    return {oer::bench::relative_rms_error(oer::bench::block_means(ours, grid),
                                           oer::bench::block_means(reference, grid), blocks),
            oer::bench::relative_noise(oer::bench::block_noise(frame.luminance_noise, grid),
                                       oer::bench::block_means(reference, grid), blocks)};
}

// One cell of the error tables: the relative RMS error against the reference and the
// reference's own relative noise over the same pixels.
struct Measured {
    double error = 0.0;
    double noise = 0.0;

    // The error of ours against the noiseless truth: the squared noise (per pixel an unbiased
    // estimate of the variance of the reference's mean, ReferenceFrame::luminance_noise) is
    // the reference's share of the squared error, sqrt(max(0, error^2 - noise^2)).
    double without_noise() const { return std::sqrt(std::max(0.0, error * error - noise * noise)); }
};

// Per target of docs/design.md section 8, the range of the measured error over the worlds, as
// measured and less the reference's noise, and the worlds within the target.
std::string target_summary(const std::vector<std::string>& rows,
                           const std::vector<std::vector<Measured>>& measured,
                           std::size_t world_count) {
    struct Target {
        std::string row;
        double limit;
    };
    const Target targets[] = {{"metal roughness 0.3, alone", 0.15},
                              {"dielectric roughness 0.5, alone", 0.06},
                              {"metal roughness 0.05, alone", 0.30},
                              {"metal roughness 0.3, in the grid", 0.15},
                              {"dielectric roughness 0.5, in the grid", 0.06},
                              {"metal roughness 0.05, in the grid", 0.30},
                              {"gold bunny, roughness 0.3, 4x4 blocks", 0.15},
                              {"dress form (fabric, lacquered stand), 4x4 blocks", 0.15}};
    std::ostringstream page;
    page << "\nPer target: the range over the worlds as measured, and less the reference's noise "
            "(sqrt(error^2 - noise^2): the squared noise is the reference's expected share of "
            "the squared error), and the worlds within the target by the latter.\n\n"
            "| target | limit | measured | less the reference's noise | worlds within |\n"
            "|---|---|---|---|---|\n";
    for (const Target& target : targets) {
        const auto found = std::find(rows.begin(), rows.end(), target.row);
        if (found == rows.end()) {
            continue;
        }
        const std::vector<Measured>& cells = measured[std::size_t(found - rows.begin())];
        double low = HUGE_VAL, high = 0.0, clean_low = HUGE_VAL, clean_high = 0.0;
        int within = 0;
        for (const Measured& cell : cells) {
            low = std::min(low, cell.error);
            high = std::max(high, cell.error);
            clean_low = std::min(clean_low, cell.without_noise());
            clean_high = std::max(clean_high, cell.without_noise());
            within += cell.without_noise() <= target.limit;
        }
        char line[256];
        std::snprintf(line, sizeof line, "| %s | %.2f | %.3f–%.3f | %.3f–%.3f | %d of %zu |\n",
                      target.row.c_str(), target.limit, low, high, clean_low, clean_high, within,
                      world_count);
        page << line;
    }
    return page.str();
}

// The mesh with primitive `index` alone (its materials and textures kept): one sphere of the
// grid, which then reflects nothing of its neighbours.
std::shared_ptr<const oer::Mesh> primitive_alone(const oer::Mesh& mesh, std::size_t index) {
    oer::Mesh alone = mesh;
    alone.primitives = {mesh.primitives.at(index)};
    const oer::Primitive& primitive = alone.primitives[0];
    alone.bounds = {primitive.positions.front(), primitive.positions.front()};
    for (const glm::vec3& p : primitive.positions) {
        alone.bounds.min = glm::min(alone.bounds.min, p);
        alone.bounds.max = glm::max(alone.bounds.max, p);
    }
    alone.vertex_count = primitive.positions.size();
    alone.triangle_count = primitive.indices.size() / 3;
    return std::make_shared<const oer::Mesh>(std::move(alone));
}

// The rest of a markdown table whose first header cell is written: a column per world, then
// a row per name with its cells.
std::string table_body(const std::vector<World>& worlds, const std::vector<std::string>& names,
                       const std::vector<std::vector<std::string>>& cells) {
    std::ostringstream table;
    for (const World& world : worlds) {
        table << " " << world.name << " |";
    }
    table << "\n|---|";
    for (std::size_t i = 0; i < worlds.size(); ++i) {
        table << "---|";
    }
    table << "\n";
    for (std::size_t row = 0; row < names.size(); ++row) {
        table << "| " << names[row] << " |";
        for (const std::string& cell : cells[row]) {
            table << " " << cell << " |";
        }
        table << "\n";
    }
    return table.str();
}

// The tables of ours against the reference, per world.
std::string error_tables(oer::bench::BenchRenderer& renderer, const std::vector<World>& worlds,
                         const Arguments& arguments) {
    const std::vector<float> roughness = {0.0f, 0.05f, 0.3f, 0.5f, 1.0f};
    oer::MaterialSpheresOptions sphere_options;
    sphere_options.roughness = roughness;
    const std::vector<std::byte> glb = oer::material_spheres_glb(sphere_options);
    const auto spheres = std::make_shared<const oer::Mesh>(
        oer::load_mesh_memory(glb, "material-spheres.glb", oer::MeshFormat::Glb));
    const auto bunny = std::make_shared<const oer::Mesh>(oer::load_mesh_file(kBunny));
    // The grid (each sphere reflects its neighbours, which the rasteriser does not see), each
    // sphere of it alone on the floor (what the targets are about: a material under a world),
    // and two products.
    std::vector<ErrorScene> scenes = {{"spheres", spheres, nullptr, true}};
    for (std::size_t i = 0; i < spheres->primitives.size(); ++i) {
        scenes.push_back(
            {spheres->materials.at(std::size_t(spheres->primitives[i].material)).name + ", alone",
             primitive_alone(*spheres, i), nullptr, true});
    }
    scenes.push_back({"gold bunny, roughness 0.3, 4x4 blocks", gold(*bunny), nullptr, false});
    scenes.push_back({"dress form (fabric, lacquered stand), 4x4 blocks",
                      std::make_shared<const oer::Mesh>(oer::make_default_product()), nullptr,
                      false});
    for (ErrorScene& scene : scenes) {
        oer::FrameRequest request = error_request(scene, worlds.front(), arguments.size);
        request.transfer = nullptr;
        oer::TransferBakeOptions bake;
        bake.bounce = oer::Bounce::One;
        scene.transfer =
            std::make_shared<const oer::SceneTransfer>(oer::bake_transfer(request, bake));
    }
    // Rows: one per sphere of the grid (its material's name), then the other scenes; columns:
    // worlds.
    std::vector<std::string> rows;
    for (const oer::Primitive& primitive : spheres->primitives) {
        rows.push_back(spheres->materials.at(std::size_t(primitive.material)).name +
                       ", in the grid");
    }
    for (std::size_t i = 1; i < scenes.size(); ++i) {
        rows.push_back(scenes[i].title);
    }
    std::vector<std::vector<std::string>> cells(rows.size());
    std::vector<std::vector<Measured>> measured(rows.size());
    // The products' sRGB frames (the service's display transform) by the 3D Commerce measures.
    std::vector<std::string> products;
    for (const ErrorScene& scene : scenes) {
        if (!scene.per_sphere) {
            products.push_back(scene.title.substr(0, scene.title.find(", 4x4 blocks")));
        }
    }
    std::vector<std::vector<std::string>> display_cells(products.size());
    double lowest_psnr = HUGE_VAL, lowest_ssim = HUGE_VAL;
    std::string times = "| frame ms: ours / reference |";
    for (const World& world : worlds) {
        std::size_t row = 0, product = 0;
        double ours_ms = 0.0, reference_ms = 0.0;
        for (const ErrorScene& scene : scenes) {
            const oer::FrameRequest request = error_request(scene, world, arguments.size);
            renderer.render(request);  // warm: programs, textures, shadow maps
            const oer::Frame frame = renderer.render(request);
            oer::ReferenceOptions options;
            options.bounce = oer::Bounce::One;
            options.samples = arguments.samples;
            const oer::ReferenceFrame reference = oer::render_reference(request, options);
            ours_ms += color_pass_ms(frame);
            reference_ms += reference.render_ms;
            const std::vector<double> ours = oer::bench::frame_luminance(frame.linear);
            const std::vector<double> truth = oer::bench::frame_luminance(reference.linear);
            const auto add = [&](double error, double noise) {
                char text[64];
                std::snprintf(text, sizeof text, "%.3f (%.3f)", error, noise);
                measured[row].push_back({error, noise});
                cells[row++].push_back(text);
            };
            if (scene.per_sphere) {
                for (const std::vector<std::uint8_t>& mask : sphere_masks(
                         *scene.mesh, *request.camera, arguments.size, frame.linear, reference)) {
                    add(oer::bench::relative_rms_error(ours, truth, mask),
                        oer::bench::relative_noise(reference.luminance_noise, truth, mask));
                }
            } else {
                const auto [error, noise] = block_error(ours, truth, reference, frame.linear);
                add(error, noise);
                const auto display = [&](const std::vector<float>& rgba) {
                    return oer::bench::display_image(rgba, arguments.size, arguments.size, 1.0, 0.0,
                                                     oer::ToneMapper::Neutral);
                };
                const oer::Rgba8Image ours_srgb = display(frame.linear);
                const oer::Rgba8Image truth_srgb = display(reference.linear);
                const std::vector<std::uint8_t> mask = object_mask(reference, frame.linear);
                const double psnr = oer::bench::psnr_db(ours_srgb, truth_srgb, mask);
                const double ssim = oer::bench::ssim(ours_srgb, truth_srgb, mask);
                lowest_psnr = std::min(lowest_psnr, psnr);
                lowest_ssim = std::min(lowest_ssim, ssim);
                char text[64];
                std::snprintf(text, sizeof text, "%.1f dB / %.3f", psnr, ssim);
                display_cells[product++].push_back(text);
            }
            std::printf("%-12s %-50s ours %6.1f ms, reference %7.0f ms\n", world.name.c_str(),
                        scene.title.c_str(), color_pass_ms(frame), reference.render_ms);
        }
        char time[96];
        std::snprintf(time, sizeof time, " %.0f / %.0f |", ours_ms, reference_ms);
        times += time;
    }
    std::ostringstream page;
    page << "\n### Against the reference renderer\n\n"
         << "Relative RMS of luminance against `oer reference` (the same glTF BRDF, path traced "
            "with one bounce, "
         << arguments.samples << " samples per pixel), " << arguments.size << "x" << arguments.size
         << ", every frame as the service renders it (occlusion and one bounce through the "
            "scene's baked transfer, on its floor); in brackets the reference's own noise "
            "over the same pixels. Spheres: over each sphere's whole pixels, in the grid (where "
            "each reflects its neighbours, which the rasteriser's reflections do not see) and "
            "alone (the grid's sphere by itself, framed); the bunny and the dress form: over "
            "4x4 blocks. Targets (docs/design.md section 8): metal at "
            "roughness 0.3 at most 0.15, dielectric (plastic) at 0.5 at most 0.06, mirror "
            "(metal at 0.05) at most 0.30.\n\n| scene |";
    page << table_body(worlds, rows, cells);
    page << times << "\n";
    page << "\nThe Khronos 3D Commerce certification's measures of the products' frames against "
            "the reference's, both through the service's display transform (Khronos PBR "
            "Neutral, exposure 0, sRGB), on the luma of the pixels on the product: PSNR and "
            "SSIM (Wang, Bovik, Sheikh and Simoncelli 2004; 11x11 Gaussian window). The "
            "certification asks PSNR > 20 dB and SSIM > 0.70.\n\n| product |";
    page << table_body(worlds, products, display_cells);
    char lowest[160];
    std::snprintf(lowest, sizeof lowest,
                  "\nLowest over the products and worlds: PSNR %.1f dB, SSIM %.3f.\n", lowest_psnr,
                  lowest_ssim);
    page << lowest;
    page << target_summary(rows, measured, worlds.size());
    return page.str();
}

int run(const Arguments& arguments) {
    const fs::path out = arguments.out;
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
    std::vector<World> worlds;
    for (const fs::path& world_path : chosen_worlds(arguments)) {
        const std::string world = world_path.stem().string();
        oer::LoadedImage loaded = oer::load_image_file(world_path.string());
        const auto map = std::make_shared<const oer::HdrImage>(std::move(loaded.image));
        const auto rig =
            std::make_shared<const oer::Rig>(oer::build_rig(*map, loaded.repaired, {}));
        const auto start = oer::bench::Clock::now();
        const auto cube =
            std::make_shared<const oer::SpecularEnvironment>(oer::prefilter_specular(*map, *rig));
        const double prefilter_ms = oer::bench::ms_since(start);
        worlds.push_back({world, map, rig, cube});
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
    page << error_tables(renderer, worlds, arguments);
    oer::bench::write_text_file((out / "materials.md").string(), page.str());
    std::printf("wrote %s\n", (out / "materials.md").c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(parse_arguments(argc, argv));
    } catch (const oer::Error& error) {
        std::fprintf(stderr, "material gallery: %s\n", error.what());
        return 1;
    }
}
