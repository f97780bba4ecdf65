#include "gpu_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/common.hpp>

namespace oer {

namespace {

template <typename T>
gl::Object upload_buffer(const std::vector<T>& data) {
    gl::Object buffer = gl::create_buffer();
    glNamedBufferStorage(buffer.get(),
                         GLsizeiptr(std::max<std::size_t>(1, data.size()) * sizeof(T)),
                         data.empty() ? nullptr : data.data(), 0);
    return buffer;
}

void attach(GLuint vertex_array, GLuint buffer, GLuint location, GLint components) {
    glVertexArrayVertexBuffer(vertex_array, location, buffer, 0,
                              GLsizei(components * sizeof(float)));
    glVertexArrayAttribFormat(vertex_array, location, components, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vertex_array, location, location);
    glEnableVertexArrayAttrib(vertex_array, location);
}

// Filtering and wrapping come from the sampler object of each use (RendererState::sampler),
// which overrides the texture's own parameters; every texture has its mipmaps, whatever its
// samplers ask for.
gl::Object upload_texture(const Texture& texture) {
    gl::Object name = gl::create_texture(GL_TEXTURE_2D);
    const int levels =
        1 + int(std::floor(std::log2(double(std::max(texture.width, texture.height)))));
    glTextureStorage2D(name.get(), levels,
                       texture.encoding == TextureEncoding::Srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8,
                       texture.width, texture.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(name.get(), 0, 0, 0, texture.width, texture.height, GL_RGBA,
                        GL_UNSIGNED_BYTE, texture.rgba.data());
    glGenerateTextureMipmap(name.get());
    return name;
}

}  // namespace

void attach_transferred_irradiance(const GpuPrimitive& primitive, GLuint buffer,
                                   std::size_t first_vertex) {
    constexpr GLuint kLocation = 4;
    const GLuint vertex_array = primitive.vertex_array.get();
    if (buffer == 0) {
        glDisableVertexArrayAttrib(vertex_array, kLocation);
        glVertexAttrib3f(kLocation, 0.0f, 0.0f, 0.0f);
        return;
    }
    glVertexArrayVertexBuffer(vertex_array, kLocation, buffer,
                              GLintptr(first_vertex * 3 * sizeof(float)), 3 * sizeof(float));
    glVertexArrayAttribFormat(vertex_array, kLocation, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vertex_array, kLocation, kLocation);
    glEnableVertexArrayAttrib(vertex_array, kLocation);
}

void draw_primitive(const GpuPrimitive& primitive, float max_error, float max_edge) {
    const LodLevel& level = choose_lod(primitive.lods, max_error, max_edge);
    glBindVertexArray(primitive.vertex_array.get());
    glDrawElements(
        GL_TRIANGLES, GLsizei(level.index_count), GL_UNSIGNED_INT,
        reinterpret_cast<const void*>(std::uintptr_t(level.first_index) * sizeof(std::uint32_t)));
}

GpuMesh upload_mesh(const Mesh& mesh) {
    GpuMesh gpu;
    for (const Primitive& primitive : mesh.primitives) {
        GpuPrimitive out;
        out.vertex_array = gl::create_vertex_array();
        const GLuint vao = out.vertex_array.get();
        out.buffers.push_back(upload_buffer(primitive.positions));
        attach(vao, out.buffers.back().get(), 0, 3);
        out.buffers.push_back(upload_buffer(primitive.normals));
        attach(vao, out.buffers.back().get(), 1, 3);
        if (primitive.texcoords.size() == primitive.positions.size()) {
            out.buffers.push_back(upload_buffer(primitive.texcoords));
            attach(vao, out.buffers.back().get(), 2, 2);
        }
        // Location 4 is the transfer's irradiance (attach_transferred_irradiance).
        if (primitive.texcoords1.size() == primitive.positions.size()) {
            out.buffers.push_back(upload_buffer(primitive.texcoords1));
            attach(vao, out.buffers.back().get(), 5, 2);
        }
        if (primitive.colors.size() == primitive.positions.size()) {
            out.buffers.push_back(upload_buffer(primitive.colors));
            attach(vao, out.buffers.back().get(), 6, 4);
        }
        if (primitive.tangents.size() == primitive.positions.size()) {
            out.buffers.push_back(upload_buffer(primitive.tangents));
            attach(vao, out.buffers.back().get(), 3, 4);
        }
        if (!primitive.positions.empty()) {
            glm::vec3 low = primitive.positions.front(), high = low;
            for (const glm::vec3& p : primitive.positions) {
                low = glm::min(low, p);
                high = glm::max(high, p);
            }
            out.centre = 0.5f * (low + high);
        }
        LodIndices lods = build_lods(primitive);
        out.buffers.push_back(upload_buffer(lods.indices));
        glVertexArrayElementBuffer(vao, out.buffers.back().get());
        out.lods = std::move(lods.levels);
        gpu.primitives.push_back(std::move(out));
    }
    for (const Texture& texture : mesh.textures) {
        gpu.textures.push_back(upload_texture(texture));
    }
    return gpu;
}

}  // namespace oer
