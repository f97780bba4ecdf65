#version 450 core
// G-buffer: world position, normal and shininess, linear albedo and specular weight.
in vec3 v_world_position;
in vec3 v_normal;
in vec2 v_texcoord;
uniform vec4 u_base_color;
uniform int u_has_texture;
layout(binding = 0) uniform sampler2D u_base_texture;
uniform float u_specular_weight;  // 0: Lambertian only
uniform float u_shininess;
uniform vec3 u_eye;
layout(location = 0) out vec4 o_position;  // world position
layout(location = 1) out vec4 o_normal;    // world normal on the side seen, shininess
layout(location = 2) out vec4 o_albedo;    // linear albedo, specular weight
void main() {
    vec3 n = normalize(v_normal);
    // Open meshes (the bunny's base) show their inside, lit as a surface: a back face whose
    // normals also face away. A back face whose normals face the eye is a fold, such as
    // simplification leaves in slivers, and keeps them.
    if (!gl_FrontFacing && dot(n, u_eye - v_world_position) < 0.0) {
        n = -n;
    }
    vec3 albedo = u_base_color.rgb;
    if (u_has_texture != 0) {
        albedo *= texture(u_base_texture, v_texcoord).rgb;
    }
    o_position = vec4(v_world_position, 1.0);
    o_normal = vec4(n, u_shininess);
    o_albedo = vec4(albedo, u_specular_weight);
}
