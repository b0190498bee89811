//! SPIR-V of every `glsl/<name>.<stage>.glsl`, compiled by `build.rs` and embedded at build time.
//! `NAME_STAGE` holds the bytes of `glsl/name.stage.glsl` (dashes and dots become underscores).

// Crate-private: the self-test's shader and constants are read by the backend's tests only.
#![cfg_attr(not(test), allow(dead_code))]

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
