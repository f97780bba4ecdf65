#include "spin_set.hpp"

#include <webp/encode.h>
#include <webp/mux.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "oer/core/error.hpp"

namespace oer::server {

namespace {

void check_same_size(const std::vector<Rgba8Image>& views) {
    if (views.empty()) {
        throw Error(ErrorKind::InvalidInput, "a spin set needs at least one view");
    }
    for (const Rgba8Image& view : views) {
        if (view.width != views.front().width || view.height != views.front().height) {
            throw Error(ErrorKind::InvalidInput, "a spin set's views must share one size");
        }
    }
}

}  // namespace

std::string animated_webp(const std::vector<Rgba8Image>& views, int frame_ms, int quality) {
    check_same_size(views);
    WebPAnimEncoderOptions options;
    WebPConfig config;
    if (!WebPAnimEncoderOptionsInit(&options) || !WebPConfigInit(&config)) {
        throw Error(ErrorKind::Internal, "libwebp: version mismatch");
    }
    options.anim_params.loop_count = 0;  // for ever
    config.quality = float(std::clamp(quality, 1, 100));
    const std::unique_ptr<WebPAnimEncoder, void (*)(WebPAnimEncoder*)> encoder(
        WebPAnimEncoderNew(views.front().width, views.front().height, &options),
        WebPAnimEncoderDelete);
    if (!encoder) {
        throw Error(ErrorKind::Internal, "libwebp: cannot make an animation encoder");
    }
    int timestamp = 0;
    for (const Rgba8Image& view : views) {
        WebPPicture picture;
        if (!WebPPictureInit(&picture)) {
            throw Error(ErrorKind::Internal, "libwebp: version mismatch");
        }
        picture.width = view.width;
        picture.height = view.height;
        picture.use_argb = 1;
        const bool imported = WebPPictureImportRGBA(&picture, view.pixels.data(), view.width * 4);
        const bool added =
            imported && WebPAnimEncoderAdd(encoder.get(), &picture, timestamp, &config);
        WebPPictureFree(&picture);
        if (!added) {
            throw Error(ErrorKind::Internal, std::string("libwebp: cannot add a view: ") +
                                                 WebPAnimEncoderGetError(encoder.get()));
        }
        timestamp += frame_ms;
    }
    // The end of the last view's time.
    WebPData data;
    WebPDataInit(&data);
    if (!WebPAnimEncoderAdd(encoder.get(), nullptr, timestamp, nullptr) ||
        !WebPAnimEncoderAssemble(encoder.get(), &data)) {
        throw Error(ErrorKind::Internal, std::string("libwebp: cannot assemble the animation: ") +
                                             WebPAnimEncoderGetError(encoder.get()));
    }
    std::string bytes(reinterpret_cast<const char*>(data.bytes), data.size);
    WebPDataClear(&data);
    return bytes;
}

Rgba8Image sprite_sheet(const std::vector<Rgba8Image>& views, int columns) {
    check_same_size(views);
    const int width = views.front().width;
    const int height = views.front().height;
    const int rows = (int(views.size()) + columns - 1) / columns;
    Rgba8Image sheet;
    sheet.width = width * columns;
    sheet.height = height * rows;
    sheet.pixels.assign(std::size_t(sheet.width) * std::size_t(sheet.height) * 4, 0);
    for (std::size_t i = 0; i < views.size(); ++i) {
        const std::size_t left = (i % std::size_t(columns)) * std::size_t(width);
        const std::size_t top = (i / std::size_t(columns)) * std::size_t(height);
        for (int y = 0; y < height; ++y) {
            std::memcpy(
                &sheet.pixels[((top + std::size_t(y)) * std::size_t(sheet.width) + left) * 4],
                &views[i].pixels[std::size_t(y) * std::size_t(width) * 4], std::size_t(width) * 4);
        }
    }
    return sheet;
}

}  // namespace oer::server
