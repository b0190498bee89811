// One pixel of the BRDF map (model.md §1.1, the thesis's figures), shared by map.frag (a full-screen triangle) and
// map.comp (one invocation per pixel): the inscribed disk is the hemisphere of view directions. The pixel at
// (x, y) from the centre (x right, y up, radius 1) looks along sin θ_r = √(x²+y²), φ_r = atan2(y, x), i.e.
// ω_r = (x, y, √(1 − x² − y²)); the light is params.light. Outside the disk: black.
// Requires params.glsl, spectrum.glsl, brdf.glsl, baked.glsl or taylor.glsl + approaches.glsl, and map_push.glsl.

// The colour of the pixel whose centre is at `frag_coord` (pixels of the target, as gl_FragCoord.xy).
vec4 map_pixel(vec2 frag_coord) {
    vec2 xy = (frag_coord - map.offset - 0.5 * map.size) / (0.5 * map.size);
    xy.y = -xy.y;
    float r2 = dot(xy, xy);
    if (r2 >= 1.0) return vec4(0.0, 0.0, 0.0, 1.0);
    vec3 omega_r = vec3(xy, sqrt(1.0 - r2));
#ifdef BAKED
    // A map pixel spans 2/size in ω_r.xy, and so in (u, v).
    float lod = FOOTPRINT == 1u ? table_lod(2.0 / map.size.x) : 0.0;
    vec3 rgb = xyz_to_linear_srgb(baked_diffraction_xyz(params.light.xyz, omega_r, lod)) * params.light_white.w;
    return vec4(DISPLAY_OUTPUT == 1u ? display_encode(rgb, params.display.x, params.display.y) : rgb, 1.0);
#else
    return vec4(shade(params.light.xyz, omega_r), 1.0);
#endif
}
