// The surface's shading (surface.frag: one fragment; surface_resolve.frag: one triangle of a visibility-buffer
// pixel): diffraction (the thesis's approaches, or the baked table) plus the skin's pigment under the grating, lit
// by the light the surface transmits (1 − R, exact Fresnel; the thesis's texture blending, model.md §3.8) from the sun's
// disc, from the sky above the horizon and from the lamps. Include after the diffraction, frame, shadow and sky
// includes.

// What the vertex shader hands a surface point (surface.vert's outputs, interpolated).
struct SurfaceInputs {
    vec3 patch_light;
    vec3 patch_view;
    vec3 world_normal;
    vec3 tint;
    vec3 shadow_coord;
    vec4 patch_axis;
    vec3 sky_diffracted_at_vertex;
    vec3 world_position;
    // Where the object's maps are read (maps.glsl).
    vec2 uv;
};

#include "pigment.glsl"
#include "lamps.glsl"

// 1 in a matte material's pipelines: no grating, no skin, no footprint (the diffraction compiles out).
layout(constant_id = SPEC_MATTE) const uint MATTE = 0;

// Whether the material has the skin and its grating (else matte: only its pigment).
bool coated_material() {
    return MATTE == 0u && frame.orientation.w < 0.5;
}
#include "maps.glsl"

// `s` with the object's maps applied at its uv (`dx`, `dy`: the uv's steps to the next pixel across and down); its
// normal map alone where not `pigment` (a neighbouring point whose frame only sets a footprint).
SurfaceInputs mapped(SurfaceInputs s, vec2 dx, vec2 dy, bool pigment) {
    apply_maps(s.uv, dx, dy, pigment, s.world_position, s.tint, s.patch_light, s.patch_view, s.world_normal,
               s.patch_axis);
    return s;
}

// The diffraction of light from `omega_i` towards `omega_r` (patch frame), linear RGB relative to the light's
// (times `params.light_white.w` in physical units); `steps`: the pixel's footprint in (u, v) (baked only).
vec3 diffraction_rgb(vec3 omega_i, vec3 omega_r, vec4 steps) {
#ifdef BAKED
    // Without footprint filtering, no steps: one read at level 0.
    return xyz_to_linear_srgb(baked_diffraction_xyz_over(omega_i, omega_r, FOOTPRINT == 1u ? steps : vec4(0.0)));
#else
    return xyz_to_linear_srgb(diffraction_xyz(omega_i, omega_r));
#endif
}

// The world direction `d` in the patch frame at a surface point (its interpolated normal and patch axis, as the
// sky's diffraction reads them).
vec3 patch_direction(SurfaceInputs s, vec3 d) {
    vec3 normal = normalize(s.world_normal);
    vec3 x = normalize(s.patch_axis.xyz - normal * dot(normal, s.patch_axis.xyz));
    vec3 y = s.patch_axis.w * cross(normal, x);
    return vec3(dot(d, x), dot(d, y), dot(d, normal));
}

// Lamp k's direction in the patch frame at the surface point (xyz) and its irradiance there at normal incidence
// per unit of the frame's luminance (w): lamps.glsl's `lamp_light`.
vec4 lamp_at(SurfaceInputs s, uint k) {
    vec4 lamp = lamp_light(k, s.world_position);
    return vec4(patch_direction(s, lamp.xyz), lamp.w);
}

// What lamp k (`lamp`: `lamp_at`) adds to the surface point's colour: its diffraction and the pigment it lights,
// as the sun's, its irradiance in place of the sun's Ω_sun, times the share of its disc no shadow hides
// (shadow.glsl's `lamp_visibility`); `steps`: the pixel's footprint in the lamp's (u, v). Where the material's
// coherence follows the light (params.window.w, its length), the baked read is widened to the lamp's shorter
// coherence (model.md §3.13); the Taylor approaches keep the material's.
vec3 lamp_colour(SurfaceInputs s, uint k, vec4 lamp, vec4 steps) {
    vec3 omega_i = lamp.xyz;
    vec3 omega_r = normalize(s.patch_view);
    bool coated = coated_material();
    float visible = lamp.w > 0.0 ? lamp_visibility(k, s.world_position, s.world_normal) : 0.0;
    float share = lamp.w / SUN_SOLID_ANGLE;
    vec3 rgb = vec3(0.0);
    if (coated && omega_i.z > 0.0 && share > 0.0 && visible > 0.0) {
#ifdef BAKED
        if (params.window.w > 0.0) {
            steps = widen_steps(steps, widening_variance(lamp_coherence_um(k, s.world_position), params.window.w));
        }
#endif
        rgb = diffraction_rgb(omega_i, omega_r, steps) * (params.light_white.w * share * visible);
    }
    vec3 albedo = frame.pigment.rgb * s.tint;
    return rgb + pigment_rgb(omega_i, omega_r, 0.0, albedo, 0.0, visible, coated) * params.light_white.rgb * share;
}

// The linear RGB a surface point sends towards the camera (the sun's and the environment's light; the lamps'
// is `lamp_colour`'s); `steps`: the pixel's steps in (u, v), across and down,
// which the baked table filters over (footprint.glsl's `footprint_steps`; unused by the Taylor approaches).
vec3 surface_colour(SurfaceInputs s, vec4 steps) {
    vec3 omega_i = normalize(s.patch_light);
    vec3 omega_r = normalize(s.patch_view);
    // A matte material (a ground) has no grating and no skin: only its pigment.
    bool coated = coated_material();
    // The sun's share that no shadow hides (1 where the scene has no shadow map).
    float sun_visible = sun_visibility(s.shadow_coord);
    vec3 rgb = vec3(0.0);
    if (coated && sun_visible > 0.0) {
        rgb = diffraction_rgb(omega_i, omega_r, steps);
        // 1 in relative units; under a physical light, the BRDF in sr⁻¹ times the sun's irradiance per unit of
        // its radiance (`spectrum::diffraction_gain`).
        rgb *= params.light_white.w * sun_visible;
    }
    vec3 normal = normalize(s.world_normal);
    float normal_up = normal.y;
    vec3 albedo = frame.pigment.rgb * s.tint;
    rgb += pigment_rgb(omega_i, omega_r, normal_up, albedo, frame.pigment.w, sun_visible, coated) * params.light_white.rgb;
    rgb += pigment_sky_rgb(omega_r, albedo, sky_over_pi(normal), coated);
    if (coated) {
        // The environment's own diffraction (no shadow: like the sky's light on the pigment, it is not occluded).
        vec3 x = normalize(s.patch_axis.xyz - normal * dot(normal, s.patch_axis.xyz));
        rgb += sky_diffraction(omega_r, x, s.patch_axis.w * cross(normal, x), normal, s.sky_diffracted_at_vertex);
    }
    return rgb;
}
