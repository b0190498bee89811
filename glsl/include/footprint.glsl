// A pixel's footprint in (u, v): what the baked table filters over, and what the G-buffer reports so that the
// table's resolution follows the views a frame shows. Guarded: baked.glsl includes it, and so does twins.comp.
#ifndef FOOTPRINT_GLSL
#define FOOTPRINT_GLSL

// The widest footprint in (u, v) a pixel may claim: where a mesh edge or a crease makes the derivatives of u and v
// jump (the 2×2 quad straddles two surfaces), they no longer describe one pixel's views. A pixel at most this wide
// averages over a patch of directions about 7° across.
const float MAX_FOOTPRINT = 0.25;

// The most reads of the baked table along a pixel's longer step in (u, v) (`baked_xyz_over`): anisotropic
// filtering, as a GPU's sampler approximates it.
const uint MAX_FOOTPRINT_TAPS = 4u;

// A pixel's two steps in (u, v), to the next pixel across and down, each at most MAX_FOOTPRINT long: (across,
// down).
vec4 footprint_steps(vec2 across, vec2 down) {
    return vec4(across * min(1.0, MAX_FOOTPRINT / max(length(across), 1e-30)),
                down * min(1.0, MAX_FOOTPRINT / max(length(down), 1e-30)));
}

// The variance in (u, v) that widens a lobe of a material at `material_um` to that of a light of the shorter
// coherence `light_um` (0 where it is not shorter): the window's per-axis standard deviation √2·λ/(π·L), squared,
// at WIDENING_LAMBDA_UM (`lamp::widening_variance`).
float widening_variance(float light_um, float material_um) {
    float scale = 2.0 * WIDENING_LAMBDA_UM * WIDENING_LAMBDA_UM / (PI * PI);
    return max(scale * (1.0 / (light_um * light_um) - 1.0 / (material_um * material_um)), 0.0);
}

// A pixel's steps widened by an isotropic Gaussian of `variance` in (u, v): the footprint along the principal axes
// of the pixel's uniform spread ((a·aᵀ + b·bᵀ)/12) plus the Gaussian's, each step √12 standard deviations
// (`lamp::widen_steps`).
vec4 widen_steps(vec4 steps, float variance) {
    if (variance <= 0.0) return steps;
    vec2 a = steps.xy, b = steps.zw;
    float p = a.x * a.x + b.x * b.x + 12.0 * variance;
    float q = a.x * a.y + b.x * b.y;
    float r = a.y * a.y + b.y * b.y + 12.0 * variance;
    float mean = 0.5 * (p + r), half_gap = sqrt(0.25 * (p - r) * (p - r) + q * q);
    float major = mean + half_gap, minor = max(mean - half_gap, 0.0);
    vec2 e = abs(q) > 1e-30 ? normalize(vec2(major - r, q)) : (p >= r ? vec2(1.0, 0.0) : vec2(0.0, 1.0));
    return vec4(e * sqrt(major), vec2(-e.y, e.x) * sqrt(minor));
}

#ifndef NO_DERIVATIVES
// The screen derivatives of (u, v) as `footprint_steps`. Call it in uniform control flow.
vec4 pixel_steps(vec2 uv) {
    return footprint_steps(dFdx(uv), dFdy(uv));
}

// The larger of the screen derivatives of (u, v), at most MAX_FOOTPRINT. Call it in uniform control flow
// (derivatives come from the 2×2 quad; a compute shader, which has none, defines NO_DERIVATIVES).
float pixel_footprint(vec2 uv) {
    return min(max(length(dFdx(uv)), length(dFdy(uv))), MAX_FOOTPRINT);
}
#endif
#endif // FOOTPRINT_GLSL
