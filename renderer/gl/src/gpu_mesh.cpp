#include "gpu_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

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

gl::Object upload_texture(const Texture& texture) {
    gl::Object name = gl::create_texture(GL_TEXTURE_2D);
    const int levels =
        1 + int(std::floor(std::log2(double(std::max(texture.width, texture.height)))));
    glTextureStorage2D(name.get(), levels, GL_SRGB8_ALPHA8, texture.width, texture.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(name.get(), 0, 0, 0, texture.width, texture.height, GL_RGBA,
                        GL_UNSIGNED_BYTE, texture.rgba.data());
    glGenerateTextureMipmap(name.get());
    glTextureParameteri(name.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(name.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(name.get(), GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(name.get(), GL_TEXTURE_WRAP_T, GL_REPEAT);
    return name;
}

}  // namespace

void draw_primitive(const GpuPrimitive& primitive, float max_error) {
    const LodLevel& level = choose_lod(primitive.lods, max_error);
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
        LodIndices lods = build_lods(primitive);
        out.buffers.push_back(upload_buffer(lods.indices));
        glVertexArrayElementBuffer(vao, out.buffers.back().get());
        out.lods = std::move(lods.levels);
        out.material = primitive.material;
        gpu.primitives.push_back(std::move(out));
    }
    for (const Texture& texture : mesh.textures) {
        gpu.textures.push_back(upload_texture(texture));
    }
    return gpu;
}

}  // namespace oer
