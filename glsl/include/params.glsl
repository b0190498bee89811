// Specialization constants and resources shared by every diffraction shader.
// The uniform block `params` is generated from `DiffractionParams` in crates/gpu-interface (its size is in the
// generated file's first line); the constants' values come from `material::Material::spec_constants`, their ids and
// the bindings from interface.glsl.
#include "interface.glsl"

layout(constant_id = SPEC_TERMS) const uint TERMS = 1;          // Taylor terms F_0..F_{TERMS-1}; baked: Chebyshev terms in w
layout(constant_id = SPEC_WINDOW_RADIUS) const int WINDOW_RADIUS = 1;   // taps either side of the nearest bin
layout(constant_id = SPEC_LAMBDA_COUNT) const uint LAMBDA_COUNT = 81;  // uniform wavelength samples (FLSS, PQ, gem's specular)
layout(constant_id = SPEC_APPROACH) const uint APPROACH = 0; // see APPROACH_*
layout(constant_id = SPEC_DISPLAY_OUTPUT) const uint DISPLAY_OUTPUT = 0; // 0: linear scene-referred RGB; 1: exposure + sRGB OETF
// Baked: 0 reads the table's finest level (a BRDF map's point values); 1 filters over the pixel's footprint.
layout(constant_id = SPEC_FOOTPRINT) const uint FOOTPRINT = 1;

#ifdef COUNT_FETCHES
// The counting variant adds each fragment's fetches, and 1, to fetch_counts[y · COUNT_STRIDE + x] (a row of the
// target): the texels a pixel cost and how many times it was shaded. Mirrored by `render::workload::Counts`.
layout(constant_id = SPEC_COUNT_STRIDE) const uint COUNT_STRIDE = 1;
layout(std430, set = 0, binding = BINDING_FETCH_COUNTS) buffer FetchCounts { uvec2 fetch_counts[]; };
// Texels fetched by this fragment so far (Taylor terms, or the baked table's trilinear samples).
uint fetch_count = 0u;
#endif

// The counting variant's record of this fragment's fetches (a no-op otherwise).
void record_fetches() {
#ifdef COUNT_FETCHES
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint i = pixel.y * COUNT_STRIDE + pixel.x;
    atomicAdd(fetch_counts[i].x, fetch_count);
    atomicAdd(fetch_counts[i].y, 1u);
#endif
}

// The material's uniforms, generated from `gpu::interface::DiffractionParams` (the Rust struct is their one source).
#include "diffraction_params.glsl"

#ifdef BAKED
// The baked colour table: Chebyshev coefficients of X, Y, Z in w packed four to a layer (coefficient d of channel
// c is scalar 3d + c), mip-mapped, sampled trilinearly.
layout(set = 0, binding = BINDING_TABLE) uniform sampler2DArray baked_table;
#else
// F_n as RG32F (re, im), one layer per Taylor term, DC at texel (nx/2, ny/2).
layout(set = 0, binding = BINDING_TABLE) uniform sampler2DArray taylor_terms;
#endif

// (x̄, ȳ, z̄, D65/100) per nm from 380 to 780 nm.
layout(std430, set = 0, binding = BINDING_SPECTRUM) readonly buffer SpectrumTable { vec4 spectrum_table[]; };

