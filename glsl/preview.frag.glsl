#version 460
#include "preview_frame.glsl"

layout(location = 0) in vec3 world_pos;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in vec3 world_tangent;
layout(location = 3) in vec3 tint;
layout(location = 0) out vec4 out_color;

// Anisotropic (Kajiya-Kay style) highlight along the tangent, so the patch orientation is visible even in the
// preview; exponent chosen for a visible but narrow streak.
const float STREAK_EXPONENT = 48.0;
const float AMBIENT = 0.06;

void main() {
    vec3 n = normalize(world_normal);
    vec3 t = normalize(world_tangent - n * dot(world_tangent, n));
    vec3 l = normalize(frame.light_dir.xyz);
    vec3 v = normalize(frame.camera_pos.xyz - world_pos);
    vec3 h = normalize(l + v);
    float diffuse = max(dot(n, l), 0.0);
    float th = dot(t, h);
    float streak = pow(sqrt(max(1.0 - th * th, 0.0)), STREAK_EXPONENT) * step(0.0, dot(n, l));
    vec3 linear = frame.base_color.rgb * tint * (AMBIENT + diffuse) + vec3(0.35) * streak;
    // The target is an sRGB format: the hardware applies the transfer function on store.
    out_color = vec4(linear, 1.0);
}
