// glTF as shops' pipelines ship it: assimp-testmodels' 2CylinderEngine (29 meshes, 82 nodes,
// meshes reused by several nodes) compressed by the real tools, glTF-Transform's CLI 4.5.1
// (tests/mesh/gltf_tools, pinned by its package-lock.json) and Debian's gltfpack 0.18, run here
// into the build folder; each file is loaded and compared with the uncompressed original in
// world space: every vertex of one within the quantization's tolerance of a vertex of the
// other, with its normal within the normals' tolerance, and the same triangles (or, after
// simplification, no more); and each is rendered (`oer render`, the same camera and lighting)
// and its frame compared with the original's, pixel by pixel. Each test prints the file's size
// and load time against the original's, and the frames' difference.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "gltf_test_assets.hpp"
#include "oer/image/image_io.hpp"

using namespace oer;
using namespace oer::mesh_testing;

namespace {

const fs::path kSource = kAssimpGltf / "2CylinderEngine-glTF-Binary" / "2CylinderEngine.glb";
const fs::path kWork = OER_GLTF_TOOLS_WORK;

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
};

std::vector<Vertex> vertices_of(const Mesh& mesh) {
    std::vector<Vertex> out;
    for (const Primitive& p : mesh.primitives) {
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
            out.push_back({p.positions[i], p.normals[i]});
        }
    }
    return out;
}

double area_of(const Mesh& mesh) {
    double area = 0.0;
    for (const Primitive& p : mesh.primitives) {
        for (std::size_t t = 0; t < p.indices.size() / 3; ++t) {
            area += 0.5 * double(glm::length(geometric_normal(p, t)));
        }
    }
    return area;
}

// The vertices of `mesh` in a grid of cells of `cell`, to find the ones near a point.
class VertexGrid {
  public:
    VertexGrid(std::vector<Vertex> vertices, float cell)
        : vertices_(std::move(vertices)), cell_(cell) {
        for (std::size_t i = 0; i < vertices_.size(); ++i) {
            cells_[key(cell_of(vertices_[i].position))].push_back(i);
        }
    }

    // The distance to the nearest vertex within `radius` (<= cell), and the largest cosine
    // between `normal` and the normals of the vertices within `radius`; infinity and -2 when
    // there is none.
    std::pair<float, float> nearest(const Vertex& v, float radius) const {
        float distance = std::numeric_limits<float>::infinity();
        float cosine = -2.0f;
        const glm::ivec3 c = cell_of(v.position);
        for (int dx = -1; dx <= 1; ++dx) {
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto found = cells_.find(key(c + glm::ivec3(dx, dy, dz)));
                    if (found == cells_.end()) {
                        continue;
                    }
                    for (std::size_t i : found->second) {
                        const float d = glm::length(vertices_[i].position - v.position);
                        distance = std::min(distance, d);
                        if (d <= radius) {
                            cosine = std::max(cosine, glm::dot(vertices_[i].normal, v.normal));
                        }
                    }
                }
            }
        }
        return {distance, cosine};
    }

  private:
    glm::ivec3 cell_of(const glm::vec3& p) const { return glm::ivec3(glm::floor(p / cell_)); }
    static std::int64_t key(const glm::ivec3& c) {
        return (std::int64_t(c.x) * 73856093) ^ (std::int64_t(c.y) * 19349663) ^
               (std::int64_t(c.z) * 83492791);
    }

    std::vector<Vertex> vertices_;
    float cell_;
    std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

// Every vertex of `from` within `tolerance` of one of `to`, whose normal is within
// `normal_degrees` of its own.
void expect_near(const std::vector<Vertex>& from, const VertexGrid& to, float tolerance,
                 float normal_degrees, const std::string& what) {
    const float min_cosine = std::cos(glm::radians(normal_degrees));
    float worst_distance = 0.0f;
    float worst_cosine = 1.0f;
    for (const Vertex& v : from) {
        const auto [distance, cosine] = to.nearest(v, tolerance);
        worst_distance = std::max(worst_distance, distance);
        worst_cosine = std::min(worst_cosine, cosine);
    }
    std::cout << "[          ] " << what << ": farthest vertex " << worst_distance
              << ", worst normal " << glm::degrees(std::acos(std::clamp(worst_cosine, -1.0f, 1.0f)))
              << " degrees\n";
    EXPECT_LE(worst_distance, tolerance) << what;
    EXPECT_GE(worst_cosine, min_cosine) << what;
}

double load_milliseconds(const std::vector<std::uint8_t>& bytes) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
        const auto start = std::chrono::steady_clock::now();
        load_mesh_memory(as_bytes(bytes), "timed.glb", MeshFormat::Glb, kUnrefined);
        best = std::min(best, std::chrono::duration<double, std::milli>(
                                  std::chrono::steady_clock::now() - start)
                                  .count());
    }
    return best;
}

// The extensions a .glb declares it uses.
std::vector<std::string> extensions_used(const std::vector<std::uint8_t>& glb) {
    const std::uint32_t length = std::uint32_t(glb[12]) | std::uint32_t(glb[13]) << 8 |
                                 std::uint32_t(glb[14]) << 16 | std::uint32_t(glb[15]) << 24;
    const json d = json::parse(glb.begin() + 20, glb.begin() + 20 + length);
    return d.value("extensionsUsed", std::vector<std::string>());
}

// The source's 121496 triangles include 11154 with a repeated index and 6 more with two corners
// at one position: gltfpack drops the first, Draco both.
enum class Degenerate { Kept, RepeatedIndicesDropped, CoincidentCornersDropped };

std::uint64_t triangles_kept(const Mesh& mesh, Degenerate degenerate) {
    std::uint64_t kept = 0;
    for (const Primitive& p : mesh.primitives) {
        for (std::size_t t = 0; t + 2 < p.indices.size(); t += 3) {
            const std::uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
            const bool repeated = a == b || b == c || a == c;
            const bool coincident = p.positions[a] == p.positions[b] ||
                                    p.positions[b] == p.positions[c] ||
                                    p.positions[a] == p.positions[c];
            kept += degenerate == Degenerate::Kept ||
                    (degenerate == Degenerate::RepeatedIndicesDropped && !repeated) ||
                    (degenerate == Degenerate::CoincidentCornersDropped && !coincident);
        }
    }
    return kept;
}

struct Expected {
    std::vector<std::string> extensions;
    float position_bits = 0.0f;  // the tolerance: the source's diagonal / 2^bits
    float normal_degrees = 0.0f;
    Degenerate degenerate = Degenerate::Kept;
    bool simplified = false;  // fewer triangles, not every original vertex kept
};

// The frame of the .glb at `mesh` as `oer render` draws it into `output` (linear EXR): 160x120,
// one sample, the built-in studio, occlusion off (the geometry and its shadows, without a bake
// per file), from a camera fixed by the source's bounds `seen` so that every file is seen alike.
HdrImage rendered(const fs::path& mesh, const fs::path& output, const Bounds& seen) {
    const glm::vec3 centre = seen.centre();
    const float diagonal = glm::length(seen.max - seen.min);
    const glm::vec3 eye = centre + 1.1f * diagonal * glm::normalize(glm::vec3(1.0f, 0.7f, 1.3f));
    const auto vector = [](const glm::vec3& v) {
        return std::to_string(v.x) + "," + std::to_string(v.y) + "," + std::to_string(v.z);
    };
    const std::string command = std::string(OER_CLI_PATH) + " render --env default --mesh " +
                                mesh.string() + " --eye " + vector(eye) + " --target " +
                                vector(centre) + " --size 160x120 --samples 1 --occlusion off -o " +
                                output.string() + " > " + output.string() + ".log 2>&1";
    if (std::system(command.c_str()) != 0) {
        ADD_FAILURE() << command << " failed: see " << output << ".log";
        return {};
    }
    return load_image_file(output.string()).image;
}

// How two frames differ, per channel, relative to the first frame's mean value: the mean, and
// the share of values off by more than a tenth of it.
struct FrameDifference {
    double mean = 1.0;
    double beyond_a_tenth = 1.0;
};

FrameDifference frame_difference(const HdrImage& reference, const HdrImage& other) {
    if (reference.pixels.empty() || reference.pixels.size() != other.pixels.size()) {
        ADD_FAILURE() << "frames of different sizes";
        return {};
    }
    double scale = 0.0;
    for (const float value : reference.pixels) {
        scale += double(value);
    }
    scale /= double(reference.pixels.size());
    double sum = 0.0;
    std::size_t beyond = 0;
    for (std::size_t i = 0; i < reference.pixels.size(); ++i) {
        const double difference =
            std::abs(double(reference.pixels[i]) - double(other.pixels[i])) / scale;
        sum += difference;
        beyond += difference > 0.1 ? 1 : 0;
    }
    return {sum / double(reference.pixels.size()),
            double(beyond) / double(reference.pixels.size())};
}

class CompressedGltfToolsSlow : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        fs::create_directories(kWork);
        const std::string install = std::string(OER_CMAKE) + " -DNPM=" + OER_NPM +
                                    " -DFOLDER=" + OER_GLTF_TOOLS_DIR + " -P " +
                                    OER_GLTF_TOOLS_DIR + "/npm_ci.cmake > " +
                                    (kWork / "npm.log").string() + " 2>&1";
        installed_ = std::system(install.c_str()) == 0;
    }

    void SetUp() override {
        REQUIRE_ASSIMP_SAMPLES();
        ASSERT_TRUE(installed_) << "npm ci in " << OER_GLTF_TOOLS_DIR << " failed: see "
                                << (kWork / "npm.log");
    }

    // glTF-Transform's command `command` (with its options) from the source to `output`.
    static std::string gltf_transform(const std::string& command, const std::string& output) {
        return std::string(OER_NODE) + " " + OER_GLTF_TOOLS_DIR +
               "/node_modules/@gltf-transform/cli/bin/cli.js " + command + " " + kSource.string() +
               " " + (kWork / output).string();
    }

    static std::string gltfpack(const std::string& options, const std::string& output) {
        return std::string(OER_GLTFPACK) + " -i " + kSource.string() + " -o " +
               (kWork / output).string() + (options.empty() ? "" : " " + options);
    }

    // Runs `command`, which writes `output`, then compares it with the source.
    static void check(const std::string& command, const std::string& output,
                      const Expected& expected) {
        const fs::path log = kWork / (output + ".log");
        fs::remove(kWork / output);
        ASSERT_EQ(std::system((command + " > " + log.string() + " 2>&1").c_str()), 0)
            << command << ": see " << log;
        const std::vector<std::uint8_t> compressed = read_bytes(kWork / output);
        const std::vector<std::uint8_t> original = read_bytes(kSource);
        const std::vector<std::string> used = extensions_used(compressed);
        for (const std::string& extension : expected.extensions) {
            EXPECT_NE(std::find(used.begin(), used.end(), extension), used.end())
                << output << " does not use " << extension;
        }
        const Mesh plain =
            load_mesh_memory(as_bytes(original), "source.glb", MeshFormat::Glb, kUnrefined);
        const Mesh mesh =
            load_mesh_memory(as_bytes(compressed), output, MeshFormat::Glb, kUnrefined);
        expect_valid(mesh);
        EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();
        const float tolerance =
            glm::length(plain.bounds.max - plain.bounds.min) / std::exp2(expected.position_bits);
        const VertexGrid plain_grid(vertices_of(plain), tolerance);
        expect_near(vertices_of(mesh), plain_grid, tolerance, expected.normal_degrees,
                    output + " against the source");
        if (expected.simplified) {
            EXPECT_LE(mesh.triangle_count, plain.triangle_count);
            EXPECT_GE(mesh.triangle_count, plain.triangle_count / 2);
        } else {
            const VertexGrid grid(vertices_of(mesh), tolerance);
            expect_near(vertices_of(plain), grid, tolerance, expected.normal_degrees,
                        "the source against " + output);
            EXPECT_EQ(mesh.triangle_count, triangles_kept(plain, expected.degenerate));
        }
        EXPECT_NEAR(area_of(mesh) / area_of(plain), 1.0, 0.01);
        // Drawn, the compressed file's frame is the source's but for quantization: a few
        // values at silhouettes and shadow edges (measured: a mean of 0.00004 to 0.0035 of the
        // frame's mean, 0.02 % to 0.5 % of values off by more than a tenth; gltfpack's, which
        // drops degenerate triangles and re-splits the primitives, the most).
        const HdrImage frame = rendered(kWork / output, kWork / (output + ".exr"), plain.bounds);
        const FrameDifference drawn = frame_difference(source_frame(plain.bounds), frame);
        std::cout << "[          ] " << output << " drawn: mean difference " << 100.0 * drawn.mean
                  << " % of the source frame's mean, " << 100.0 * drawn.beyond_a_tenth
                  << " % of values off by more than 10 %\n";
        EXPECT_LE(drawn.mean, expected.simplified ? 0.01 : 0.006) << output;
        EXPECT_LE(drawn.beyond_a_tenth, expected.simplified ? 0.02 : 0.01) << output;
        std::cout << "[          ] " << output << ": " << compressed.size() << " bytes ("
                  << 100.0 * double(compressed.size()) / double(original.size())
                  << " % of the source's " << original.size() << "), loaded in "
                  << load_milliseconds(compressed) << " ms (the source in "
                  << load_milliseconds(original) << " ms), " << mesh.primitives.size()
                  << " primitives, " << mesh.triangle_count << " triangles\n";
    }

    // The source's frame, rendered by the first test that needs it: every test draws the same
    // file from the same camera (its bounds), and each `oer render` costs seconds.
    static const HdrImage& source_frame(const Bounds& seen) {
        if (!source_frame_) {
            source_frame_ = rendered(kSource, kWork / "source.exr", seen);
        }
        return *source_frame_;
    }

    static bool installed_;
    static std::optional<HdrImage> source_frame_;
};

bool CompressedGltfToolsSlow::installed_ = false;
std::optional<HdrImage> CompressedGltfToolsSlow::source_frame_;

}  // namespace

// glTF-Transform's defaults: 14-bit positions, 10-bit normals (Draco), 8-bit octahedral
// normals (meshopt); the tolerances leave a factor of 4 over the step.
TEST_F(CompressedGltfToolsSlow, GltfTransformDraco) {
    check(gltf_transform("draco", "draco.glb"), "draco.glb",
          {{"KHR_draco_mesh_compression"}, 12.0f, 3.0f, Degenerate::CoincidentCornersDropped});
}

TEST_F(CompressedGltfToolsSlow, GltfTransformMeshopt) {
    check(gltf_transform("meshopt", "meshopt.glb"), "meshopt.glb",
          {{"EXT_meshopt_compression", "KHR_mesh_quantization"}, 12.0f, 3.0f});
}

TEST_F(CompressedGltfToolsSlow, GltfTransformQuantize) {
    check(gltf_transform("quantize", "quantize.glb"), "quantize.glb",
          {{"KHR_mesh_quantization"}, 12.0f, 3.0f});
}

TEST_F(CompressedGltfToolsSlow, GltfTransformInstance) {
    // Floats throughout: the instances' transforms alone move the vertices, by rounding.
    check(gltf_transform("instance", "instance.glb"), "instance.glb",
          {{"EXT_mesh_gpu_instancing"}, 20.0f, 0.1f});
}

TEST_F(CompressedGltfToolsSlow, GltfTransformOptimizeDefaults) {
    // Deduplication, instancing, flattening, joining, welding, simplification, then meshopt.
    check(gltf_transform("optimize", "optimize.glb"), "optimize.glb",
          {{"EXT_meshopt_compression", "KHR_mesh_quantization", "EXT_mesh_gpu_instancing"},
           12.0f,
           3.0f,
           Degenerate::Kept,
           true});
}

// gltfpack's defaults: 14-bit positions, 8-bit normals.
TEST_F(CompressedGltfToolsSlow, GltfpackCompressed) {
    check(gltfpack("-cc", "gltfpack-cc.glb"), "gltfpack-cc.glb",
          {{"EXT_meshopt_compression", "KHR_mesh_quantization"},
           12.0f,
           3.0f,
           Degenerate::RepeatedIndicesDropped});
}

TEST_F(CompressedGltfToolsSlow, GltfpackDefaults) {
    check(gltfpack("", "gltfpack.glb"), "gltfpack.glb",
          {{"KHR_mesh_quantization"}, 12.0f, 3.0f, Degenerate::RepeatedIndicesDropped});
}

// With instancing (-mi): the instances' translations and scales through meshopt's EXPONENTIAL
// filter, their rotations as normalized SHORTs through QUATERNION: every filter of the extension.
// Rotations of 16 bits (-ar 16): gltfpack's default 12 bits turn the instances by up to 1e-3
// radians, which moves the vertices of this model (quantized over its 800 units) by up to 0.7.
TEST_F(CompressedGltfToolsSlow, GltfpackInstancedCompressed) {
    check(gltfpack("-cc -mi -ar 16", "gltfpack-cc-mi.glb"), "gltfpack-cc-mi.glb",
          {{"EXT_meshopt_compression", "KHR_mesh_quantization", "EXT_mesh_gpu_instancing"},
           12.0f,
           3.0f,
           Degenerate::RepeatedIndicesDropped});
}
