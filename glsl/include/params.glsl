// Specialization constants and resources shared by every diffraction shader.
// Mirrored by `shading::DiffractionParams` (std140, 128 bytes) and `shading::Material::spec_constants`.

layout(constant_id = 0) const uint TERMS = 1;          // Taylor terms F_0..F_{TERMS-1}
layout(constant_id = 1) const int WINDOW_RADIUS = 1;   // taps either side of the nearest bin
layout(constant_id = 2) const uint LAMBDA_COUNT = 81;  // uniform wavelength samples (FLSS, PQ, gem's specular)
layout(constant_id = 3) const uint APPROACH = 0;       // see APPROACH_*
layout(constant_id = 4) const uint DISPLAY_OUTPUT = 0; // 0: linear scene-referred RGB; 1: exposure + sRGB OETF

#ifdef COUNT_FETCHES
// The counting variant adds each fragment's fetches to fetch_counts[y · COUNT_STRIDE + x] (a row of the target).
layout(constant_id = 5) const uint COUNT_STRIDE = 1;
layout(std430, set = 0, binding = 4) buffer FetchCounts { uint fetch_counts[]; };
#endif

const uint APPROACH_FLSS = 0u;
const uint APPROACH_NMM = 1u;
const uint APPROACH_PQ = 2u;
const uint APPROACH_GEM = 3u;

layout(std140, set = 0, binding = 1) uniform DiffractionParams {
    ivec4 patch_px;  // nx, ny, layers, 0
    vec4 patch_um;   // Lx, Ly, dx, dy (µm)
    vec4 window;     // σ_x, σ_y (bins), σ_f (cycles/µm), 0
    vec4 spectral;   // λ_min (nm), Δλ (nm), Σ ȳSΔλ of that sampling, ∫ȳS dλ (1 nm)
    vec4 light;      // ω_i in the patch frame (maps, compute)
    vec4 pq;         // periods along x, y
    vec4 gem;        // grating direction (x, y), spacing (µm; 0 = none), order efficiency
    vec4 display;    // 2^exposure
} params;

// F_n as RG32F (re, im), one layer per Taylor term, DC at texel (nx/2, ny/2).
layout(set = 0, binding = 2) uniform sampler2DArray taylor_terms;

// (x̄, ȳ, z̄, D65/100) per nm from 380 to 780 nm.
layout(std430, set = 0, binding = 3) readonly buffer SpectrumTable { vec4 spectrum_table[]; };

const float PI = 3.14159265358979;
