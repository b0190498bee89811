#version 460
// The surface pass: diffraction (the thesis's approaches) plus the skin's pigment under the grating, lit by the
// light the surface transmits (1 − R, Schlick; the thesis's texture blending, model.md §3.8) from the sun's
// disc and from a uniform sky.
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#ifdef BAKED
#include "baked.glsl"
#else
#include "taylor.glsl"
#include "approaches.glsl"
#endif
#include "surface_frame.glsl"

// After a depth pre-pass only the visible surface passes the EQUAL test: testing before the shader runs (which the
// counting variant's atomics would otherwise forbid) shades each pixel once.
layout(early_fragment_tests) in;

layout(location = 0) in vec3 patch_light;
layout(location = 1) in vec3 patch_view;
layout(location = 0) out vec4 out_color;

// The sun's solid angle (0.53° across), sr: its diffuse contribution relative to its glint in a mirror
// (`optics::SUN_SOLID_ANGLE`).
const float SUN_SOLID_ANGLE = 6.8e-5;

// The light the skin's pigment returns under the grating, linear RGB; mirrors `optics::pigment_rgb` (the
// profiler's reference adds it on the CPU): the pigment lit through the transmitted share 1 − R (Schlick) by the
// sun and a uniform sky of radiance `ambient`.
vec3 pigment_rgb(vec3 omega_i, vec3 omega_r, vec3 pigment, float ambient) {
    if (omega_r.z <= 0.0) return vec3(0.0);
    float r0 = (SKIN_INDEX - 1.0) * (SKIN_INDEX - 1.0) / ((SKIN_INDEX + 1.0) * (SKIN_INDEX + 1.0));
    float transmitted = 1.0 - r0 * fresnel_ratio(omega_i, omega_r, SKIN_INDEX);
    float irradiance = ambient + SUN_SOLID_ANGLE / PI * max(omega_i.z, 0.0);
    return transmitted * pigment * irradiance;
}

void main() {
    vec3 omega_i = normalize(patch_light);
    vec3 omega_r = normalize(patch_view);
#ifdef BAKED
    float footprint = pixel_footprint(-omega_i.xy - omega_r.xy);
    vec3 rgb = xyz_to_linear_srgb(baked_diffraction_xyz(omega_i, omega_r, FOOTPRINT == 1u ? table_lod(footprint) : 0.0));
#else
    vec3 rgb = xyz_to_linear_srgb(diffraction_xyz(omega_i, omega_r));
#endif
    rgb += pigment_rgb(omega_i, omega_r, frame.pigment.rgb, frame.pigment.w);
    out_color = vec4(DISPLAY_OUTPUT == 1u ? display_encode(rgb, params.display.x) : rgb, 1.0);
    record_fetches();
}
