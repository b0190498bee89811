#version 460
// The environment behind a scene (`render::background`): each pixel's view ray looked up in the equirectangular
// map (panorama.glsl), in the frame's units, and display-encoded like the surface pass's output where the target
// is the display's.
#include "interface.glsl"
#include "background_uniforms.glsl"
#include "display.glsl"
#include "panorama.glsl"

// The depth test first: the samples an object covers never run this shader.
layout(early_fragment_tests) in;

layout(constant_id = SPEC_DISPLAY_OUTPUT) const uint DISPLAY_OUTPUT = 0;
layout(set = 0, binding = BINDING_ENVIRONMENT) uniform sampler2D environment_map;
layout(location = 0) in vec2 ndc;
layout(location = 0) out vec4 out_color;


void main() {
    vec4 far = background.inverse_view_proj * vec4(ndc, 0.0, 1.0); // the far plane (reversed depth: 0)
    vec3 d = normalize(far.xyz / far.w - background.camera.xyz);
    // The map turned by its rotation about +y.
    vec3 rgb = texture(environment_map, panorama_uv(d, background.view.y)).rgb * background.view.x;
    out_color = vec4(DISPLAY_OUTPUT == 1u ? display_encode(rgb, background.display.x, background.display.y) : rgb, 1.0);
}
