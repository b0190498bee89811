//! # diffract
//!
//! A Vulkan renderer of the colours that nanostructures make by diffraction, after J. Stam's *Diffraction
//! Shaders* (SIGGRAPH 1999) and M. Single's thesis / Dhillon et al., *Interactive Diffraction from Biological
//! Nanostructures* (CGF 2014). The method, with the errors found in the thesis, is restated in the repository's
//! `docs/model.md`, which comments cite as `model.md §N`.
//!
//! ## Architecture
//! - [`vk`]: the Vulkan backend, and the only module that creates or destroys Vulkan objects: a [`vk::Context`]
//!   (instance, device, allocator, queue) and leaf objects (buffers, images, pipelines, timestamp queries) that
//!   are destroyed explicitly. Validation is on demand and every message is counted.
//! - [`render`]: frames, speaking in the project's terms: offscreen targets, passes, readback.
//! - [`camera`], [`mesh`]: scene geometry on the CPU.
//! - [`shaders`]: the SPIR-V that `build.rs` compiled from `glsl/`.
//! - [`physics`]: height fields, the Taylor-term precomputation and the exact CPU reference of the BRDF (no GPU).
//! - [`brdf`]: the BRDF at chosen directions by any evaluator (exact, Taylor in f64 or f32, the GPU's compute
//!   shader), with the refusals every command shares.
//! - [`output`]: writing frames to image files.
//! - [`cli`]: the `diffract` command line (a thin binary calls [`cli::main`]); `anyhow` lives only there.
//!
//! Errors are [`error::Error`]: each renders as one line a user can act on.

pub mod brdf;
pub mod cache;
pub mod camera;
pub mod cli;
pub mod error;
pub mod fuzz;
pub mod generate;
pub mod input;
pub mod mesh;
pub mod output;
pub mod physics;
pub mod profile;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod shading;
pub mod view;
pub mod vk;

pub use error::{Error, Result};
