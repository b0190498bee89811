// The surface's shading (surface.frag: one fragment; surface_resolve.frag: one triangle of a visibility-buffer
// pixel): diffraction (the thesis's approaches, or the baked table) plus the skin's pigment under the grating, lit
// by the light the surface transmits (1 − R, exact Fresnel; the thesis's texture blending, model.md §3.8) from the sun's
// disc and from the sky above the horizon. Include after the diffraction, frame, shadow and sky includes.

// What the vertex shader hands a surface point (surface.vert's outputs, interpolated).
struct SurfaceInputs {
    vec3 patch_light;
    vec3 patch_view;
    vec3 world_normal;
    vec3 tint;
    vec3 shadow_coord;
    vec4 patch_axis;
    vec3 sky_diffracted_at_vertex;
};

#include "pigment.glsl"

// The linear RGB a surface point sends towards the camera; `steps`: the pixel's steps in (u, v), across and down,
// which the baked table filters over (footprint.glsl's `footprint_steps`; unused by the Taylor approaches).
vec3 surface_colour(SurfaceInputs s, vec4 steps) {
    vec3 omega_i = normalize(s.patch_light);
    vec3 omega_r = normalize(s.patch_view);
    // A matte material (a ground) has no grating and no skin: only its pigment.
    bool coated = frame.orientation.w < 0.5;
    // The sun's share that no shadow hides (1 where the scene has no shadow map).
    float sun_visible = sun_visibility(s.shadow_coord);
    vec3 rgb = vec3(0.0);
    if (coated && sun_visible > 0.0) {
#ifdef BAKED
        // Without footprint filtering, no steps: one read at level 0.
        rgb = xyz_to_linear_srgb(baked_diffraction_xyz_over(omega_i, omega_r, FOOTPRINT == 1u ? steps : vec4(0.0)));
#else
        rgb = xyz_to_linear_srgb(diffraction_xyz(omega_i, omega_r));
#endif
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
