#version 460
// The preview pass: a mesh lit by one directional light, without diffraction (`diffract render --preview`).
#include "preview_frame.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec3 in_pigment;

layout(location = 0) out vec3 world_pos;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec3 world_tangent;
layout(location = 3) out vec3 tint;

void main() {
    vec4 p = frame.model * vec4(in_position, 1.0);
    world_pos = p.xyz;
    // Model matrices are rotations with uniform scale, so the normal transforms like a direction.
    world_normal = mat3(frame.model) * in_normal;
    world_tangent = mat3(frame.model) * in_tangent.xyz;
    tint = in_pigment;
    gl_Position = frame.view_proj * p;
}
