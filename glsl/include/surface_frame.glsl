// Per-object uniforms of the surface (geometry) pass: `frame`, generated from `gpu::interface::SurfaceUniforms`
// (the Rust struct is their one source).
#include "surface_uniforms.glsl"
