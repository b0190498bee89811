// The baked approach: the spectrally integrated colour of the patch over (u, v), its dependence on w a Chebyshev
// series, prefiltered into mip levels; mirrors src/physics/baked/sample.rs (same names).
// Requires params.glsl (compiled with BAKED) and brdf.glsl.
#include "footprint.glsl"

// RGBA layers a read fetches: 3 channels × TERMS coefficients of one segment of w, four to a layer
// (`baked::layers_for`). Segment s's layers are s·TABLE_LAYERS onwards (`Grid::segments`).
const uint TABLE_LAYERS = (3u * TERMS + 3u) / 4u;
// Texels a read of the table takes (`MipFilter::texels_per_read`: 8 trilinear, 4 from the nearest level): what
// the counting variants add per read.
layout(constant_id = SPEC_TABLE_TEXELS) const uint TABLE_TEXELS = 8u;

// How much finer than a pixel's footprint the mip level is chosen (FOOTPRINT_LOD_BIAS, from interface.glsl): a
// trilinear fetch averages a level's texels (a box, variance T²/12) and interpolates between them (a tent, T²/6);
// their sum matches the pixel's box of width F (F²/12) for texels T = F/√3, one log2(√3) below the level whose
// texels are F wide.

// The mip level for a pixel whose footprint in (u, v) is `footprint`, clamped to the levels there are
// (`BakedTable::lod`).
float table_lod(float footprint) {
    float texel = params.table_w.z;
    if (!(footprint > texel)) return 0.0;
    return clamp(log2(footprint / texel) - FOOTPRINT_LOD_BIAS, 0.0, params.table_w.w);
}

// The segment of w and t ∈ [−1, 1] within it (`Grid::segment_of`): params.table_w.x is the interval's lower end,
// .y its segments per unit of w, params.patch_px.w the segments.
uint table_segment(float w, out float t) {
    uint segments = uint(params.patch_px.w);
    float x = clamp((w - params.table_w.x) * params.table_w.y, 0.0, float(segments));
    uint segment = min(uint(x), segments - 1u);
    t = clamp(2.0 * (x - float(segment)) - 1.0, -1.0, 1.0);
    return segment;
}

// XYZ relative to a D65 mirror, before the gain and the shadowing, at `uvw` and mip level `lod`
// (`BakedTable::xyz`): samples of the layers of w's segment, then Σ_d a_d·T_d(t) per channel, clamped at 0.
vec3 baked_xyz(vec3 uvw, float lod) {
    float t;
    uint first = table_segment(uvw.z, t) * TABLE_LAYERS;
    float cheb[TERMS];
    cheb[0] = 1.0;
    for (uint d = 1u; d < TERMS; ++d) cheb[d] = d == 1u ? t : 2.0 * t * cheb[d - 1u] - cheb[d - 2u];
    vec2 coords = (uvw.xy - params.table_uv.xy) / params.table_uv.zw;
    vec3 xyz = vec3(0.0);
    for (uint layer = 0u; layer < TABLE_LAYERS; ++layer) {
        vec4 c = textureLod(baked_table, vec3(coords, float(first + layer)), lod);
        for (uint j = 0u; j < 4u; ++j) {
            uint s = 4u * layer + j;
            if (s < 3u * TERMS) xyz[s % 3u] += c[j] * cheb[s / 3u];
        }
    }
#ifdef COUNT_FETCHES
    fetch_count += TABLE_LAYERS * TABLE_TEXELS;
#endif
    return max(xyz, vec3(0.0));
}

// The table's XYZ averaged over a pixel whose steps in (u, v) are `steps` (`footprint_steps`): up to
// MAX_FOOTPRINT_TAPS reads spread along the longer step, each filtering (by its mip level) over the shorter step or
// over its share of the longer, whichever is wider — anisotropic filtering as the Vulkan specification approximates
// it. One level from the longer step alone, as before, blurred the shorter way too, and on the default snake put
// baked further from the exact reference than FLSS's point samples (docs/performance.md, "The trade on the
// default scene").
vec3 baked_xyz_over(vec3 uvw, vec4 steps) {
    float across = length(steps.xy), down = length(steps.zw);
    vec2 axis = across >= down ? steps.xy : steps.zw;
    float major = max(across, down), minor = min(across, down);
    float texel = params.table_w.z;
    uint taps = 1u;
    if (major > texel) taps = uint(clamp(ceil(major / max(minor, texel)), 1.0, float(MAX_FOOTPRINT_TAPS)));
    float lod = table_lod(max(minor, major / float(taps)));
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < taps; ++i) {
        float offset = (float(i) + 0.5) / float(taps) - 0.5;
        sum += baked_xyz(vec3(uvw.xy + offset * axis, uvw.z), lod);
    }
    return sum / float(taps);
}

// The relative reflectance's colour for one pair of patch-frame directions: XYZ · C · shadowing (the baked twin
// of `diffraction_xyz` in approaches.glsl).
vec3 baked_diffraction_xyz(vec3 omega_i, vec3 omega_r, float lod) {
    if (omega_i.z <= 0.0 || omega_r.z <= 0.0) return vec3(0.0);
    return baked_xyz(-omega_i - omega_r, lod) * gain_factor(omega_i, omega_r) * shadow_mask(omega_i, omega_r);
}

// The same over a pixel whose steps in (u, v) are `steps` (`baked_xyz_over`; the gain and the shadowing at the
// pixel's centre). Steps of zero read once, at level 0: `baked_diffraction_xyz` at lod 0.
vec3 baked_diffraction_xyz_over(vec3 omega_i, vec3 omega_r, vec4 steps) {
    if (omega_i.z <= 0.0 || omega_r.z <= 0.0) return vec3(0.0);
    return baked_xyz_over(-omega_i - omega_r, steps) * gain_factor(omega_i, omega_r) * shadow_mask(omega_i, omega_r);
}
