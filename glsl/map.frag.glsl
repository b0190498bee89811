#version 460
// The BRDF map (model.md §1.1, the thesis's figures): the inscribed disk is the hemisphere of view directions.
// The pixel at (x, y) from the centre (x right, y up, radius 1) looks along sin θ_r = √(x²+y²), φ_r = atan2(y, x),
// i.e. ω_r = (x, y, √(1 − x² − y²)); the light is params.light. Outside the disk: black.
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#include "taylor.glsl"
#include "approaches.glsl"

// The map's square (side `size`) starts at pixel `offset` of the target.
layout(push_constant) uniform MapPush { vec2 size; vec2 offset; } map;
layout(location = 0) out vec4 out_color;

void main() {
    vec2 xy = (gl_FragCoord.xy - map.offset - 0.5 * map.size) / (0.5 * map.size);
    xy.y = -xy.y;
    float r2 = dot(xy, xy);
    if (r2 >= 1.0) {
        out_color = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    vec3 omega_r = vec3(xy, sqrt(1.0 - r2));
    out_color = vec4(shade(params.light.xyz, omega_r), 1.0);
    record_fetches();
}
