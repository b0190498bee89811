#version 460
// The surface pass: a mesh shaded by diffraction. The tangent frame orients the patch on the surface:
// x = the vertex tangent (made orthogonal to the normal), y = w·(normal × tangent), z = the normal.
// Light and view are expressed in that frame here and interpolated per fragment; the view vector stays
// unnormalised so that its interpolation is exact (model.md §4). Positions go through the model matrix and the
// camera is the current one (the thesis used object-space positions and a stale camera: §7.2 item 14).
#include "surface_frame.glsl"

#include "vertex_inputs.glsl" // in_position, in_normal, in_tangent, in_pigment, in_uv (gpu::shaders::VERTEX_ATTRIBUTES)

layout(location = 0) out vec3 patch_light;
layout(location = 1) out vec3 patch_view;
// The shading normal in the world (the sky lights what faces up) and the vertex's tint of the material's pigment.
layout(location = 2) out vec3 world_normal;
layout(location = 3) out vec3 tint;
// The point in the sun's shadow map's clip space, pushed off its surface along the normal towards the light
// (`render::shadow`: by frame.shadow.y, growing as 1/cos θ_i up to SHADOW_MAX_OFFSET_GROWTH) so that a surface
// does not shadow itself.
layout(location = 4) out vec3 shadow_coord;
// The patch's x axis in the world and the frame's handedness w (its y is w·(normal × x)): how the environment is
// seen from the patch (sky_diffraction.glsl).
layout(location = 5) out vec4 patch_axis;
// The environment's light diffracted towards the view at this vertex (sky_diffraction.glsl's `sky_diffracted`) in
// the variant built with SKY_DIFFRACTION_AT_VERTEX (`surface_sky.vert`); zero in the others.
layout(location = 6) out vec3 sky_diffracted_at_vertex;
// The point in the world (where the lamps are seen from: lamps.glsl).
layout(location = 7) out vec3 world_position;
// Where the object's maps are read (maps.glsl).
layout(location = 8) out vec2 uv;

#ifdef SKY_DIFFRACTION_AT_VERTEX
#include "brdf.glsl"
#include "sky_diffraction.glsl"
#endif

#ifdef VISIBILITY
// The visibility buffer's raster pass (`render::visibility`, the variants `surface_visibility.vert` and
// `surface_sky_visibility.vert`) also keeps every vertex's outputs, from which its shading pass rebuilds a pixel's
// inputs (surface_resolve.frag reads them in this order).
layout(std430, binding = BINDING_VERTEX_OUTPUTS) writeonly buffer VertexOutputs {
    vec4 vertex_outputs[];
};
#endif

void main() {
    // The depth pre-pass and the shading pass run this shader in two pipelines, and the shading pass's EQUAL depth
    // test needs both to compute the same bits: `precise` forbids the contractions and reorderings that a compiler
    // might choose differently in each. (`invariant gl_Position` says the same, but Debian 12's validation layer
    // rejects the decoration glslang puts on the gl_PerVertex member.)
    precise vec4 p = frame.model * vec4(in_position, 1.0);
    vec3 n = normalize(mat3(frame.normal_matrix) * in_normal);
    vec3 t = mat3(frame.model) * in_tangent.xyz;
    t = normalize(t - n * dot(n, t));
    vec3 b = in_tangent.w * cross(n, t);
    // The material's orientation turns the patch about the normal.
    vec3 patch_x = frame.orientation.x * t + frame.orientation.y * b;
    vec3 patch_y = frame.orientation.x * b - frame.orientation.y * t;
    t = patch_x;
    b = patch_y;
    vec3 l = normalize(frame.light_dir.xyz);
    patch_light = vec3(dot(l, t), dot(l, b), dot(l, n));
    vec3 v = frame.camera_pos.xyz - p.xyz;
    patch_view = vec3(dot(v, t), dot(v, b), dot(v, n));
    world_normal = n;
    world_position = p.xyz;
    patch_axis = vec4(t, in_tangent.w < 0.0 ? -1.0 : 1.0);
    tint = in_pigment;
    uv = in_uv;
#ifdef SKY_DIFFRACTION_AT_VERTEX
    sky_diffracted_at_vertex = sky_diffracted(normalize(patch_view), t, b, n);
#else
    sky_diffracted_at_vertex = vec3(0.0);
#endif
    float cos_l = dot(n, l);
    float growth = min(1.0 / max(abs(cos_l), 1e-3), SHADOW_MAX_OFFSET_GROWTH);
    vec3 lifted = p.xyz + (cos_l >= 0.0 ? n : -n) * (frame.shadow.y * growth);
    shadow_coord = (frame.shadow_view_proj * vec4(lifted, 1.0)).xyz;
    precise vec4 clip = frame.view_proj * p;
    gl_Position = clip;
#ifdef VISIBILITY
    // A vertex that several triangles share writes the same values each time it is shaded.
    uint base = uint(gl_VertexIndex) * VERTEX_OUTPUT_VEC4S;
    vertex_outputs[base] = clip;
    vertex_outputs[base + 1u] = vec4(patch_light, tint.r);
    vertex_outputs[base + 2u] = vec4(patch_view, tint.g);
    vertex_outputs[base + 3u] = vec4(world_normal, tint.b);
    vertex_outputs[base + 4u] = vec4(shadow_coord, patch_axis.w);
    vertex_outputs[base + 5u] = vec4(patch_axis.xyz, uv.x);
    vertex_outputs[base + 6u] = vec4(sky_diffracted_at_vertex, uv.y);
#endif
}
