#version 460
// The visibility buffer's shading pass (`render::visibility`): one full-screen triangle per object, one invocation
// per pixel. It shades the first of the object's triangles among the pixel's samples: it rebuilds the inputs the
// rasteriser would have interpolated at the pixel's centre from the triangle's three vertices (their outputs kept
// by surface.vert's VISIBILITY variant), shades them once with the forward pass's own code (surface_shade.glsl)
// and weighs the colour by the share of samples the triangle covers. A pixel that sees more of the object's
// triangles (an edge) is listed for the edge pass (surface_edges.comp), which shades the others alike and adds
// them: what a multisampled forward frame averages, with one colour write per pixel instead of one per sample,
// and no hidden layer shaded.
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

// The full-screen triangle lies at the far plane and passes only where the resolved depth is nearer, that is where
// some sample shows an object: tested before the shader runs, so that the pixels of the background are skipped.
layout(early_fragment_tests) in;

layout(location = 0) out vec4 out_color;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int n = min(SAMPLE_COUNT, int(VISIBILITY_MAX_SAMPLES));
    uint id[VISIBILITY_MAX_SAMPLES];
    // The samples that see this object and are not shaded yet.
    uint pending = object_samples(pixel, n, id);
    // Where the object is not, nothing is written (and a block of pixels without it ends here).
    if (pending == 0u) discard;
    float covered = float(bitCount(pending)) / float(n);
    vec3 rgb = shade_triangle(gl_FragCoord.xy, id, n, pending);
#ifndef ONE_SAMPLE
    // Further triangles (an edge) are shaded by the edge pass, compute dispatches over the listed pixels only:
    // llvmpipe runs a branch's or a loop's body for a whole block of pixels if one of them needs it, and 88 % of
    // the snake's blocks hold an edge pixel (most of them spokes of a scale's fan), so a second shading here
    // cost as much as the first (docs/performance.md).
    if (pending != 0u) list_edge_pixel(0u, pixel);
#endif
    // Added to what the other objects wrote (blending ONE, ONE), over the constant background the target was
    // cleared to: the pixel ends as Σ colour + (1 − Σ covered) · background. Under an environment (background 0)
    // the background pass adds its share after (ONE_MINUS_DST_ALPHA).
    vec4 background = vec4(visibility.background_r, visibility.background_g, visibility.background_b,
                           visibility.background_a);
    out_color = vec4(rgb - covered * background.rgb, covered * (1.0 - background.a));
}
