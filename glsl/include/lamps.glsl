// Lamps (`light::lamp`, their twin: the same names): point and spot lights in `frame.lamps`, LAMP_VEC4S each
// (`light::lamp::LampUniforms`): (position, intensity over the frame's unit of luminance), (a spot's axis,
// its cone's half-angle in degrees: 360 for a point lamp), (its edge's width in degrees, the disc's radius², the
// coherence length times the angular radius that gives it, the disc's radius).
// Requires surface_frame.glsl.

// The share of a spot's intensity at `angle_deg` from its axis: 1 inside cone − soft, 0 beyond the cone, a
// smoothstep between (`lamp::spot_factor`).
float spot_factor(float angle_deg, float cone_deg, float soft_deg) {
    float t = clamp((cone_deg - angle_deg) / max(soft_deg, 1e-6), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// How many lamps light the view (`render::variants::ViewSpec`; `frame.lamp_count.x` holds the same number): a
// constant, so that the lamps compile out where there are none, stay in uniform control flow, and are each shaded
// at a constant index (EACH_LAMP: a count read from the uniforms cost a lamp-lit frame 1.5× on lavapipe).
layout(constant_id = SPEC_LAMPS) const uint LAMPS = 0;

// `statement` once for each lamp, with `k` its index as a constant: on lavapipe a loop of LAMPS iterations (left
// rolled for two lamps) cost as much as a count read from the uniforms (likely: uniforms read at an index that
// varies are read lane by lane).
#if MAX_LAMPS != 8
#error "EACH_LAMP writes out MAX_LAMPS lamps"
#endif
#define EACH_LAMP(k, statement) \
    { const uint k = 0u; if (LAMPS > k) { statement; } } \
    { const uint k = 1u; if (LAMPS > k) { statement; } } \
    { const uint k = 2u; if (LAMPS > k) { statement; } } \
    { const uint k = 3u; if (LAMPS > k) { statement; } } \
    { const uint k = 4u; if (LAMPS > k) { statement; } } \
    { const uint k = 5u; if (LAMPS > k) { statement; } } \
    { const uint k = 6u; if (LAMPS > k) { statement; } } \
    { const uint k = 7u; if (LAMPS > k) { statement; } }

// The coherence length of lamp k's light at the world point `p`, µm: sunlight's 65 µm times the sun's angular
// radius over the lamp's there, at least 1 µm (`Lamp::coherence_at`; model.md §1.13).
float lamp_coherence_um(uint k, vec3 p) {
    vec4 disc = frame.lamps[LAMP_VEC4S * k + 2u];
    return max(disc.z / atan(disc.w, length(frame.lamps[LAMP_VEC4S * k].xyz - p)), 1.0);
}

// The unit vector from the world point `p` towards lamp k (`lamp_light`'s direction alone, the same bits).
vec3 lamp_direction(uint k, vec3 p) {
    vec3 to_lamp = frame.lamps[LAMP_VEC4S * k].xyz - p;
    return to_lamp * inversesqrt(max(dot(to_lamp, to_lamp), 1e-30));
}

// Lamp k seen from the world point `p`: the unit vector towards it (xyz) and its irradiance at normal incidence
// there per unit of the frame's luminance (w, in sr, as the sun's Ω_sun is): I/(d² + r²), the inverse-square law
// made finite at the disc (exact on the axis of a disc of radius r; `Lamp::illuminance`).
vec4 lamp_light(uint k, vec3 p) {
    vec4 at = frame.lamps[LAMP_VEC4S * k];
    vec4 beam = frame.lamps[LAMP_VEC4S * k + 1u];
    vec4 disc = frame.lamps[LAMP_VEC4S * k + 2u];
    vec3 to_lamp = at.xyz - p;
    float d2 = dot(to_lamp, to_lamp);
    vec3 l = to_lamp * inversesqrt(max(d2, 1e-30));
    // A point lamp (its cone 360°) lights every way: no angle to work out (spot_factor would give 1 at any).
    float angle_deg = beam.w >= 180.0 ? 0.0 : degrees(acos(clamp(dot(-l, beam.xyz), -1.0, 1.0)));
    return vec4(l, at.w * spot_factor(angle_deg, beam.w, disc.x) / (d2 + disc.y));
}
