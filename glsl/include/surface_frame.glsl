// Per-object uniforms of the surface (geometry) pass: `frame`, generated from `gpu::interface::SurfaceUniforms`
// (the Rust struct is their one source).
#include "surface_uniforms.glsl"

// 0 in the pipelines of a view the sun does not light (`render::variants::ViewSpec`; `frame.light_dir.w` says the
// same at run time): the sun's diffraction, its light on the pigment and its shadow compile out.
layout(constant_id = SPEC_SUN) const uint SUN = 1;
