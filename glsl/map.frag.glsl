#version 460
// The BRDF map drawn by a full-screen triangle (the viewer's inset, and the profiler's fragment variant); its
// pixels are map_pixel.glsl's, as map.comp's are.
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#ifdef BAKED
#include "baked.glsl"
#else
#include "taylor.glsl"
#include "approaches.glsl"
#endif

// The map's square (side `size`) starts at pixel `offset` of the target.
#include "map_push.glsl"
#include "map_pixel.glsl"
layout(location = 0) out vec4 out_color;

void main() {
    out_color = map_pixel(gl_FragCoord.xy);
    record_fetches();
}
