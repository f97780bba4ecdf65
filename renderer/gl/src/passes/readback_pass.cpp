// Readback. Reads: `finished`, the finished frame, bottom row first as GL keeps it. Writes:
// result.linear (RGBA float radiance) or result.display (RGBA8 sRGB), top row first. Leaves GL
// as a frame found it: the default framebuffer, depth writes on, no vertex array, program or
// shadow samplers (gl_bindings.hpp's kShadowMaps and kShadowDepths) bound.
#include <cstring>
#include <vector>

#include "gl_bindings.hpp"
#include "passes/frame_passes.hpp"

namespace oer {

void read_back(const FrameRequest& request, GLuint finished, Frame& result) {
    const std::size_t row_values = std::size_t(request.width) * 4;
    if (request.linear) {
        std::vector<float> pixels(row_values * std::size_t(request.height));
        glGetTextureImage(finished, 0, GL_RGBA, GL_FLOAT, GLsizei(pixels.size() * sizeof(float)),
                          pixels.data());
        result.linear.resize(pixels.size());
        for (int y = 0; y < request.height; ++y) {
            std::memcpy(&result.linear[std::size_t(y) * row_values],
                        &pixels[std::size_t(request.height - 1 - y) * row_values],
                        row_values * sizeof(float));
        }
    } else {
        std::vector<std::uint8_t> pixels(row_values * std::size_t(request.height));
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glGetTextureImage(finished, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(pixels.size()),
                          pixels.data());
        result.display.width = request.width;
        result.display.height = request.height;
        result.display.pixels.resize(pixels.size());
        for (int y = 0; y < request.height; ++y) {
            std::memcpy(&result.display.pixels[std::size_t(y) * row_values],
                        &pixels[std::size_t(request.height - 1 - y) * row_values], row_values);
        }
    }
    leave_frame_state();
}

void leave_frame_state() {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDepthMask(GL_TRUE);
    glBindVertexArray(0);
    glUseProgram(0);
    glBindSampler(gl_bindings::kShadowMaps.index, 0);
    glBindSampler(gl_bindings::kShadowDepths.index, 0);
}

}  // namespace oer
