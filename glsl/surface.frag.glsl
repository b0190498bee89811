#version 460
// The surface pass: each fragment shaded by surface_shade.glsl (diffraction plus the skin's pigment under the
// grating) with the inputs its vertices give it.
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

// After a depth pre-pass only the visible surface passes the EQUAL test; without one (meshes drawn front first,
// `Mesh::front_first`) a fragment that a surface drawn before it hides fails LESS. Testing before the shader runs
// (which the counting variant's atomics would otherwise forbid) shades each pixel once, or about once.
layout(early_fragment_tests) in;

layout(location = 0) in vec3 patch_light;
layout(location = 1) in vec3 patch_view;
layout(location = 2) in vec3 world_normal;
layout(location = 3) in vec3 tint;
layout(location = 4) in vec3 shadow_coord;
layout(location = 5) in vec4 patch_axis;
layout(location = 6) in vec3 sky_diffracted_at_vertex;
layout(location = 7) in vec3 world_position;
layout(location = 8) in vec2 uv;
layout(location = 0) out vec4 out_color;

// What lamp k adds to the fragment's colour (its footprint from the derivatives of its (u, v)).
vec3 lamp_term(SurfaceInputs s, uint k) {
    vec4 lamp = lamp_at(s, k);
    vec4 lamp_steps = vec4(0.0);
#ifdef BAKED
    if (MATTE == 0u) lamp_steps = pixel_steps(-lamp.xy - normalize(s.patch_view).xy);
#endif
    return lamp_colour(s, k, lamp, lamp_steps);
}

void main() {
    SurfaceInputs s = SurfaceInputs(patch_light, patch_view, world_normal, tint, shadow_coord, patch_axis,
                                    sky_diffracted_at_vertex, world_position, uv);
    // The maps first, so that the footprint below follows the mapped normal's change across the pixel.
    if (has_maps()) s = mapped(s, dFdx(uv), dFdy(uv), true);
    vec4 steps = vec4(0.0);
#ifdef BAKED
    // Derivatives, so in uniform control flow (before the shading's branches); none for a matte material.
    if (MATTE == 0u) steps = pixel_steps(-normalize(s.patch_light).xy - normalize(s.patch_view).xy);
#endif
    vec3 rgb = surface_colour(s, steps);
    // The lamps' count is a constant, so each lamp's derivatives too are taken in uniform control flow (and a view
    // without lamps has none: LAMPS, a specialization constant).
    EACH_LAMP(k, rgb += lamp_term(s, k));
    out_color = vec4(DISPLAY_OUTPUT == 1u ? display_encode(rgb, params.display.x, params.display.y) : rgb, 1.0);
    record_fetches();
}
