#pragma once
// A linear-radiance RGB float image, row-major, y down, interleaved RGB.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace oer {

struct HdrImage {
    int width = 0;
    int height = 0;
    std::vector<float> pixels;  // width * height * 3 floats

    HdrImage() = default;
    HdrImage(int w, int h)
        : width(w), height(h), pixels(std::size_t(w) * std::size_t(h) * 3, 0.0f) {}

    std::size_t pixel_count() const { return std::size_t(width) * std::size_t(height); }
    float* at(int x, int y) { return &pixels[(std::size_t(y) * std::size_t(width) + x) * 3]; }
    const float* at(int x, int y) const {
        return &pixels[(std::size_t(y) * std::size_t(width) + x) * 3];
    }
    glm::vec3 rgb(std::size_t index) const {
        return {pixels[index * 3], pixels[index * 3 + 1], pixels[index * 3 + 2]};
    }
    void set(std::size_t index, glm::vec3 value) {
        pixels[index * 3] = value.r;
        pixels[index * 3 + 1] = value.g;
        pixels[index * 3 + 2] = value.b;
    }
};

// An 8-bit display image, row 0 at the top, RGBA (alpha 255 where opaque). Alpha is straight
// (color not multiplied by alpha), as PNG stores it.
struct Rgba8Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;  // width * height * 4
};

}  // namespace oer
