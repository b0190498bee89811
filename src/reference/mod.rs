//! The truth the renderer is measured against, and the measuring: the BRDF at chosen directions by every
//! evaluator ([`brdf`]), the exact reference images of a frame ([`exact_image`]) and of a BRDF map under an
//! environment ([`exact_env`]), the profiler of speed against accuracy ([`profiler`]), and the functions that exist
//! in Rust and in GLSL set against each other ([`twins`]).

pub mod brdf;
pub mod exact_env;
pub mod exact_image;
pub mod profiler;
pub mod twins;
