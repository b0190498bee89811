// A pixel's footprint in (u, v): what the baked table filters over, and what the G-buffer reports so that the
// table's resolution follows the views a frame shows.

// The widest footprint in (u, v) a pixel may claim: where a mesh edge or a crease makes the derivatives of u and v
// jump (the 2×2 quad straddles two surfaces), they no longer describe one pixel's views. A pixel at most this wide
// averages over a patch of directions about 7° across.
const float MAX_FOOTPRINT = 0.25;

#ifndef NO_DERIVATIVES
// The larger of the screen derivatives of (u, v), at most MAX_FOOTPRINT. Call it in uniform control flow
// (derivatives come from the 2×2 quad; a compute shader, which has none, defines NO_DERIVATIVES).
float pixel_footprint(vec2 uv) {
    return min(max(length(dFdx(uv)), length(dFdy(uv))), MAX_FOOTPRINT);
}
#endif
