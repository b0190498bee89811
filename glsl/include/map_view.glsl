// The view of a BRDF map's pixel (model.md §1.1, the thesis's figures; `light::sampling::map_view`, its twin): the
// inscribed disk of a map `size` pixels wide at `offset` in its target is the hemisphere of views. The pixel whose
// centre is at (x, y) from the disk's centre (x right, y up, radius 1) looks along ω_r = (x, y, √(1 − x² − y²)).
// Returns ω_r and 1, or zero outside the disk.
vec4 map_view(vec2 frag_coord, vec2 offset, vec2 size) {
    vec2 xy = (frag_coord - offset - 0.5 * size) / (0.5 * size);
    xy.y = -xy.y;
    float r2 = dot(xy, xy);
    if (r2 >= 1.0) return vec4(0.0);
    return vec4(xy, sqrt(1.0 - r2), 1.0);
}
