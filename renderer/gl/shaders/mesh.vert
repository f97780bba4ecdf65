#version 450 core
// Mesh vertices to clip space, with their world position, world normal, both uv sets, colour
// and world tangent.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
// xyz the direction of increasing u, w the bitangent's sign (glTF's TANGENT); a primitive
// without tangents leaves the attribute disabled, (1, 0, 0, 1), and no material of it reads it.
layout(location = 3) in vec4 a_tangent;
// The transfer's irradiance at the vertex (occlusion frames, renderer/transfer's
// transfer_lighting.hpp), computed per frame on the CPU; a frame without occlusion leaves the
// attribute disabled, (0, 0, 0).
layout(location = 4) in vec3 a_transferred_irradiance;
// The second uv set (TEXCOORD_1); a primitive without it leaves the attribute disabled, (0, 0),
// and no material of it reads it.
layout(location = 5) in vec2 a_texcoord1;
// The vertex colour (glTF COLOR_0, linear RGBA); a primitive without one leaves the attribute
// disabled, (1, 1, 1, 1).
layout(location = 6) in vec4 a_color;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
out vec3 v_world_position;
out vec3 v_normal;
out vec2 v_texcoord;
out vec2 v_texcoord1;
out vec4 v_color;
out vec4 v_tangent;
out vec3 v_transferred_irradiance;
void main() {
    vec4 world = u_model * vec4(a_position, 1.0);
    v_world_position = world.xyz;
    v_normal = u_normal_matrix * a_normal;
    v_texcoord = a_texcoord;
    v_texcoord1 = a_texcoord1;
    v_color = a_color;
    v_transferred_irradiance = a_transferred_irradiance;
    // Tangents are carried as directions on the surface (by the model matrix, not its inverse
    // transpose); a mirroring transform turns the bitangent cross(n, t) around, so the sign
    // follows the determinant.
    mat3 linear = mat3(u_model);
    v_tangent = vec4(linear * a_tangent.xyz, a_tangent.w * sign(determinant(linear)));
    gl_Position = u_view_projection * world;
}
