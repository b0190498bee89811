// The sun's shadow map (`render::shadow`): how much of the sun's disc reaches a point, 0 (umbra) to 1 (lit).
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
    // No sun at all: a map without one lights the scene alone (SurfaceUniforms::light_dir's w).
    if (frame.light_dir.w <= 0.0) return 0.0;
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
