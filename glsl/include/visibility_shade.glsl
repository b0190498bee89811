// The visibility buffer's shading of one pixel's visible triangles (`render::visibility`), shared by the shading
// pass (surface_resolve.frag: each pixel's first triangle) and the edge pass (surface_edges.comp: the further
// triangles of the pixels that see more than one). Include after surface_shade.glsl and visibility_push.glsl.

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

// The object's pixels that see more than one of its triangles (`VisibilityState::edges`), appended by the shading
// pass and the edge pass: one list for each further triangle (list k − 1 holds the pixels that see more than k
// triangles, whose (k + 1)-th the edge pass's k-th dispatch shades and then lists the pixel in list k if it sees
// more still), each of `edge_list_words()` words: the indirect dispatch's work groups (x grows by one for every
// VISIBILITY_EDGE_GROUP pixels; y and z are 1), the number of pixels, then each pixel as x | y << 16.
layout(std430, binding = BINDING_VISIBILITY_EDGES) buffer VisibilityEdges {
    uint edge_words[];
};

uint edge_list_words() {
    ivec2 size = IDS_SIZE;
    return 4u + uint(size.x) * uint(size.y);
}

// Appends `pixel` to edge list `k`.
void list_edge_pixel(uint k, ivec2 pixel) {
    uint list = k * edge_list_words();
    uint i = atomicAdd(edge_words[list + 3u], 1u);
    edge_words[list + 4u + i] = uint(pixel.x) | uint(pixel.y) << 16;
    if (i % VISIBILITY_EDGE_GROUP == 0u) atomicAdd(edge_words[list], 1u);
}
#endif
layout(std430, binding = BINDING_VERTEX_OUTPUTS) readonly buffer VertexOutputs {
    vec4 vertex_outputs[];
};
layout(std430, binding = BINDING_MESH_INDICES) readonly buffer MeshIndices {
    uint mesh_indices[];
};

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

// A triangle's surface inputs at barycentrics `b`, from its three vertices' outputs `o`: what the rasteriser would
// have interpolated, and the point in the world (the interpolated clip position taken back through the camera).
SurfaceInputs inputs_at(vec4 o[3][VERTEX_OUTPUT_VEC4S], vec3 b) {
    vec4 at[VERTEX_OUTPUT_VEC4S];
    for (uint k = 0u; k < VERTEX_OUTPUT_VEC4S; k++) {
        at[k] = b.x * o[0][k] + b.y * o[1][k] + b.z * o[2][k];
    }
    vec4 point = frame.inverse_view_proj * at[0];
    return SurfaceInputs(at[1].xyz, at[2].xyz, at[3].xyz, vec3(at[1].w, at[2].w, at[3].w), at[4].xyz,
                         vec4(at[5].xyz, at[4].w), at[6].xyz, point.xyz / point.w, vec2(at[5].w, at[6].w));
}

// The (u, v) the sun's light is read at for a surface point.
vec2 sun_table_uv(SurfaceInputs s) {
    return -normalize(s.patch_light).xy - normalize(s.patch_view).xy;
}

// The (u, v) lamp k's light is read at for a surface point (its direction alone: no spot or irradiance).
vec2 lamp_table_uv(SurfaceInputs s, uint k) {
    return -patch_direction(s, lamp_direction(k, s.world_position)).xy - normalize(s.patch_view).xy;
}

// The ids of the `n` samples of `pixel` (id), and a bit for each that sees the drawn object.
uint object_samples(ivec2 pixel, int n, out uint id[VISIBILITY_MAX_SAMPLES]) {
    uint samples = 0u;
    for (int s = 0; s < n; s++) {
        id[s] = SAMPLE_ID(pixel, s);
        if ((id[s] >> VISIBILITY_OBJECT_SHIFT) == visibility.object) samples |= 1u << uint(s);
    }
    return samples;
}

// The samples (bits, of `n`) that see the same triangle as the first of `pending`.
uint first_triangle_samples(uint id[VISIBILITY_MAX_SAMPLES], int n, uint pending) {
    uint first = id[findLSB(pending)];
    uint same = 0u;
    for (int s = 0; s < n; s++) {
        if (id[s] == first) same |= 1u << uint(s);
    }
    return same;
}

// What lamp k adds to the colour of a surface point (`inputs`), its footprint from the points of the next pixels
// across and down.
vec3 lamp_term(SurfaceInputs inputs, SurfaceInputs inputs_across, SurfaceInputs inputs_down, uint k) {
    vec4 lamp = lamp_at(inputs, k);
    vec4 lamp_steps = vec4(0.0);
#ifdef BAKED
    if (MATTE == 0u) {
        vec2 lamp_uv = -lamp.xy - normalize(inputs.patch_view).xy;
        lamp_steps = footprint_steps(lamp_table_uv(inputs_across, k) - lamp_uv, lamp_table_uv(inputs_down, k) - lamp_uv);
    }
#endif
    return lamp_colour(inputs, k, lamp, lamp_steps);
}

// The share of the colour of the pixel whose centre is `centre` (pixels, as gl_FragCoord.xy) of the triangle that
// the first of the `pending` samples sees (bits of `id`, of `n`): its inputs rebuilt at the pixel centre and
// shaded, weighed by the samples that see it, which it then clears from `pending`.
vec3 shade_triangle(vec2 centre, uint id[VISIBILITY_MAX_SAMPLES], int n, inout uint pending) {
    vec2 size = vec2(IDS_SIZE);
    vec2 ndc = centre / size * 2.0 - 1.0;
    vec2 pixel_step = 2.0 / size;
    uint triangle = id[findLSB(pending)] & ((1u << VISIBILITY_OBJECT_SHIFT) - 1u);
    uvec3 v = uvec3(mesh_indices[3u * triangle], mesh_indices[3u * triangle + 1u], mesh_indices[3u * triangle + 2u]);
    uint same = first_triangle_samples(id, n, pending);
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
    SurfaceInputs inputs = inputs_at(o, b);
    // The points of the next pixels across and down on the triangle's plane: the maps' gradients, and the baked
    // read's footprint (how far (u, v) moves to them: the forward pass's derivatives, taken fine). Against the exact
    // reference this measures the forward pass's error or less (docs/performance.md); the quad's coarse
    // differences, or central ones, measured up to 8 % more.
    vec3 b_across = barycentrics(c0, c1, c2, ndc + vec2(pixel_step.x, 0.0));
    vec3 b_down = barycentrics(c0, c1, c2, ndc + vec2(0.0, pixel_step.y));
    bool maps = has_maps();
    // Whether the mapped normal turns the frame, so that the footprint needs the neighbours' mapped frames.
    bool turned = maps && frame.maps.y > 0.0;
    SurfaceInputs inputs_across = inputs, inputs_down = inputs;
    if (maps) {
        vec3 us = vec3(o[0][5].w, o[1][5].w, o[2][5].w), vs = vec3(o[0][6].w, o[1][6].w, o[2][6].w);
        vec2 dx = vec2(dot(b_across, us), dot(b_across, vs)) - inputs.uv;
        vec2 dy = vec2(dot(b_down, us), dot(b_down, vs)) - inputs.uv;
        inputs = mapped(inputs, dx, dy, true);
        if (turned) {
            // Each neighbour's frame turned with the same gradients: the footprint follows the mapped normal.
            inputs_across = mapped(inputs_at(o, b_across), dx, dy, false);
            inputs_down = mapped(inputs_at(o, b_down), dx, dy, false);
        }
    }
    vec4 steps = vec4(0.0);
#ifdef BAKED
    if (MATTE != 0u) {
        // A matte material reads no table.
    } else if (turned) {
        vec2 uv = sun_table_uv(inputs);
        steps = footprint_steps(sun_table_uv(inputs_across) - uv, sun_table_uv(inputs_down) - uv);
    } else {
        mat3 light = mat3(o[0][1].xyz, o[1][1].xyz, o[2][1].xyz);
        mat3 view = mat3(o[0][2].xyz, o[1][2].xyz, o[2][2].xyz);
        vec2 uv = table_uv(light, view, b);
        steps = footprint_steps(table_uv(light, view, b_across) - uv, table_uv(light, view, b_down) - uv);
    }
#endif
    vec3 rgb = surface_colour(inputs, steps);
    if (LAMPS == 0u) return float(bitCount(same)) / float(n) * rgb;
#ifdef BAKED
    // Each lamp's footprint as the sun's: its (u, v) at the next pixel across and down, on the triangle's plane
    // (the neighbours' inputs built once for every lamp; mapped above where a normal map turns them).
    if (!turned && MATTE == 0u) {
        inputs_across = inputs_at(o, b_across);
        inputs_down = inputs_at(o, b_down);
    }
#endif
    EACH_LAMP(k, rgb += lamp_term(inputs, inputs_across, inputs_down, k));
    return float(bitCount(same)) / float(n) * rgb;
}
