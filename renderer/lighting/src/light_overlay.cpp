#include "oer/lighting/light_overlay.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>

#include "oer/core/error.hpp"
#include "oer/lighting/equirect.hpp"

namespace oer {

namespace {

// 3x5 bitmap digits, one row per 3-bit number, most significant bit on the left.
constexpr std::array<std::array<std::uint8_t, 5>, 10> kDigits = {{
    {7, 5, 5, 5, 7},
    {2, 6, 2, 2, 7},
    {7, 1, 7, 4, 7},
    {7, 1, 7, 1, 7},
    {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7},
    {7, 4, 7, 5, 7},
    {7, 1, 1, 1, 1},
    {7, 5, 7, 5, 7},
    {7, 5, 7, 1, 7},
}};

constexpr std::array<glm::vec3, 6> kColors = {{
    {1.0f, 0.2f, 0.2f},
    {0.2f, 1.0f, 0.2f},
    {0.3f, 0.5f, 1.0f},
    {1.0f, 1.0f, 0.2f},
    {1.0f, 0.2f, 1.0f},
    {0.2f, 1.0f, 1.0f},
}};

void fill(HdrImage& image, int x0, int y0, int size, glm::vec3 color) {
    for (int y = std::max(0, y0); y < std::min(image.height, y0 + size); ++y) {
        for (int x = std::max(0, x0); x < std::min(image.width, x0 + size); ++x) {
            image.set(std::size_t(y) * image.width + x, color);
        }
    }
}

void draw_number(HdrImage& image, int number, int x, int y, int scale, glm::vec3 color) {
    const std::string text = std::to_string(number);
    const int width = int(text.size()) * 4 * scale;
    x = std::clamp(x, 0, std::max(0, image.width - width));
    y = std::clamp(y, 0, std::max(0, image.height - 5 * scale));
    // A dark backing box keeps the digits legible over bright light pixels.
    for (int by = y - scale; by < y + 6 * scale; by += scale) {
        for (int bx = x - scale; bx < x + width; bx += scale) {
            fill(image, bx, by, scale, glm::vec3(0.0f));
        }
    }
    for (std::size_t c = 0; c < text.size(); ++c) {
        const auto& glyph = kDigits[text[c] - '0'];
        for (int row = 0; row < 5; ++row) {
            for (int column = 0; column < 3; ++column) {
                if (glyph[row] & (4 >> column)) {
                    fill(image, x + (int(c) * 4 + column) * scale, y + row * scale, scale, color);
                }
            }
        }
    }
}

}  // namespace

HdrImage draw_light_overlay(const HdrImage& display, const std::vector<Light>& lights) {
    const int w = display.width, h = display.height;
    if (lights.size() > 255) {
        throw Error(ErrorKind::InvalidInput,
                    "too many lights to draw: " + std::to_string(lights.size()));
    }
    std::vector<std::uint8_t> label(display.pixel_count(), 0);
    for (std::size_t k = 0; k < lights.size(); ++k) {
        for (const std::uint32_t index : lights[k].pixels) {
            if (index >= label.size()) {
                throw Error(ErrorKind::InvalidInput, "light pixel outside the image");
            }
            label[index] = std::uint8_t(k + 1);
        }
    }
    HdrImage out = display;
    const int thickness = std::max(1, h / 256);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::uint8_t own = label[std::size_t(y) * w + x];
            if (own == 0) {
                continue;
            }
            // Outline: a mask pixel with a 4-neighbour outside the mask (wrapping at the seam).
            const bool edge = label[std::size_t(y) * w + (x + 1) % w] != own ||
                              label[std::size_t(y) * w + (x + w - 1) % w] != own ||
                              (y > 0 && label[std::size_t(y - 1) * w + x] != own) ||
                              (y + 1 < h && label[std::size_t(y + 1) * w + x] != own);
            if (edge) {
                fill(out, x - thickness / 2, y - thickness / 2, thickness,
                     kColors[(own - 1) % kColors.size()]);
            }
        }
    }
    const int scale = std::max(1, h / 128);
    for (std::size_t k = 0; k < lights.size(); ++k) {
        const glm::dvec2 centre = equirect::position_of(lights[k].direction, w, h);
        const int offset = int(lights[k].angular_radius / 3.14159265358979 * h) + 2 * scale;
        draw_number(out, int(k + 1), int(centre.x) + offset, int(centre.y) - offset - 5 * scale,
                    scale, kColors[k % kColors.size()]);
    }
    return out;
}

}  // namespace oer
