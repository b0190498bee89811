#version 460
// The visibility buffer's shading pass (`render::visibility`): one full-screen triangle per object, one invocation
// per pixel. For each of the object's triangles among the pixel's samples, it rebuilds the inputs the rasteriser
// would have interpolated at the pixel's centre from the triangle's three vertices (their outputs kept by
// surface.vert's VISIBILITY variant), shades them once with the forward pass's own code (surface_shade.glsl) and
// weighs the colour by the share of samples the triangle covers: what a multisampled forward frame averages, with
// one colour write per pixel instead of one per sample, and no hidden layer shaded.
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

// The full-screen triangle lies at the far plane and passes only where the resolved depth is nearer, that is where
// some sample shows an object: tested before the shader runs, so that the pixels of the background are skipped.
layout(early_fragment_tests) in;

#ifdef ONE_SAMPLE
// The variants `surface_resolve_one.frag` and `surface_resolve_baked_one.frag`, for frames of one sample per pixel.
layout(binding = BINDING_VISIBILITY_IDS) uniform usampler2D ids;
#define SAMPLE_ID(pixel, s) texelFetch(ids, pixel, 0).r
#define SAMPLE_COUNT 1
#define IDS_SIZE textureSize(ids, 0)
#else
layout(binding = BINDING_VISIBILITY_IDS) uniform usampler2DMS ids;
#define SAMPLE_ID(pixel, s) texelFetch(ids, pixel, s).r
#define SAMPLE_COUNT textureSamples(ids)
#define IDS_SIZE textureSize(ids)
#endif
layout(std430, binding = BINDING_VERTEX_OUTPUTS) readonly buffer VertexOutputs {
    vec4 vertex_outputs[];
};
layout(std430, binding = BINDING_MESH_INDICES) readonly buffer MeshIndices {
    uint mesh_indices[];
};
layout(location = 0) out vec4 out_color;

// The perspective-correct barycentrics of the point of a triangle (clip positions c0, c1, c2) that lands on `ndc`:
// the weights b, summing to 1, with Σ bᵢ (xᵢ − ndc.x wᵢ) = Σ bᵢ (yᵢ − ndc.y wᵢ) = 0, so that Σ bᵢ cᵢ projects onto
// `ndc`. In homogeneous coordinates, so a vertex behind the camera (w < 0, clipped by the rasteriser) needs no
// special case.
vec3 barycentrics(vec4 c0, vec4 c1, vec4 c2, vec2 ndc) {
    vec3 w = vec3(c0.w, c1.w, c2.w);
    vec3 b = cross(vec3(c0.x, c1.x, c2.x) - ndc.x * w, vec3(c0.y, c1.y, c2.y) - ndc.y * w);
    return b / (b.x + b.y + b.z);
}

// The (u, v) the baked table is read at (surface.frag's footprint argument) at barycentrics b, from the three
// vertices' light (l) and view (v) vectors.
vec2 table_uv(mat3 l, mat3 v, vec3 b) {
    return -normalize(l * b).xy - normalize(v * b).xy;
}

// The share of the pixel's colour of the triangle that the first of the `pending` samples sees (bits of `id`, of
// `n`): its inputs rebuilt at the pixel centre and shaded, weighed by the samples that see it, which it then
// clears from `pending`; `covered` grows by their share.
vec3 shade_triangle(uint id[VISIBILITY_MAX_SAMPLES], int n, inout uint pending, inout float covered) {
    vec2 size = vec2(IDS_SIZE);
    vec2 ndc = gl_FragCoord.xy / size * 2.0 - 1.0;
    vec2 pixel_step = 2.0 / size;
    uint first = id[findLSB(pending)];
    uint triangle = first & ((1u << VISIBILITY_OBJECT_SHIFT) - 1u);
    uvec3 v = uvec3(mesh_indices[3u * triangle], mesh_indices[3u * triangle + 1u], mesh_indices[3u * triangle + 2u]);
    uint same = 0u;
    for (int s = 0; s < n; s++) {
        if (id[s] == first) same |= 1u << uint(s);
    }
    pending &= ~same;
    // The three vertices' outputs, each read once.
    vec4 o[3][VERTEX_OUTPUT_VEC4S];
    for (int corner = 0; corner < 3; corner++) {
        for (uint k = 0u; k < VERTEX_OUTPUT_VEC4S; k++) {
            o[corner][k] = vertex_outputs[v[corner] * VERTEX_OUTPUT_VEC4S + k];
        }
    }
    vec4 c0 = o[0][0], c1 = o[1][0], c2 = o[2][0];
    vec3 b = barycentrics(c0, c1, c2, ndc);
    vec4 at[VERTEX_OUTPUT_VEC4S];
    for (uint k = 1u; k < VERTEX_OUTPUT_VEC4S; k++) {
        at[k] = b.x * o[0][k] + b.y * o[1][k] + b.z * o[2][k];
    }
    SurfaceInputs inputs = SurfaceInputs(at[1].xyz, at[2].xyz, at[3].xyz, vec3(at[1].w, at[2].w, at[3].w),
                                         at[4].xyz, vec4(at[5].xyz, at[4].w), at[6].xyz);
    float footprint = 0.0;
#ifdef BAKED
    // The footprint: how far (u, v) moves to the next pixel across and down, on the triangle's plane (the forward
    // pass's derivatives, taken fine). Against the exact reference this measures the forward pass's error or less
    // (docs/performance.md); the quad's coarse differences, or central ones, measured up to 8 % more.
    mat3 light = mat3(o[0][1].xyz, o[1][1].xyz, o[2][1].xyz);
    mat3 view = mat3(o[0][2].xyz, o[1][2].xyz, o[2][2].xyz);
    vec2 uv = table_uv(light, view, b);
    vec2 across = table_uv(light, view, barycentrics(c0, c1, c2, ndc + vec2(pixel_step.x, 0.0))) - uv;
    vec2 down = table_uv(light, view, barycentrics(c0, c1, c2, ndc + vec2(0.0, pixel_step.y))) - uv;
    footprint = min(max(length(across), length(down)), MAX_FOOTPRINT);
#endif
    float weight = float(bitCount(same)) / float(n);
    covered += weight;
    return weight * surface_colour(inputs, footprint);
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    int n = min(SAMPLE_COUNT, int(VISIBILITY_MAX_SAMPLES));
    uint id[VISIBILITY_MAX_SAMPLES];
    // The samples that see this object and are not shaded yet.
    uint pending = 0u;
    for (int s = 0; s < n; s++) {
        id[s] = SAMPLE_ID(pixel, s);
        if ((id[s] >> VISIBILITY_OBJECT_SHIFT) == visibility.object) pending |= 1u << uint(s);
    }
    // Where the object is not, nothing is written (and a block of pixels without it ends here).
    if (pending == 0u) discard;
    float covered = 0.0;
    // One shading per distinct triangle among the object's samples, each at the pixel centre: one for most pixels,
    // two or more on an edge. The first is written out and the rest looped: llvmpipe runs a loop's body at least
    // once for every block of pixels, whether a pixel needs it or not, so a loop around the only shading would
    // cost a third more at one sample (41 against 51-61 ms for the default scene at 800², docs/performance.md).
    vec3 rgb = shade_triangle(id, n, pending, covered);
#ifndef ONE_SAMPLE
    while (pending != 0u) rgb += shade_triangle(id, n, pending, covered);
#endif
    // Added to what the other objects wrote (blending ONE, ONE), over the constant background the target was
    // cleared to: the pixel ends as Σ colour + (1 − Σ covered) · background. Under an environment (background 0)
    // the background pass adds its share after (ONE_MINUS_DST_ALPHA).
    vec4 background = vec4(visibility.background_r, visibility.background_g, visibility.background_b,
                           visibility.background_a);
    out_color = vec4(rgb - covered * background.rgb, covered * (1.0 - background.a));
}
