#include "oer/api/frame_encoding.hpp"

#include "oer/core/error.hpp"
#include "oer/image/image_encoding.hpp"

namespace oer::api {

std::vector<std::uint8_t> encode(const Frame& frame, ImageFormat format, int quality) {
    switch (format) {
        case ImageFormat::Jpeg:
            return encode_jpeg(frame.display, quality);
        case ImageFormat::Png:
            return encode_png(frame.display);
        case ImageFormat::Exr:
            return encode_exr(frame.width, frame.height, frame.linear);
    }
    throw Error(ErrorKind::Internal, "unknown image format");
}

std::string content_type_of(ImageFormat format) {
    switch (format) {
        case ImageFormat::Jpeg:
            return "image/jpeg";
        case ImageFormat::Png:
            return "image/png";
        case ImageFormat::Exr:
            return "image/x-exr";
    }
    throw Error(ErrorKind::Internal, "unknown image format");
}

}  // namespace oer::api
