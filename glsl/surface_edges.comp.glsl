#version 460
// The visibility buffer's edge pass (`render::visibility`): dispatch k (visibility.edge) shades, for every pixel
// listed as seeing more than k of the object's triangles (by the shading pass, which shaded the first, or by
// dispatch k − 1), its (k + 1)-th at the pixel centre, weighed by its samples, adds it to the pixel, and lists
// the pixel for dispatch k + 1 if it sees more. As a compute dispatch over a list, its invocations are packed
// densely and each shades once: in the full-screen pass a second shading ran for every block of pixels that held
// one edge pixel, and a loop over further triangles runs for every group of lanes that holds one pixel with more.
#define NO_DERIVATIVES
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#ifdef BAKED
#include "baked.glsl"
#else
#include "taylor.glsl"
#include "approaches.glsl"
#endif
#include "surface_frame.glsl"
#include "shadow.glsl"
#include "sky_diffraction.glsl"
#include "surface_shade.glsl"
#include "visibility_push.glsl"
#include "visibility_shade.glsl"

layout(local_size_x = VISIBILITY_EDGE_GROUP) in;
// The frame's one-sample colour, which the shading pass (and the background) wrote.
layout(set = 0, binding = BINDING_VISIBILITY_TARGET, rgba32f) uniform image2D target;

void main() {
    uint list = (visibility.edge - 1u) * edge_list_words();
    uint i = gl_GlobalInvocationID.x;
    if (i >= edge_words[list + 3u]) return;
    uint packed = edge_words[list + 4u + i];
    ivec2 pixel = ivec2(packed & 0xffffu, packed >> 16);
    int n = min(SAMPLE_COUNT, int(VISIBILITY_MAX_SAMPLES));
    uint id[VISIBILITY_MAX_SAMPLES];
    uint pending = object_samples(pixel, n, id);
    // The triangles before this dispatch's: the shading pass's and the earlier dispatches'.
    for (uint k = 0u; k < visibility.edge; k++) pending &= ~first_triangle_samples(id, n, pending);
    vec3 rgb = shade_triangle(vec2(pixel) + 0.5, id, n, pending);
    imageStore(target, pixel, imageLoad(target, pixel) + vec4(rgb, 0.0));
    // A pixel that sees more still goes to the next dispatch (there is a list for every triangle but the first).
    if (pending != 0u) list_edge_pixel(visibility.edge, pixel);
}
