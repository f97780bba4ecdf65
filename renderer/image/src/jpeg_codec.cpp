#include "jpeg_codec.hpp"

#include <turbojpeg.h>

#include <memory>
#include <string>

#include "oer/core/error.hpp"

namespace oer::jpeg_detail {

namespace {

struct HandleDeleter {
    void operator()(void* handle) const { tjDestroy(handle); }
};
using Handle = std::unique_ptr<void, HandleDeleter>;

// One compressor and one decompressor per thread, made on first use (each holds libjpeg's
// state and buffers: creating them for every frame costs more than a small frame's encode).
tjhandle thread_handle(bool compress) {
    thread_local Handle compressor;
    thread_local Handle decompressor;
    Handle& handle = compress ? compressor : decompressor;
    if (!handle) {
        handle.reset(compress ? tjInitCompress() : tjInitDecompress());
        if (!handle) {
            throw Error(ErrorKind::Internal, std::string("TurboJPEG: cannot create a ") +
                                                 (compress ? "compressor" : "decompressor") + ": " +
                                                 tjGetErrorStr2(nullptr));
        }
    }
    return handle.get();
}

}  // namespace

std::vector<std::uint8_t> encode(const Rgba8Image& image, int quality) {
    tjhandle handle = thread_handle(true);
    const bool high = quality >= 90;
    const int subsampling = high ? TJSAMP_444 : TJSAMP_420;
    // Compress straight into a buffer of the worst-case size, then shrink it: no copy.
    std::vector<std::uint8_t> bytes(tjBufSize(image.width, image.height, subsampling));
    unsigned char* destination = bytes.data();
    unsigned long size = bytes.size();
    const int flags = TJFLAG_NOREALLOC | (high ? TJFLAG_ACCURATEDCT : 0);
    if (tjCompress2(handle, image.pixels.data(), image.width, 0, image.height, TJPF_RGBA,
                    &destination, &size, subsampling, quality, flags) != 0) {
        throw Error(ErrorKind::Internal,
                    std::string("JPEG encoding failed: ") + tjGetErrorStr2(handle));
    }
    bytes.resize(size);
    return bytes;
}

Rgba8Image decode(std::span<const std::uint8_t> bytes, std::uint64_t max_pixels) {
    tjhandle handle = thread_handle(false);
    int width = 0, height = 0, subsampling = 0, colorspace = 0;
    if (tjDecompressHeader3(handle, bytes.data(), static_cast<unsigned long>(bytes.size()), &width,
                            &height, &subsampling, &colorspace) != 0) {
        throw Error(ErrorKind::InvalidInput,
                    std::string("not a readable JPEG: ") + tjGetErrorStr2(handle));
    }
    if (width <= 0 || height <= 0) {
        throw Error(ErrorKind::InvalidInput,
                    "JPEG of size " + std::to_string(width) + "x" + std::to_string(height));
    }
    if (std::uint64_t(width) * std::uint64_t(height) > max_pixels) {
        throw Error(ErrorKind::LimitExceeded,
                    "JPEG of " + std::to_string(width) + "x" + std::to_string(height) +
                        " pixels is over the limit of " + std::to_string(max_pixels) + " pixels");
    }
    Rgba8Image image;
    image.width = width;
    image.height = height;
    image.pixels.resize(std::size_t(width) * std::size_t(height) * 4);
    // A warning (premature end of data, corrupt entropy data) is an error: the image would be
    // partly grey. Progressive scans are limited (libjpeg-turbo's guard against scan bombs).
    if (tjDecompress2(handle, bytes.data(), static_cast<unsigned long>(bytes.size()),
                      image.pixels.data(), width, 0, height, TJPF_RGBA,
                      TJFLAG_STOPONWARNING | TJFLAG_LIMITSCANS | TJFLAG_ACCURATEDCT) != 0) {
        throw Error(ErrorKind::InvalidInput, "corrupt JPEG (" + std::to_string(width) + "x" +
                                                 std::to_string(height) +
                                                 "): " + tjGetErrorStr2(handle));
    }
    return image;
}

}  // namespace oer::jpeg_detail
