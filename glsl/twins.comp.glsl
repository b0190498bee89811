#version 460
// The GLSL halves of the functions that exist in Rust and in GLSL (ARCHITECTURE.md, "Twins";
// `reference::twins`): each invocation evaluates the function `twin.function` (TWIN_*) at one point, four vec4s of
// arguments, with the very includes the frames compile, so that a test can set it against its Rust twin. The
// BAKED variant (twins_baked.comp) reads a material's baked table; the other needs no material.
#define NO_DERIVATIVES
#define SKY_DIFFRACTION_AT_VERTEX
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#ifdef BAKED
#include "baked.glsl"
#endif
#include "surface_frame.glsl"
#include "pigment.glsl"
#include "lamps.glsl"
#include "footprint.glsl"
#include "map_view.glsl"
#include "sky_diffraction.glsl" // and panorama.glsl
#include "twin_push.glsl"

layout(local_size_x = LOCAL_SIZE_X) in;
layout(std430, set = 0, binding = BINDING_TWIN_IN) readonly buffer TwinIn { vec4 twin_in[]; };
layout(std430, set = 0, binding = BINDING_TWIN_OUT) writeonly buffer TwinOut { vec4 twin_out[]; };
// One distribution (`Distribution2D::gpu_words`), bound to both of env_sampling.glsl's buffers.
layout(std430, set = 0, binding = BINDING_TABLE_SAMPLING) readonly buffer TableSampling { float table_sampling[]; };
layout(std430, set = 0, binding = BINDING_ENV_SAMPLING) readonly buffer EnvSampling { float env_sampling[]; };
#include "env_sampling.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= twin.count) return;
    vec4 a = twin_in[4u * i], b = twin_in[4u * i + 1u], c = twin_in[4u * i + 2u], d = twin_in[4u * i + 3u];
    vec4 result = vec4(0.0);
    switch (twin.function) {
    case TWIN_FRESNEL_REFLECTANCE: result.x = fresnel_reflectance(a.x, a.y); break;
    case TWIN_FRESNEL_RATIO: result.x = fresnel_ratio(a.xyz, b.xyz, a.w); break;
    case TWIN_GAIN_FACTOR: result.x = gain_factor(a.xyz, b.xyz); break;
    case TWIN_SHADOW_MASK: result.x = shadow_mask(a.xyz, b.xyz); break;
    case TWIN_TRANSMITTANCE: result.x = transmittance(a.x); break;
    case TWIN_PIGMENT_RGB: result.xyz = pigment_rgb(a.xyz, b.xyz, a.w, c.xyz, b.w, c.w, d.x > 0.5); break;
    case TWIN_PIGMENT_SKY_RGB: result.xyz = pigment_sky_rgb(a.xyz, b.xyz, c.xyz, d.x > 0.5); break;
    case TWIN_SKY_OVER_PI: result.xyz = sky_over_pi(a.xyz); break;
    case TWIN_SRGB_OETF: result.x = srgb_oetf(a.x); break;
    case TWIN_AGX: result.xyz = agx(a.xyz); break;
    case TWIN_DISPLAY_ENCODE: result.xyz = display_encode(a.xyz, a.w, b.x); break;
    case TWIN_XYZ_TO_LINEAR_SRGB: result.xyz = xyz_to_linear_srgb(a.xyz); break;
    case TWIN_SPECTRUM_AT: result = spectrum_at(a.x); break;
    case TWIN_PANORAMA_UV: result.xy = panorama_uv(a.xyz, a.w); break;
    case TWIN_MAP_VIEW: result = map_view(a.xy, a.zw, b.xy); break;
    case TWIN_MOMENT_GRID_OF_VIEW: result.xy = moment_grid_of_view(a.xyz); break;
    case TWIN_SKY_COEFFICIENTS: {
        vec3 coefficients[9];
        sky_coefficients(a.xyz, b.xyz, c.xyz, coefficients);
        result.xyz = coefficients[uint(d.x)];
        break;
    }
    case TWIN_SAMPLE_CELL: {
        vec2 frac;
        uvec2 cell = sample_cell(true, floatBitsToUint(b.x), floatBitsToUint(b.y), a.xy, frac);
        result = vec4(vec2(cell), frac);
        break;
    }
    case TWIN_R2: result.xy = r2(floatBitsToUint(a.x), floatBitsToUint(a.yz)); break;
    case TWIN_TENT: result.x = tent(a.x); break;
    case TWIN_SPOT_FACTOR: result.x = spot_factor(a.x, a.y, a.z); break;
    case TWIN_LAMP_LIGHT: result = lamp_light(uint(a.w), a.xyz); break;
    case TWIN_LAMP_COHERENCE: result.x = lamp_coherence_um(uint(a.w), a.xyz); break;
    case TWIN_WIDENING_VARIANCE: result.x = widening_variance(a.x, a.y); break;
    case TWIN_WIDEN_STEPS: result = widen_steps(a, b.x); break;
#ifdef BAKED
    case TWIN_TABLE_LOD: result.x = table_lod(a.x); break;
    case TWIN_TABLE_SEGMENT: {
        float t;
        result.x = float(table_segment(a.x, t));
        result.y = t;
        break;
    }
    case TWIN_BAKED_XYZ: result.xyz = baked_xyz(a.xyz, a.w); break;
#endif
    default: result = vec4(-1.0);
    }
    twin_out[i] = result;
}
