// WebP textures of glTF (EXT_texture_webp): the header check (WebPGetFeatures against the pixel
// limit) and libwebp's decode into the loader's buffer (renderer/mesh/src/texture_webp.cpp),
// as texture_decoding_target.hpp says.
#include <cstddef>
#include <cstdint>

#include "texture_decoding_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    oer::fuzz::parse_or_refuse([&] {
        oer::fuzz::decode_texture_image(oer::fuzz::as_bytes(data, size),
                                        oer::mesh_detail::ImageFormat::Webp);
    });
    return 0;
}
