// A pixel's footprint in (u, v): what the baked table filters over, and what the G-buffer reports so that the
// table's resolution follows the views a frame shows.

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
