// AVIF textures of glTF (EXT_texture_avif): the container's parse (libavif, its size against the
// pixel limit before any AV1 data is decoded) and the decode into the loader's buffer
// (renderer/mesh/src/texture_avif.cpp), as texture_decoding_target.hpp says.
#include <cstddef>
#include <cstdint>

#include "texture_decoding_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    oer::fuzz::parse_or_refuse([&] {
        oer::fuzz::decode_texture_image(oer::fuzz::as_bytes(data, size),
                                        oer::mesh_detail::ImageFormat::Avif);
    });
    return 0;
}
