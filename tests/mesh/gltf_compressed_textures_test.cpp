// glTF textures beyond PNG and JPEG: WebP (EXT_texture_webp) and AVIF (EXT_texture_avif),
// decoded, and KTX2 with Basis Universal payloads (KHR_texture_basisu), whose header is checked
// but which is not decoded (no transcoder in the build: the texture's PNG or JPEG fallback is
// used). The assets were made by the real tools from tests/data/textures/source.png
// (make_textures.sh: glTF-Transform 4.5.1's webp and avif commands, basisu 1.15 for ETC1S and
// UASTC+Zstandard); hostile headers are made here.
#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf_test_assets.hpp"
#include "oer/core/error.hpp"
#include "oer/mesh/mesh.hpp"
#include "oer/mesh/mesh_loading.hpp"
#include "process_memory.hpp"
#include "texture_decoding.hpp"

using namespace oer;
using namespace oer::mesh_testing;

namespace {

const fs::path kData = OER_TEXTURE_DATA_DIR;

std::vector<std::uint8_t> data_file(const std::string& name) {
    std::vector<std::uint8_t> bytes = read_bytes(kData / name);
    EXPECT_FALSE(bytes.empty()) << name;
    return bytes;
}

Mesh load_textured_glb(const std::vector<std::uint8_t>& bytes, const MeshLimits& limits = {}) {
    return load_mesh_memory(as_bytes(bytes), "test.glb", MeshFormat::Glb, limits);
}

const Texture& base_colour_texture(const Mesh& mesh) {
    const Material& material = mesh.materials.at(std::size_t(mesh.primitives.at(0).material));
    EXPECT_TRUE(material.base_color_texture.present());
    return mesh.textures.at(std::size_t(material.base_color_texture.texture));
}

// The per-channel absolute differences of two RGBA textures of one size.
struct Difference {
    double mean = 0.0;
    int max = 0;
    double over_32 = 0.0;  // the fraction of channels that differ by more than 32
};

Difference difference(const Texture& a, const Texture& b) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    Difference d;
    if (a.rgba.size() != b.rgba.size() || a.rgba.empty()) {
        ADD_FAILURE() << "the textures differ in size";
        return d;
    }
    std::uint64_t sum = 0;
    std::size_t over = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) {
        const int delta = std::abs(int(a.rgba[i]) - int(b.rgba[i]));
        sum += std::uint64_t(delta);
        d.max = std::max(d.max, delta);
        over += delta > 32 ? 1 : 0;
    }
    d.mean = double(sum) / double(a.rgba.size());
    d.over_32 = double(over) / double(a.rgba.size());
    return d;
}

// A .glb of source.glb's textured quad with images `images` (encoded bytes, each in a
// bufferView) and texture 0 `texture`, its extensions used (and `required`).
std::vector<std::uint8_t> quad_with(const std::vector<std::vector<std::uint8_t>>& images,
                                    const json& texture, const json& required = json::array()) {
    GltfBuilder b;
    const std::vector<glm::vec3> positions{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<glm::vec2> uv{{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    const std::vector<std::uint16_t> indices{0, 1, 2, 0, 2, 3};
    const int uv_accessor =
        b.accessor(b.view(uv.data(), uv.size() * sizeof(glm::vec2)), kFloat, uv.size(), "VEC2");
    b.mesh(json::array(
        {{{"attributes", {{"POSITION", b.positions(positions)}, {"TEXCOORD_0", uv_accessor}}},
          {"indices", b.indices(indices, kUnsignedShort)},
          {"material", 0}}}));
    b.node({{"mesh", 0}});
    b.doc["materials"] =
        json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    b.doc["images"] = json::array();
    for (const std::vector<std::uint8_t>& image : images) {
        b.doc["images"].push_back({{"bufferView", b.view(image.data(), image.size())}});
    }
    b.doc["textures"] = json::array({texture});
    json used = json::array();
    const json extensions = texture.value("extensions", json::object());
    for (const auto& [name, value] : extensions.items()) {
        used.push_back(name);
    }
    if (!used.empty()) {
        b.doc["extensionsUsed"] = used;
    }
    if (!required.empty()) {
        b.doc["extensionsRequired"] = required;
    }
    return b.glb();
}

// The bytes of image `index` of a .glb whose images are in bufferViews of its BIN chunk.
std::vector<std::uint8_t> glb_image(const std::vector<std::uint8_t>& glb, int index) {
    auto u32 = [&](std::size_t at) {
        return std::uint32_t(glb.at(at)) | std::uint32_t(glb.at(at + 1)) << 8 |
               std::uint32_t(glb.at(at + 2)) << 16 | std::uint32_t(glb.at(at + 3)) << 24;
    };
    const std::size_t json_length = u32(12);
    const json doc = json::parse(glb.begin() + 20, glb.begin() + 20 + std::ptrdiff_t(json_length));
    const json& view =
        doc.at("bufferViews").at(doc.at("images").at(index).at("bufferView").get<std::size_t>());
    const std::size_t bin = 20 + json_length + 8;
    const std::size_t offset = bin + view.value("byteOffset", std::size_t(0));
    return {glb.begin() + std::ptrdiff_t(offset),
            glb.begin() + std::ptrdiff_t(offset + view.at("byteLength").get<std::size_t>())};
}

std::span<const std::byte> span_of(const std::vector<std::uint8_t>& bytes) {
    return as_bytes(bytes);
}

bool has_warning(const Mesh& mesh, const std::string& part) {
    return std::any_of(mesh.warnings.begin(), mesh.warnings.end(),
                       [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

// Seconds per call of `body`, the best of `rounds` rounds of `calls` calls each.
double seconds_per_call(const std::function<void()>& body, int calls = 20, int rounds = 3) {
    double best = 1e9;
    for (int round = 0; round < rounds; ++round) {
        const auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < calls; ++i) {
            body();
        }
        best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() /
                      calls);
    }
    return best;
}

// The base colour of `glb` (made by glTF-Transform from source.glb) against source.glb's:
// within `mean` on average, and off by more than 32 (of 255) in at most `over_32` of the
// channels. Lossy coding with 4:2:0 chroma errs little on the source's gradients, more only on
// the hard edges of its discs, stripes and checker.
void expect_close_to_source(const char* glb, const char* extension, double mean, double over_32) {
    const Mesh compressed = load_textured_glb(data_file(glb));
    const Mesh png = load_textured_glb(data_file("source.glb"));
    EXPECT_TRUE(compressed.warnings.empty()) << glb << ": " << compressed.warnings.front();
    ASSERT_EQ(compressed.textures.size(), 1u) << glb;
    const std::vector<std::uint8_t> bytes = data_file(glb);
    ASSERT_NE(std::string(bytes.begin(), bytes.end()).find(extension), std::string::npos)
        << glb << " does not use " << extension;
    const Texture& decoded = base_colour_texture(compressed);
    const Texture& source = base_colour_texture(png);
    ASSERT_EQ(decoded.width, 128) << glb;
    ASSERT_EQ(decoded.height, 128) << glb;
    const Difference d = difference(decoded, source);
    std::cout << "[          ] " << glb << " against its PNG: mean " << d.mean << ", max " << d.max
              << ", " << 100.0 * d.over_32 << " % of channels off by more than 32\n";
    EXPECT_LT(d.mean, mean) << glb;
    EXPECT_LT(d.over_32, over_32) << glb;
    // The source is opaque, and so is what the compressed image decodes to.
    for (std::size_t i = 3; i < decoded.rgba.size(); i += 4) {
        ASSERT_EQ(decoded.rgba[i], 255) << glb << " pixel " << i / 4;
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// WebP and AVIF

TEST(GltfCompressedTextures, WebpFromGltfTransformDecodesCloseToItsSourcePng) {
    // Quality 90: measured mean 3.38, 1.95 % over 32 (2026-12-05, libwebp 1.2.4).
    expect_close_to_source("webp.glb", "EXT_texture_webp", 4.0, 0.025);
}

TEST(GltfCompressedTextures, AvifFromGltfTransformDecodesCloseToItsSourcePng) {
    // Quality 80: measured mean 3.08, 1.82 % over 32 (2026-12-05, libavif 0.11.1 with dav1d).
    expect_close_to_source("avif.glb", "EXT_texture_avif", 3.5, 0.025);
}

TEST(GltfCompressedTextures, WebpAndAvifSourcesArePreferredOverTheFallback) {
    const Mesh png = load_textured_glb(data_file("source.glb"));
    for (const auto& [glb, extension] :
         {std::pair{"webp.glb", "EXT_texture_webp"}, std::pair{"avif.glb", "EXT_texture_avif"}}) {
        const Mesh compressed = load_textured_glb(data_file(glb));
        // The compressed image as image 1, the PNG it was made from as the core source (the
        // fallback): the lossy image's pixels differ from the PNG's, so they tell which was used.
        const json texture = {{"source", 0}, {"extensions", {{extension, {{"source", 1}}}}}};
        const Mesh mesh = load_textured_glb(
            quad_with({data_file("source.png"), glb_image(data_file(glb), 0)}, texture));
        ASSERT_NE(base_colour_texture(compressed).rgba, base_colour_texture(png).rgba) << glb;
        EXPECT_EQ(base_colour_texture(mesh).rgba, base_colour_texture(compressed).rgba) << glb;
        EXPECT_TRUE(mesh.warnings.empty()) << mesh.warnings.front();
    }
    // A texture with both: WebP first (it decodes faster).
    const json both = {
        {"extensions",
         {{"EXT_texture_avif", {{"source", 1}}}, {"EXT_texture_webp", {{"source", 0}}}}}};
    const Mesh mesh = load_textured_glb(quad_with(
        {glb_image(data_file("webp.glb"), 0), glb_image(data_file("avif.glb"), 0)}, both));
    EXPECT_EQ(base_colour_texture(mesh).rgba,
              base_colour_texture(load_textured_glb(data_file("webp.glb"))).rgba);
}

TEST(GltfCompressedTextures, BadExtensionSourcesAreRejectedNamingTheExtension) {
    const std::vector<std::uint8_t> png = data_file("source.png");
    for (const char* extension : {"EXT_texture_webp", "EXT_texture_avif", "KHR_texture_basisu"}) {
        for (const json& source : {json(3), json(-1), json("0"), json(0.5)}) {
            const json texture = {{"source", 0},
                                  {"extensions", {{extension, {{"source", source}}}}}};
            expect_error([&] { load_textured_glb(quad_with({png}, texture)); },
                         ErrorKind::InvalidInput,
                         {std::string("texture 0: extensions.") + extension + ".source"});
        }
    }
}

TEST(GltfCompressedTextures, CompressedAgainstPngSizesAndDecodeTimes) {
    // Not bounds but the figures of renderer/mesh/README.md, printed; the one check: each
    // compressed image is smaller than the PNG.
    const std::vector<std::uint8_t> png = data_file("source.png");
    const double png_s =
        seconds_per_call([&] { (void)mesh_detail::decode_texture(span_of(png), 1 << 20, "png"); });
    std::cout << "[          ] 128x128 RGB: PNG " << png.size() << " bytes, decoded in "
              << png_s * 1e6 << " us\n";
    for (const char* glb : {"webp.glb", "avif.glb"}) {
        const std::vector<std::uint8_t> image = glb_image(data_file(glb), 0);
        const double s = seconds_per_call(
            [&] { (void)mesh_detail::decode_texture(span_of(image), 1 << 20, glb); });
        std::cout << "[          ] " << glb << "'s image: " << image.size() << " bytes, decoded in "
                  << s * 1e6 << " us\n";
        EXPECT_LT(image.size(), png.size()) << glb;
    }
    for (const char* ktx2 : {"etc1s.ktx2", "uastc-zstd.ktx2"}) {
        std::cout << "[          ] " << ktx2 << " (with its mipmaps): " << data_file(ktx2).size()
                  << " bytes, not decoded\n";
    }
}

// ---------------------------------------------------------------------------------------------
// KTX2 (KHR_texture_basisu)

TEST(GltfCompressedTextures, Ktx2HeadersOfBasisuAreReadAndTheirPayloadNamed) {
    for (const auto& [name, payload] :
         {std::pair{"etc1s.ktx2", "Basis Universal ETC1S"},
          std::pair{"uastc-zstd.ktx2", "Basis Universal UASTC, Zstandard-supercompressed"}}) {
        const std::vector<std::uint8_t> ktx2 = data_file(name);
        const mesh_detail::ImageHeader header =
            mesh_detail::check_image_header(span_of(ktx2), 1 << 20, name);
        EXPECT_EQ(header.format, mesh_detail::ImageFormat::Ktx2) << name;
        EXPECT_EQ(header.width, 128) << name;
        EXPECT_EQ(header.height, 128) << name;
        const std::string what = name;  // clang 14 captures no structured binding
        expect_error([&] { mesh_detail::decode_texture(span_of(ktx2), 1 << 20, what); },
                     ErrorKind::Unsupported,
                     {std::string(name) + ": KTX2 textures (KHR_texture_basisu; this one " +
                      payload + ") are not supported"});
    }
}

TEST(GltfCompressedTextures, Ktx2TextureWithAFallbackShowsTheFallbackAndSaysSo) {
    const std::vector<std::uint8_t> png = data_file("source.png");
    const Mesh reference = load_textured_glb(data_file("source.glb"));
    for (const char* name : {"etc1s.ktx2", "uastc-zstd.ktx2"}) {
        const json texture = {{"source", 0},
                              {"extensions", {{"KHR_texture_basisu", {{"source", 1}}}}}};
        const Mesh mesh = load_textured_glb(quad_with({png, data_file(name)}, texture));
        EXPECT_EQ(base_colour_texture(mesh).rgba, base_colour_texture(reference).rgba) << name;
        EXPECT_TRUE(has_warning(mesh,
                                "baseColorTexture (texture 0): its KTX2 source "
                                "(KHR_texture_basisu) is not decoded"))
            << name;
        // The extension itself is reported as unsupported, once.
        EXPECT_TRUE(has_warning(mesh,
                                "the asset uses the extension KHR_texture_basisu, which is "
                                "not supported"))
            << name;
    }
}

TEST(GltfCompressedTextures, Ktx2TextureWithoutFallbackIsIgnoredOrRefusedWhenRequired) {
    const std::vector<std::uint8_t> ktx2 = data_file("etc1s.ktx2");
    const json texture = {{"extensions", {{"KHR_texture_basisu", {{"source", 0}}}}}};
    const Mesh mesh = load_textured_glb(quad_with({ktx2}, texture));
    EXPECT_FALSE(mesh.materials.at(0).base_color_texture.present());
    EXPECT_TRUE(has_warning(mesh,
                            "baseColorTexture (texture 0) has only a KTX2 source "
                            "(KHR_texture_basisu)"));
    expect_error(
        [&] { load_textured_glb(quad_with({ktx2}, texture, json::array({"KHR_texture_basisu"}))); },
        ErrorKind::Unsupported,
        {"test.glb: the asset requires the extension KHR_texture_basisu, which is not "
         "supported"});
}

TEST(GltfCompressedTextures, OtherFormatsAreRefusedByName) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {std::string("\0\0\0\x1c"
                     "ftypheic\0\0\0\0",
                     16),
         "HEIF images"},
        {"GIF89a\x02\0\x02\0", "GIF images"},
        {std::string("\xabKTX 11\xbb\r\n\x1a\n", 12), "KTX 1 images"},
        {"not an image at all", "the image's format is not recognised"}};
    for (const auto& [bytes, named] : cases) {
        expect_error(
            [&, &bytes = bytes] {  // clang 14 captures no structured binding
                mesh_detail::check_image_header(as_bytes(bytes), 1 << 20, "image 0");
            },
            ErrorKind::Unsupported,
            {"image 0: " + named,
             "textures are PNG, JPEG, WebP (EXT_texture_webp) or AVIF (EXT_texture_avif)"});
    }
}

// ---------------------------------------------------------------------------------------------
// Hostile images: each refused with its kind of error and a message saying what is wrong,
// within a second and without the memory its claim would take (resident growth under 16 MiB,
// held where the resident set is the program's own, not under AddressSanitizer).

namespace {

void put_u32(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint32_t value) {
    for (std::size_t i = 0; i < 4; ++i) {
        bytes.at(at + i) = std::uint8_t(value >> (8 * i));
    }
}

// A RIFF WebP holding one chunk `fourcc` of `payload`.
std::vector<std::uint8_t> webp_of(const char* fourcc, std::vector<std::uint8_t> payload) {
    payload.resize(payload.size() + payload.size() % 2);
    std::vector<std::uint8_t> bytes(20);
    std::copy_n("RIFF", 4, bytes.begin());
    put_u32(bytes, 4, std::uint32_t(12 + payload.size()));
    std::copy_n("WEBP", 4, bytes.begin() + 8);
    std::copy_n(fourcc, 4, bytes.begin() + 12);
    put_u32(bytes, 16, std::uint32_t(payload.size()));
    bytes.insert(bytes.end(), payload.begin(), payload.end());
    return bytes;
}

// Lossless (VP8L, WebP Lossless Bitstream Specification, section 3): the signature 0x2f, then
// 14 bits of width - 1, 14 of height - 1, the alpha hint and a 3-bit version (0).
std::vector<std::uint8_t> vp8l_claiming(std::uint32_t width, std::uint32_t height) {
    std::vector<std::uint8_t> payload(16, 0);
    payload[0] = 0x2f;
    put_u32(payload, 1, (width - 1) | (height - 1) << 14);
    return webp_of("VP8L", payload);
}

// Lossy (VP8, RFC 6386 section 9.1): a key frame's 3-byte tag (key frame, version 0, shown,
// first partition of 1 byte), the start code 9d 01 2a, 14-bit width and height.
std::vector<std::uint8_t> vp8_claiming(std::uint32_t width, std::uint32_t height) {
    std::vector<std::uint8_t> payload(16, 0);
    const std::uint32_t tag = 0u | 0u << 1 | 1u << 4 | 1u << 5;
    payload[0] = std::uint8_t(tag);
    payload[1] = std::uint8_t(tag >> 8);
    payload[2] = std::uint8_t(tag >> 16);
    payload[3] = 0x9d;
    payload[4] = 0x01;
    payload[5] = 0x2a;
    payload[6] = std::uint8_t(width);
    payload[7] = std::uint8_t(width >> 8);
    payload[8] = std::uint8_t(height);
    payload[9] = std::uint8_t(height >> 8);
    return webp_of("VP8 ", payload);
}

// etc1s.ktx2 with the 32-bit header field at `at` set to `value` (20: pixelWidth, 24:
// pixelHeight, 36: faceCount, 40: levelCount; KTX 2.0 section 3).
std::vector<std::uint8_t> ktx2_with(std::size_t at, std::uint32_t value) {
    std::vector<std::uint8_t> bytes = data_file("etc1s.ktx2");
    put_u32(bytes, at, value);
    return bytes;
}

// Loads `image` as the only image of the quad (texture 0 showing it under `extension`, or as
// its core source), expecting `kind` and `parts`, and bounds the time and memory it took.
void expect_refused(const std::string& what, const std::vector<std::uint8_t>& image,
                    const char* extension, ErrorKind kind, const std::vector<std::string>& parts) {
    const json texture = extension == nullptr
                             ? json{{"source", 0}}
                             : json{{"extensions", {{extension, {{"source", 0}}}}}};
    const std::vector<std::uint8_t> glb = quad_with({image}, texture);
    malloc_trim(0);
    EXPECT_TRUE(oer::testing::reset_peak_resident());
    const long before = oer::testing::resident_kib();
    const auto start = std::chrono::steady_clock::now();
    expect_error([&] { load_textured_glb(glb); }, kind, parts);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const long grown = oer::testing::peak_resident_kib() - before;
    std::cout << "[          ] " << what << " (" << image.size() << " bytes): " << seconds * 1e3
              << " ms, resident +" << grown << " KiB\n";
    EXPECT_LT(seconds, 1.0) << what;
    if (oer::testing::kResidentMemoryIsTheProgramsOwn) {
        EXPECT_LT(grown, 16 << 10) << what;
    }
}

}  // namespace

TEST(GltfCompressedTexturesHostile, WebpBombsAreRefusedOnTheirHeader) {
    // 16383 x 16383 is the most either bitstream can declare: 1 GiB as RGBA, in 36 bytes.
    expect_refused("VP8L claiming 16383x16383", vp8l_claiming(16383, 16383), "EXT_texture_webp",
                   ErrorKind::LimitExceeded,
                   {"test.glb: image 0: the image is 16383x16383 pixels, more than the limit of "
                    "16777216 pixels"});
    expect_refused("VP8 claiming 16383x16383", vp8_claiming(16383, 16383), "EXT_texture_webp",
                   ErrorKind::LimitExceeded, {"the image is 16383x16383 pixels"});
    // Within the limit the header is accepted, and the buffer of its size allocated; the
    // missing pixels are found while decoding.
    expect_refused("VP8L claiming 1024x1024", vp8l_claiming(1024, 1024), "EXT_texture_webp",
                   ErrorKind::InvalidInput, {"test.glb: image 0: the image cannot be decoded"});
}

TEST(GltfCompressedTexturesHostile, TruncatedAndDamagedWebpAreNamedSo) {
    const std::vector<std::uint8_t> webp = glb_image(data_file("webp.glb"), 0);
    const std::vector<std::uint8_t> half(webp.begin(),
                                         webp.begin() + std::ptrdiff_t(webp.size() / 2));
    expect_refused("WebP cut in half", half, "EXT_texture_webp", ErrorKind::InvalidInput,
                   {"test.glb: image 0: the image cannot be decoded (truncated WebP: the "
                    "bitstream ends early)"});
    const std::vector<std::uint8_t> header_only(webp.begin(), webp.begin() + 24);
    expect_refused("WebP of its first 24 bytes", header_only, "EXT_texture_webp",
                   ErrorKind::InvalidInput, {"test.glb: image 0: truncated WebP"});
    std::vector<std::uint8_t> no_start_code = vp8_claiming(64, 64);
    no_start_code[20 + 3] = 0;
    expect_refused("VP8 without its start code", no_start_code, "EXT_texture_webp",
                   ErrorKind::InvalidInput,
                   {"test.glb: image 0: damaged WebP header (corrupt WebP bitstream)"});
}

TEST(GltfCompressedTexturesHostile, Ktx2ClaimsBeyondTheLimitsOrTheFileAreRefused) {
    // As a core source (no extension), as in a texture's fallback: every image is checked.
    std::vector<std::uint8_t> square = ktx2_with(20, 65536);
    put_u32(square, 24, 65536);
    expect_refused("KTX2 claiming 65536x65536", square, nullptr, ErrorKind::LimitExceeded,
                   {"test.glb: image 0: the image is 65536x65536 pixels, more than the limit of "
                    "16777216 pixels"});
    std::vector<std::uint8_t> over = ktx2_with(20, 4097);
    put_u32(over, 24, 4097);
    expect_refused("KTX2 claiming 4097x4097", over, "KHR_texture_basisu", ErrorKind::LimitExceeded,
                   {"the image is 4097x4097 pixels"});
    expect_refused("KTX2 claiming 65536 levels", ktx2_with(40, 65536), "KHR_texture_basisu",
                   ErrorKind::InvalidInput,
                   {"test.glb: image 0: the KTX2 header claims 65536 mip levels, a 128x128 "
                    "image has at most 8"});
    expect_refused("KTX2 cube map", ktx2_with(36, 6), "KHR_texture_basisu", ErrorKind::Unsupported,
                   {"a KTX2 texture of glTF is one 2D image (KHR_texture_basisu), this one has "
                    "pixelDepth 0, layerCount 0 and faceCount 6"});
    const std::vector<std::uint8_t> ktx2 = data_file("etc1s.ktx2");
    for (const auto& [size, message] :
         {std::pair{std::size_t(60), "truncated KTX2: 60 bytes, fewer than its 80-byte header"},
          std::pair{std::size_t(200),
                    "truncated KTX2: its level index of 8 levels runs past "
                    "the end of the file"},
          std::pair{std::size_t(2000), "truncated KTX2: level 0 ("}}) {
        const std::vector<std::uint8_t> cut(ktx2.begin(), ktx2.begin() + std::ptrdiff_t(size));
        expect_refused("KTX2 cut to " + std::to_string(size) + " bytes", cut, "KHR_texture_basisu",
                       ErrorKind::InvalidInput, {std::string("test.glb: image 0: ") + message});
    }
}

TEST(GltfCompressedTexturesHostile, AvifClaimsBeyondTheLimitsOrTheFileAreRefused) {
    const std::vector<std::uint8_t> avif = glb_image(data_file("avif.glb"), 0);
    // The image spatial extents property ("ispe": version and flags, then width and height,
    // 32-bit big-endian; ISO/IEC 23008-12 section 6.5.3) set to 16000 x 16000: 1 GiB as RGBA,
    // under libavif's own limit of 16384 x 16384, over ours.
    const std::string text(avif.begin(), avif.end());
    const std::size_t ispe = text.find("ispe");
    ASSERT_NE(ispe, std::string::npos);
    std::vector<std::uint8_t> bomb = avif;
    for (const std::size_t at : {ispe + 8, ispe + 12}) {
        bomb[at] = 0;
        bomb[at + 1] = 0;
        bomb[at + 2] = 16000 >> 8;
        bomb[at + 3] = 16000 & 0xff;
    }
    expect_refused("AVIF claiming 16000x16000", bomb, "EXT_texture_avif", ErrorKind::LimitExceeded,
                   {"test.glb: image 0: the image is 16000x16000 pixels, more than the limit of "
                    "16777216 pixels"});
    const std::vector<std::uint8_t> head(avif.begin(), avif.begin() + 40);
    expect_refused("AVIF of its first 40 bytes", head, "EXT_texture_avif", ErrorKind::InvalidInput,
                   {"test.glb: image 0: truncated AVIF"});
    // Cut in half, its item's extents run past the end: libavif says so in its own words.
    const std::vector<std::uint8_t> half(avif.begin(),
                                         avif.begin() + std::ptrdiff_t(avif.size() / 2));
    expect_refused("AVIF cut in half", half, "EXT_texture_avif", ErrorKind::InvalidInput,
                   {"test.glb: image 0: damaged AVIF container (BMFF parsing failed: Exceeded "
                    "avifIO's sizeHint, possibly truncated data)"});
    // The AV1 data's first OBUs (its sequence header, at the start of the "mdat" box's payload)
    // overwritten: the container parses, the AV1 decoder refuses. (Damage later in the frame
    // data decodes, to other pixels: AV1 has no checksum.)
    std::vector<std::uint8_t> corrupt = avif;
    const std::size_t mdat = text.find("mdat");
    ASSERT_NE(mdat, std::string::npos);
    std::fill_n(corrupt.begin() + std::ptrdiff_t(mdat + 4), 16, std::uint8_t(0xff));
    expect_refused("AVIF with a corrupt AV1 sequence header", corrupt, "EXT_texture_avif",
                   ErrorKind::InvalidInput,
                   {"test.glb: image 0: the image cannot be decoded (corrupt AVIF: Decoding of "
                    "color planes failed"});
}
