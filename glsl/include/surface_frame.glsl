// Per-frame uniforms of the surface (geometry) pass. Mirrored by `render::surface::SurfaceUniforms`.
#include "interface.glsl"
layout(std140, set = 0, binding = BINDING_FRAME) uniform SurfaceUniforms {
    mat4 view_proj;
    mat4 model;
    mat4 normal_matrix;  // inverse transpose of the model matrix's linear part (in a mat4 for std140)
    vec4 camera_pos;     // world space
    vec4 light_dir;      // world space, unit, towards the light
    vec4 orientation;    // cos, sin of the patch's rotation about the normal (tangent towards bitangent), material index
    vec4 pigment;        // linear RGB albedo of the skin under the grating, and the sky's ambient radiance
} frame;
