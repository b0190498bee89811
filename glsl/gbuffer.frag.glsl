#version 460
// The G-buffer: what each pixel of a scene sees, unshaded — the patch-frame directions, the material and the
// pixel's footprint in (u, v). It sizes the baked tables to the views a frame shows and gives the profiler's exact
// CPU reference its inputs. Shares surface.vert and its uniforms (`orientation.z` holds the material's index).
#include "surface_frame.glsl"
#include "footprint.glsl"
#include "shadow.glsl"
#include "maps.glsl"

// 0: (ω_i, material + 1); 1: (ω_r, footprint); 2: (pigment albedo, normal · up); 3: (the world normal, the sun's
// visible share: shadow.glsl); 4: (the patch's x axis in the world, its handedness: y = w·(normal × x)); 5: (the
// point in the world, 1: where the lamps are seen from); 6 and 7: the visible shares of lamps 1–4 and 5–8.
layout(constant_id = SPEC_GBUFFER_PART) const uint PART = 0;

layout(location = 0) in vec3 patch_light;
layout(location = 1) in vec3 patch_view;
layout(location = 2) in vec3 world_normal;
layout(location = 3) in vec3 tint;
layout(location = 4) in vec3 shadow_coord;
layout(location = 5) in vec4 patch_axis;
layout(location = 7) in vec3 world_position;
layout(location = 8) in vec2 uv;
layout(location = 0) out vec4 out_color;

void main() {
    // The object's maps, as the surface pass applies them: what the exact reference shades is the mapped surface.
    vec3 light = patch_light, view = patch_view, normal = world_normal, albedo = tint;
    vec4 axis = patch_axis;
    if (has_maps()) apply_maps(uv, dFdx(uv), dFdy(uv), true, world_position, albedo, light, view, normal, axis);
    vec3 omega_i = normalize(light);
    vec3 omega_r = normalize(view);
    float footprint = pixel_footprint(-omega_i.xy - omega_r.xy);
    if (PART == 0u) {
        out_color = vec4(omega_i, frame.orientation.z + 1.0);
    } else if (PART == 1u) {
        out_color = vec4(omega_r, footprint);
    } else if (PART == 2u) {
        out_color = vec4(frame.pigment.rgb * albedo, normalize(normal).y);
    } else if (PART == 3u) {
        out_color = vec4(normalize(normal), sun_visibility(shadow_coord));
    } else if (PART == 4u) {
        out_color = axis;
    } else if (PART == 5u) {
        out_color = vec4(world_position, 1.0);
    } else {
        uint first = PART == 6u ? 0u : 4u;
        vec4 shares = vec4(1.0);
        for (uint k = 0u; k < 4u; ++k) {
            if (first + k < uint(frame.lamp_count.x)) shares[k] = lamp_visibility(first + k, world_position, normal);
        }
        out_color = shares;
    }
}
