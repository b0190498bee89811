// Drawing points from 2D distributions (`light::sampling`: its twins, same names; ARCHITECTURE.md, "Twins"): the
// R2 sequence, a distribution's cells by inverting its CDFs, the tent's inverse CDF, and a PCG hash for the
// sequences' shifts. Needs the buffers `table_sampling` and `env_sampling` (each a `Distribution2D::gpu_words`)
// declared before it.

// PCG hash (Jarzynski & Olano 2020): each call advances the pixel's stream (the sequences' shifts).
uint pcg(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
uint rng_state;
uint next_uint() {
    rng_state = pcg(rng_state);
    return rng_state;
}

float cdf_at(bool table, uint i) { return table ? table_sampling[i] : env_sampling[i]; }

// One step of the search below: take the bit if the CDF there is still ≤ x.
#define SEARCH_BIT(b) { uint mid = lo + (1u << b); if (mid < n && cdf_at(table, base + mid) <= x) lo = mid; }

// The last i < n with cdf[base + i] ≤ x, and x's place within [cdf[i], cdf[i + 1]) (`light::sampling::invert`), for
// n ≤ 2¹⁶. Written out bit by bit, without a loop: llvmpipe stops an invocation's loops after 65535 iterations in
// all (its guard against endless loops), which a search loop inside every sample's loop reached after ~2700
// samples.
uint invert(bool table, uint base, uint n, float x, out float frac) {
    uint lo = 0u;
    SEARCH_BIT(15) SEARCH_BIT(14) SEARCH_BIT(13) SEARCH_BIT(12) SEARCH_BIT(11) SEARCH_BIT(10) SEARCH_BIT(9)
    SEARCH_BIT(8) SEARCH_BIT(7) SEARCH_BIT(6) SEARCH_BIT(5) SEARCH_BIT(4) SEARCH_BIT(3) SEARCH_BIT(2)
    SEARCH_BIT(1) SEARCH_BIT(0)
    float a = cdf_at(table, base + lo), b = cdf_at(table, base + lo + 1u);
    frac = b > a ? clamp((x - a) / (b - a), 0.0, 0.99999994) : 0.5;
    return lo;
}

// The cell (col, row) of an nu × nv distribution the point xi falls in, and where in it
// (`Distribution2D::sample`).
uvec2 sample_cell(bool table, uint nu, uint nv, vec2 xi, out vec2 frac) {
    uint row = invert(table, 0u, nv, xi.y, frac.y);
    uint col = invert(table, nv + 1u + row * (nu + 1u), nu, xi.x, frac.x);
    return uvec2(col, row);
}

// A cell's density over its measure.
float cell_density(bool table, uint nu, uint nv, uint cell) {
    return cdf_at(table, nv + 1u + nv * (nu + 1u) + cell);
}

// Point k of the R2 sequence shifted by `shift` (`light::sampling::r2`).
vec2 r2(uint k, uvec2 shift) {
    uvec2 x = shift + k * uvec2(R2_STEP_X, R2_STEP_Y);
    return vec2(x >> 8u) * (1.0 / 16777216.0);
}

// The inverse CDF of the tent on [−1, 1] (`light::sampling::tent`).
float tent(float f) {
    return f < 0.5 ? sqrt(2.0 * f) - 1.0 : 1.0 - sqrt(2.0 * (1.0 - f));
}
