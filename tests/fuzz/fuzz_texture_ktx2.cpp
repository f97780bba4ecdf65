// KTX2 textures of glTF (KHR_texture_basisu): the container's header and layout checks
// (renderer/mesh/src/texture_ktx2.cpp: the pixel limit, 2D only, the mip levels a size has, the
// level index and every level inside the file), then the refusal to decode that names the
// payload (no Basis Universal transcoder in the build), as texture_decoding_target.hpp says.
#include <cstddef>
#include <cstdint>

#include "texture_decoding_target.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    oer::fuzz::parse_or_refuse([&] {
        oer::fuzz::decode_texture_image(oer::fuzz::as_bytes(data, size),
                                        oer::mesh_detail::ImageFormat::Ktx2);
    });
    return 0;
}
