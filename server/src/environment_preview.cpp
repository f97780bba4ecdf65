#include "environment_preview.hpp"

#include <algorithm>

#include "oer/core/error.hpp"
#include "oer/image/image_encoding.hpp"
#include "oer/lighting/light_overlay.hpp"
#include "oer/lighting/tonemap.hpp"

namespace oer::server {

namespace {

// The source columns (or rows) [first, last) that output pixel i of n covers; at least one.
std::pair<int, int> footprint(int i, int n, int source) {
    const int first = int(std::int64_t(i) * source / n);
    const int last = std::max(first + 1, int(std::int64_t(i + 1) * source / n));
    return {first, std::min(last, source)};
}

// Area average (nearest when enlarging).
HdrImage reduce(const HdrImage& map, int width, int height) {
    HdrImage out(width, height);
    for (int y = 0; y < height; ++y) {
        const auto [y0, y1] = footprint(y, height, map.height);
        for (int x = 0; x < width; ++x) {
            const auto [x0, x1] = footprint(x, width, map.width);
            glm::dvec3 sum(0.0);
            for (int sy = y0; sy < y1; ++sy) {
                for (int sx = x0; sx < x1; ++sx) {
                    const float* p = map.at(sx, sy);
                    sum += glm::dvec3(p[0], p[1], p[2]);
                }
            }
            out.set(std::size_t(y) * width + x, glm::vec3(sum / double((y1 - y0) * (x1 - x0))));
        }
    }
    return out;
}

// The lights with their pixels mapped onto the preview's grid.
std::vector<Light> reduced_lights(const Rig& rig, int width, int height) {
    std::vector<Light> lights;
    for (const Light& light : rig.lights) {
        Light reduced = light;
        reduced.pixels.clear();
        for (const std::uint32_t index : light.pixels) {
            const std::int64_t x = index % std::uint32_t(rig.source_width);
            const std::int64_t y = index / std::uint32_t(rig.source_width);
            reduced.pixels.push_back(std::uint32_t((y * height / rig.source_height) * width +
                                                   x * width / rig.source_width));
        }
        std::sort(reduced.pixels.begin(), reduced.pixels.end());
        reduced.pixels.erase(std::unique(reduced.pixels.begin(), reduced.pixels.end()),
                             reduced.pixels.end());
        lights.push_back(std::move(reduced));
    }
    return lights;
}

}  // namespace

std::string preview_jpeg(const HdrImage& map, const Rig& rig) {
    if (map.width != rig.source_width || map.height != rig.source_height) {
        throw Error(ErrorKind::Internal, "preview: the map is " + std::to_string(map.width) + "x" +
                                             std::to_string(map.height) + ", its rig's " +
                                             std::to_string(rig.source_width) + "x" +
                                             std::to_string(rig.source_height));
    }
    const HdrImage display =
        to_display(reduce(map, kPreviewWidth, kPreviewHeight), 0.0, ToneMapper::Neutral);
    const HdrImage overlay =
        draw_light_overlay(display, reduced_lights(rig, kPreviewWidth, kPreviewHeight));
    Rgba8Image image{kPreviewWidth, kPreviewHeight,
                     std::vector<std::uint8_t>(std::size_t(kPreviewWidth) * kPreviewHeight * 4)};
    for (std::size_t i = 0; i < overlay.pixel_count(); ++i) {
        for (int c = 0; c < 3; ++c) {
            image.pixels[i * 4 + c] =
                std::uint8_t(std::clamp(overlay.pixels[i * 3 + c], 0.0f, 1.0f) * 255.0f + 0.5f);
        }
        image.pixels[i * 4 + 3] = 255;
    }
    const std::vector<std::uint8_t> jpeg = encode_jpeg(image, 90);
    return std::string(jpeg.begin(), jpeg.end());
}

}  // namespace oer::server
