#version 460
// The environment behind a scene (`render::background`): each pixel's view ray looked up in the equirectangular
// map (the layout of `environment::direction_at`: x the azimuth from −180° to 180°, 0 along +z and 90° along +x;
// y the elevation from +90° at the top), in the frame's units, and display-encoded like the surface pass's output
// where the target is the display's.
#include "interface.glsl"
#include "background_uniforms.glsl"
#include "display.glsl"

// The depth test first: the samples an object covers never run this shader.
layout(early_fragment_tests) in;

layout(constant_id = SPEC_DISPLAY_OUTPUT) const uint DISPLAY_OUTPUT = 0;
layout(set = 0, binding = BINDING_ENVIRONMENT) uniform sampler2D environment_map;
layout(location = 0) in vec2 ndc;
layout(location = 0) out vec4 out_color;


void main() {
    vec4 far = background.inverse_view_proj * vec4(ndc, 1.0, 1.0);
    vec3 d = normalize(far.xyz / far.w - background.camera.xyz);
    // The map turned by rotation about +y: the texel at azimuth φ shows at φ + rotation.
    float azimuth = atan(d.x, d.z) - background.view.y;
    float elevation = asin(clamp(d.y, -1.0, 1.0));
    vec2 uv = vec2(azimuth / (2.0 * PI) + 0.5, 0.5 - elevation / PI);
    vec3 rgb = texture(environment_map, uv).rgb * background.view.x;
    out_color = vec4(DISPLAY_OUTPUT == 1u ? display_encode(rgb, background.display.x) : rgb, 1.0);
}
