#version 460
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#include "taylor.glsl"
#include "approaches.glsl"

layout(location = 0) in vec3 patch_light;
layout(location = 1) in vec3 patch_view;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(shade(normalize(patch_light), normalize(patch_view)), 1.0);
}
