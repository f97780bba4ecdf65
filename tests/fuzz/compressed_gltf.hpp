#pragma once
// What fuzz_gltf_meshopt and fuzz_gltf_draco share: the fuzzer's bytes wrapped as the
// compressed data of a .glb that the harness writes around them (so that every input reaches
// the decoder, not the JSON parser), loaded as an upload (mesh_upload.hpp: the limits kept, the
// resident growth within the upload's bound, here the bound for the whole .glb).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh_upload.hpp"

namespace oer::fuzz {

// Little-endian unsigned of `bytes` bytes at `at` of `data`.
inline std::uint64_t little_endian(std::span<const std::uint8_t> data, std::size_t at,
                                   std::size_t bytes) {
    std::uint64_t value = 0;
    for (std::size_t i = 0; i < bytes; ++i) {
        value |= std::uint64_t(data[at + i]) << (8 * i);
    }
    return value;
}

// A .glb of the JSON `document` (its "buffers" set here: buffer 0 the BIN chunk `bin`, then
// `extra_buffers`).
inline std::vector<std::byte> make_glb(nlohmann::json document, std::span<const std::uint8_t> bin,
                                       const nlohmann::json& extra_buffers) {
    document["asset"] = {{"version", "2.0"}};
    document["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
    for (const auto& buffer : extra_buffers) {
        document["buffers"].push_back(buffer);
    }
    std::string text = document.dump();
    while (text.size() % 4 != 0) {
        text += ' ';
    }
    const std::size_t padded = (bin.size() + 3) / 4 * 4;
    std::vector<std::byte> out;
    const auto u32 = [&out](std::size_t value) {
        for (int i = 0; i < 4; ++i) {
            out.push_back(std::byte((value >> (8 * i)) & 0xff));
        }
    };
    for (char c : std::string("glTF")) {
        out.push_back(std::byte(c));
    }
    u32(2);
    u32(12 + 8 + text.size() + 8 + padded);
    u32(text.size());
    for (char c : std::string("JSON") + text) {
        out.push_back(std::byte(c));
    }
    u32(padded);
    for (char c : std::string("BIN", 4)) {
        out.push_back(std::byte(c));
    }
    for (std::uint8_t b : bin) {
        out.push_back(std::byte(b));
    }
    out.resize(out.size() + (padded - bin.size()), std::byte(0));
    return out;
}

}  // namespace oer::fuzz
