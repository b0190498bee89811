#version 460
// One triangle over the viewport at the far plane (depth 0: a camera's depth is reversed, near 1): drawn after a
// scene's objects with an EQUAL depth
// test, it covers only the samples no object covered (the environment behind the scene, background.frag).
// The pixel's position in clip space (x, y in −1..1), interpolated exactly across the triangle.
layout(location = 0) out vec2 ndc;

void main() {
    vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    ndc = uv * 2.0 - 1.0;
    gl_Position = vec4(ndc, 0.0, 1.0);
}
