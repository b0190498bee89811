// Per-frame uniforms of the preview (lit mesh) pass. Mirrored by `render::preview::FrameUniforms`.
#include "interface.glsl"
layout(set = 0, binding = BINDING_FRAME) uniform FrameUniforms {
    mat4 view_proj;
    mat4 model;
    vec4 camera_pos;   // world space, w unused
    vec4 light_dir;    // world space, unit, towards the light
    vec4 base_color;   // linear RGB
} frame;
