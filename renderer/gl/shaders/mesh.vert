#version 450 core
// Mesh vertices to clip space, with their world position, world normal and uv.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_projection;
out vec3 v_world_position;
out vec3 v_normal;
out vec2 v_texcoord;
void main() {
    vec4 world = u_model * vec4(a_position, 1.0);
    v_world_position = world.xyz;
    v_normal = u_normal_matrix * a_normal;
    v_texcoord = a_texcoord;
    gl_Position = u_view_projection * world;
}
