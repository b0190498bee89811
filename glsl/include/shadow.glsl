// The sun's shadow map (`render::shadow`): how much of the sun reaches a point, 0 (shadowed) to 1 (lit).
// Requires surface_frame.glsl (frame.shadow) and interface.glsl.

layout(set = 0, binding = BINDING_SHADOW) uniform sampler2DShadow shadow_map;

// Percentage-closer filtering: 3×3 taps one texel apart, each a bilinear comparison where the device filters
// depth (a soft edge about three texels wide). `coord` is the point in the map's clip space (surface.vert's
// shadow_coord); outside the map the sampler's border passes (lit). 1 where the scene has no shadow map.
float sun_visibility(vec3 coord) {
    if (frame.shadow.x < 0.5) return 1.0;
    vec2 uv = coord.xy * 0.5 + 0.5;
    float depth = min(coord.z, 1.0);
    float lit = 0.0;
    for (int y = -1; y <= 1; ++y) {
        for (int x = -1; x <= 1; ++x) {
            lit += texture(shadow_map, vec3(uv + vec2(x, y) * frame.shadow.z, depth));
        }
    }
    return lit / 9.0;
}
