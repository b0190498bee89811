// Per-frame uniforms of the preview (lit mesh) pass: `frame`, generated from `render::preview::FrameUniforms`
// (the Rust struct is their one source).
#include "preview_uniforms.glsl"
