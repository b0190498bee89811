#version 460
// The profiler's roofline probe: the device's RG32F texel-fetch throughput under the Taylor sum's access
// pattern. Each fragment fetches PROBE_TAPS² neighbouring texels (the window's taps) in each of the array's
// layers (the Taylor terms), around a texel that moves with the fragment as a lookup does across a BRDF map,
// and sums them so that no fetch can be optimised away.
#include "interface.glsl"
layout(constant_id = SPEC_PROBE_LAYERS) const uint PROBE_LAYERS = 16;
layout(constant_id = SPEC_PROBE_TAPS) const int PROBE_TAPS = 8;

layout(set = 0, binding = BINDING_TABLE) uniform sampler2DArray probe_texture;
layout(location = 0) out vec4 out_color;

void main() {
    ivec2 size = textureSize(probe_texture, 0).xy;
    ivec2 centre = ivec2(gl_FragCoord.xy) % size;
    vec2 acc = vec2(0.0);
    for (int dy = 0; dy < PROBE_TAPS; ++dy) {
        for (int dx = 0; dx < PROBE_TAPS; ++dx) {
            ivec2 texel = (centre + ivec2(dx, dy)) % size;
            for (uint n = 0u; n < PROBE_LAYERS; ++n) acc += texelFetch(probe_texture, ivec3(texel, int(n)), 0).rg;
        }
    }
    out_color = vec4(acc, 0.0, 1.0);
}
