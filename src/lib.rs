//! # diffract
//!
//! A Vulkan renderer of the colours that nanostructures make by diffraction, after J. Stam's *Diffraction
//! Shaders* (SIGGRAPH 1999) and M. Single's thesis / Dhillon et al., *Interactive Diffraction from Biological
//! Nanostructures* (CGF 2014). The method, with the errors found in the thesis, is restated in the repository's
//! `docs/model.md`, which comments cite as `model.md §N`.
//!
//! ## Architecture
//! From the top down (each layer uses only those below it):
//! - `cli`: the `diffract` command line (a thin binary calls `cli::main`), behind the default feature `cli`:
//!   `clap` and `anyhow` live only there, and a library user can leave both out (`default-features = false`).
//! - `view`: the interactive viewer (winit window, input, live settings); it draws through
//!   `render::window::WindowTarget`.
//! - [`profile`]: the profiler's configurations, sweeps, exact reference images, tables and plots;
//!   [`brdf`]: the BRDF at chosen directions by any evaluator (exact, Taylor in f64 or f32, or the GPU's compute
//!   shader through [`render`]), with the refusals every command shares.
//! - [`render`]: frames, speaking in the project's terms: offscreen and window targets, passes (map, G-buffer, surface,
//!   preview), scene capture, readback.
//! - [`scene`]: scene files (camera, light, objects, materials); [`camera`], [`mesh`]: geometry on the CPU
//!   (built-in shapes, the procedural snake, OBJ meshes).
//! - [`shading`]: approaches, the settings that trade speed for accuracy and the prepared material a pass
//!   uploads.
//! - [`physics`]: height fields and their file formats, the Taylor-term precomputation, the baked table and the
//!   exact CPU reference of the BRDF (no GPU); [`generate`]: nanostructure generators in µm.
//! - [`vk`]: the Vulkan backend, and the only module that creates or destroys Vulkan objects: a [`vk::Context`]
//!   (instance, device, allocator, queue) and leaf objects (buffers, images, pipelines, timestamp queries) that
//!   are destroyed explicitly. Validation is on demand and every message is counted. `shaders`: the SPIR-V
//!   that `build.rs` compiled from `glsl/`.
//! - Shared services: `input` (bounded reading of user files), [`output`] (PNG and EXR; every write through
//!   a recognisable temporary file and a rename), `cache` (the on-disk cache of tables and references, each
//!   entry verified before use), [`stats`] (quantiles, the finite-pixel check), `progress`
//!   (progress bars on stderr), [`error`], and [`fuzz`] (the fuzz targets' entry points).
//!
//! Errors are [`error::Error`]: each renders as one line a user can act on.
//!
//! ## Example
//! The exact BRDF of a height field at chosen directions, on the CPU (no GPU needed): a flat mirror sends all of
//! the light into the mirror direction, where |P|² is 1 (the reflectance adds Stam's geometric factor, which is
//! 1 at normal incidence).
//! ```
//! use diffract::brdf::{evaluate, Evaluator};
//! use diffract::settings::Settings;
//! use diffract::physics::{HeightField, Method, Query};
//!
//! let mirror = HeightField::new(64, 64, 0.1, 0.1, vec![0.0; 64 * 64])?; // 6.4 µm square, 0.1 µm pixels
//! let mirror_view = Query { lambda_nm: 550.0, theta_i: 30.0, phi_i: 0.0, theta_r: 30.0, phi_r: 180.0 };
//! let accuracy = Settings { tolerance: 1e-4, coherence_um: 6.4, ..Settings::default() };
//! let p = evaluate(&mirror, &[mirror_view], Evaluator::Cpu(Method::Exact), &accuracy, None)?;
//! assert!((p.samples[0].power - 1.0).abs() < 1e-9);
//! # Ok::<(), diffract::Error>(())
//! ```
//! The repository's `examples/` go further: `exact_brdf` (a grating's first order where the grating equation
//! puts it), `render_frame` (bake the tables a frame needs and render it offscreen to PNG) and
//! `profile_approaches` (two approaches timed pass by pass and measured against the exact reference).

pub mod brdf;
pub(crate) mod cache;
pub mod camera;
#[cfg(feature = "cli")]
pub mod cli;
pub mod env_light;
pub mod env_prefilter;
pub mod environment;
pub mod error;
pub mod exposure;
#[doc(hidden)] // the fuzz targets' entry points (fuzz/), not an API
pub mod fuzz;
pub mod generate;
pub(crate) mod input;
pub mod mesh;
pub mod output;
pub mod physics;
pub mod profile;
pub(crate) mod progress;
pub mod render;
pub mod scene;
pub mod settings;
pub(crate) mod shaders;
pub mod shading;
pub mod stats;
#[cfg(feature = "cli")]
pub(crate) mod view;
pub mod vk;

pub use error::{Error, Result};
