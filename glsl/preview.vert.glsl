#version 460
// The preview pass: a mesh lit by one directional light, without diffraction (`diffract render --preview`).
#include "preview_frame.glsl"

// No maps: the UVs are not an input (render::preview::PREVIEW_ATTRIBUTES leaves them out).
#define NO_IN_UV
#include "vertex_inputs.glsl" // in_position, in_normal, in_tangent, in_pigment

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
