#version 450 core
// One triangle covering the viewport.
void main() {
    gl_Position =
        vec4(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1), 1.0, 1.0);
}
