// The shadow maps: the sun's (`render::shadow`) and the lamps' (`render::lamp_shadow`): how much of a light's disc
// reaches a point, 0 (umbra) to 1 (lit).
// Requires surface_frame.glsl (frame.shadow, frame.shadow_penumbra) and interface.glsl. The maps have one mip
// level, read with textureLod, so that compute shaders (the visibility buffer's edge pass) may call it too.

// 0 where the view casts no shadows (`render::scene_gpu`): the lookups compile out.
layout(constant_id = SPEC_SHADOWS) const uint SHADOWS = 1;

layout(set = 0, binding = BINDING_SHADOW) uniform sampler2DShadow shadow_map;
layout(set = 0, binding = BINDING_SHADOW_DEPTH) uniform sampler2D shadow_depths;

// The widest search and filter, in texels (a caster hundreds of texels above its shadow is blurred no further).
const float MAX_PENUMBRA_TEXELS = 256.0;

// Taps spread evenly over the unit disc: a Vogel (golden-angle) spiral of `count` points, point k at radius
// √((k + ½)/count) — equal areas — and angle k·137.5°.
vec2 tap(int k, int count) {
    float r = sqrt((float(k) + 0.5) / float(count));
    float a = float(k) * 2.39996323;
    return r * vec2(cos(a), sin(a));
}
// The blocker search's taps and the filter's: 1/WIDE_TAPS of the sun is the finest step of a penumbra wider
// than WIDE_TEXELS; a narrower one (a snake's on the ground: under a texel) is averaged over NARROW_TAPS bilinear
// comparisons.
const int SEARCH_TAPS = 16;
const int WIDE_TAPS = 32;
const int NARROW_TAPS = 4;
const float WIDE_TEXELS = 2.0;

// Percentage-closer soft shadows (Fernando 2005) with the sun's true disc: a point at depth z (the map's, 0 at
// its near plane) sees the sun through a cone of half-angle α; a blocker d world units above it along the rays
// hides the part of the disc whose rays cross it within d·tan α of the point's own ray. So: (1) search the
// texels any blocker could shadow it from (radius z·range·tan α) and average the depths of those nearer than
// it; (2) average the comparison over a disc of radius (z − blocker)·range·tan α, at least one texel (the map's
// own edges anti-aliased). `coord` is the point in the map's clip space (surface.vert's shadow_coord); outside
// the map the samplers' border passes (lit). 1 where the scene has no shadow map.
float sun_visibility(vec3 coord) {
    // No sun at all: lamps or a map without one light the scene alone (SUN; SurfaceUniforms::light_dir's w).
    if (SUN == 0u || frame.light_dir.w <= 0.0) return 0.0;
    if (SHADOWS == 0u || frame.shadow.x < 0.5) return 1.0;
    vec2 uv = coord.xy * 0.5 + 0.5;
    float z = min(coord.z, 1.0);
    float texel = frame.shadow.z;
    float texels_per_world = 1.0 / frame.shadow_penumbra.x;
    float depth_to_texels = frame.shadow_penumbra.y * frame.shadow_penumbra.z * texels_per_world;
    float search = clamp(z * depth_to_texels, 1.0, MAX_PENUMBRA_TEXELS);
    float blockers = 0.0;
    float count = 0.0;
    for (int k = 0; k < SEARCH_TAPS; ++k) {
        float d = textureLod(shadow_depths, uv + tap(k, SEARCH_TAPS) * search * texel, 0.0).r;
        if (d < z) {
            blockers += d;
            count += 1.0;
        }
    }
    if (count == 0.0) return 1.0;
    float radius = clamp((z - blockers / count) * depth_to_texels, 1.0, MAX_PENUMBRA_TEXELS);
    int taps = radius > WIDE_TEXELS ? WIDE_TAPS : NARROW_TAPS;
    float lit = 0.0;
    for (int k = 0; k < taps; ++k) {
        lit += textureLod(shadow_map, vec3(uv + tap(k, taps) * radius * texel, z), 0.0);
    }
    return lit / float(taps);
}

// The lamps' shadow maps (`render::lamp_shadow`): one atlas, lamp k's perspective map in tile k.
layout(set = 0, binding = BINDING_LAMP_SHADOW) uniform sampler2DShadow lamp_shadow_map;
layout(set = 0, binding = BINDING_LAMP_SHADOW_DEPTH) uniform sampler2D lamp_shadow_depths;

// Where lamp k's tile coordinates `uv` lie in the atlas, kept half a texel inside the tile (its neighbours'
// texels are other lamps' depths).
vec2 lamp_tile_uv(uint k, vec2 uv) {
    float half_texel = 0.5 * frame.lamp_atlas.y;
    vec2 inside = clamp(uv, vec2(half_texel), vec2(1.0 - half_texel));
    return vec2((float(k) + inside.x) / frame.lamp_atlas.x, inside.y);
}

// How much of lamp k's disc reaches the world point `p` (its normal `normal`), 0 (umbra) to 1 (lit): the sun's
// percentile-closer soft shadows in a perspective map. From p at depth d along the lamp's axis, the rays to a disc
// of radius R cross depth d_b (a blocker's) within R·(d − d_b)/d of p's own ray: R·(d − d_b)/(d·d_b) at depth 1,
// over a texel there (its scales' z) the penumbra's radius in texels; the search takes the nearest caster's depth
// (the near plane). The point is first pushed along its normal by SHADOW_NORMAL_OFFSET_TEXELS texels at its depth
// (growing as 1/cos θ_i up to SHADOW_MAX_OFFSET_GROWTH). 1 where the lamp casts no shadow or p lies outside its
// map (no caster there).
float lamp_visibility(uint k, vec3 p, vec3 normal) {
    if (SHADOWS == 0u) return 1.0;
    uint base = 4u * k;
    vec4 scales = frame.lamp_shadow_scales[k];
    float near = scales.x;
    float far = scales.y;
    if (near <= 0.0) return 1.0;
    mat4 view_proj = mat4(frame.lamp_shadow_view_proj[base], frame.lamp_shadow_view_proj[base + 1u],
                          frame.lamp_shadow_view_proj[base + 2u], frame.lamp_shadow_view_proj[base + 3u]);
    vec3 n = normalize(normal);
    vec3 to_lamp = normalize(frame.lamps[LAMP_VEC4S * k].xyz - p);
    float growth = min(1.0 / max(abs(dot(n, to_lamp)), 1e-3), SHADOW_MAX_OFFSET_GROWTH);
    float depth_here = (view_proj * vec4(p, 1.0)).w;
    vec3 lifted = p + n * (SHADOW_NORMAL_OFFSET_TEXELS * depth_here * scales.z * growth);
    vec4 clip = view_proj * vec4(lifted, 1.0);
    // Nearer than every caster (or behind the lamp): lit.
    if (clip.w <= near) return 1.0;
    vec3 ndc = clip.xyz / clip.w;
    if (any(greaterThan(abs(ndc.xy), vec2(1.0)))) return 1.0;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    float z = min(ndc.z, 1.0);
    float d = clip.w;
    float texel = frame.lamp_atlas.y;
    float disc_texels = scales.w / scales.z;
    float search = clamp(disc_texels * (d - near) / (d * near), 1.0, MAX_PENUMBRA_TEXELS);
    float blockers = 0.0;
    float count = 0.0;
    for (int i = 0; i < SEARCH_TAPS; ++i) {
        float b = textureLod(lamp_shadow_depths, lamp_tile_uv(k, uv + tap(i, SEARCH_TAPS) * search * texel), 0.0).r;
        if (b < z) {
            // The blocker's depth along the axis (the map's depth is 0 at near, 1 at far, in 1/depth).
            blockers += near * far / (far - b * (far - near));
            count += 1.0;
        }
    }
    if (count == 0.0) return 1.0;
    float blocker = blockers / count;
    float radius = clamp(disc_texels * (d - blocker) / (d * blocker), 1.0, MAX_PENUMBRA_TEXELS);
    int taps = radius > WIDE_TEXELS ? WIDE_TAPS : NARROW_TAPS;
    float lit = 0.0;
    for (int i = 0; i < taps; ++i) {
        lit += textureLod(lamp_shadow_map, vec3(lamp_tile_uv(k, uv + tap(i, taps) * radius * texel), z), 0.0);
    }
    return lit / float(taps);
}
