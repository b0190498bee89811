// One pixel of the BRDF map, shared by map.frag (a full-screen triangle) and map.comp (one invocation per pixel): its
// view from map_view.glsl, the light params.light; outside the disk, black.
// Requires params.glsl, spectrum.glsl, brdf.glsl, baked.glsl or taylor.glsl + approaches.glsl, and map_push.glsl.
#include "map_view.glsl"

// The colour of the pixel whose centre is at `frag_coord` (pixels of the target, as gl_FragCoord.xy).
vec4 map_pixel(vec2 frag_coord) {
    vec4 view = map_view(frag_coord, map.offset, map.size);
    if (view.w == 0.0) return vec4(0.0, 0.0, 0.0, 1.0);
    vec3 omega_r = view.xyz;
#ifdef BAKED
    // A map pixel spans 2/size in ω_r.xy, and so in (u, v).
    float lod = FOOTPRINT == 1u ? table_lod(2.0 / map.size.x) : 0.0;
    vec3 rgb = xyz_to_linear_srgb(baked_diffraction_xyz(params.light.xyz, omega_r, lod)) * params.light_white.w;
    return vec4(DISPLAY_OUTPUT == 1u ? display_encode(rgb, params.display.x, params.display.y) : rgb, 1.0);
#else
    return vec4(shade(params.light.xyz, omega_r), 1.0);
#endif
}
