//! # diffract
//!
//! A Vulkan renderer of the colours that nanostructures make by diffraction, after J. Stam's *Diffraction
//! Shaders* (SIGGRAPH 1999) and M. Single's thesis / Dhillon et al., *Interactive Diffraction from Biological
//! Nanostructures* (CGF 2014), in physical units, with an exact CPU reference of the BRDF to check every shader
//! against. The method is restated in the repository's `docs/model.md`, which comments cite as `model.md §N`.
//!
//! ## Where to start
//! - **Load a scan**: [`physics::formats::load`] (a PNG of heights with its scale, or a Gwyddion `.gsf`), or build
//!   a [`physics::heightfield::HeightField`] from heights in µm; [`physics::generate`] makes gratings and patches.
//! - **Evaluate the BRDF** at chosen directions: [`reference::brdf::evaluate`] (exact, Taylor in f64 or f32, or
//!   the GPU's compute shader), or [`physics::exact::Reference`] directly. No GPU is needed for the CPU's.
//! - **Render a scene offscreen**: [`scene::Scene::load`], [`render::capture::prepare_materials`],
//!   [`render::capture::SceneCapture`] on a [`gpu::vk::Context`] (the repository's `examples/render_frame.rs`).
//! - **Measure speed against accuracy**: [`reference::profiler`].
//!
//! ## Where the library's defaults are not the command line's
//! - **Tone**: [`display::Tone`]'s default is `Clip` (values proportional to the light: what `diffract map` shows);
//!   `render` and `view` show `Filmic`. Pass the one you want to [`display::tone::to_rgba8`].
//! - **Exposure**: nothing is metered unless asked: [`render::capture::SceneCapture::meter`] meters a frame as
//!   `render` does for a tone (a scene's `exposure_ev` first).
//! - **Shading path**: [`render::capture::SceneCapture::new`] draws forward; `render` takes
//!   [`render::visibility::ShadingPath::for_scene`] (the visibility buffer on a CPU device with several samples per pixel), which
//!   [`render::capture::SceneCapture::with_path`] takes too.
//! - **Clean-up**: hold GPU objects in a [`gpu::vk::Owned`], which waits for the device and frees them when it is
//!   dropped; `unsafe fn destroy` is for the crate's own frame loops.
//! - **Messages**: the library prints nothing but progress bars on a terminal's stderr. Its warnings and notes (a
//!   table it could not cache, a long build's plan, validation messages) go to the `log` crate: install a logger
//!   (`log::set_logger`, or a crate such as `env_logger`) to see them, as the command line does.
//!
//! ```
//! use diffract::material::Settings;
//! use diffract::physics::exact::{Method, Query};
//! use diffract::physics::heightfield::HeightField;
//! use diffract::reference::brdf::{evaluate, Evaluator};
//!
//! // A flat mirror sends all of the light into the mirror direction, where |P|² is 1.
//! let mirror = HeightField::new(64, 64, 0.1, 0.1, vec![0.0; 64 * 64])?; // 6.4 µm square, 0.1 µm pixels
//! let mirror_view = Query { lambda_nm: 550.0, theta_i: 30.0, phi_i: 0.0, theta_r: 30.0, phi_r: 180.0 };
//! let accuracy = Settings { tolerance: 1e-4, coherence_um: 6.4, ..Settings::default() };
//! let p = evaluate(&mirror, &[mirror_view], Evaluator::Cpu(Method::Exact), &accuracy, None)?;
//! assert!((p.samples[0].power - 1.0).abs() < 1e-9);
//! # Ok::<(), diffract::Error>(())
//! ```
//!
//! ## Layers
//! Each folder of `src/` is a layer that uses only the layers listed before it (ARCHITECTURE.md draws them; a
//! reading of every `use` line finds no import circle between files or folders):
//! 1. [`error`]: one error type; every variant renders as one line a user can act on.
//! 2. [`io`]: bounded reads of user files, atomic writes, the verified on-disk cache, progress, statistics.
//! 3. [`gpu`]: the Vulkan backend ([`gpu::vk`], the only code that creates or destroys Vulkan objects), the
//!    shaders' SPIR-V and [`gpu::interface`], the numbers and layouts the shaders and the Rust side share.
//! 4. [`physics`]: the CPU truth: height fields, the coherence window, Taylor terms, the exact BRDF, spectra,
//!    colour, illuminants, the sky and the baked table (no Vulkan).
//! 5. [`display`]: exposure, the tone curve and the verdict on a frame (CPU twins of `glsl/include/display.glsl`).
//! 6. [`light`]: environment maps, their sampling against the BRDF, the prefiltered moments, a map's sun.
//! 7. [`material`]: the settings that trade speed for accuracy and a patch prepared under them.
//! 8. [`scene`]: scene files, the camera, meshes (shapes, the procedural snake, OBJ).
//! 9. [`render`]: frames: targets, the frame renderer's state and passes, scene capture, readback.
//! 10. [`reference`](mod@reference): the BRDF by every evaluator, exact reference images, the profiler.
//! 11. `view` and `cli` (feature `cli`): the viewer's window and the `diffract` command line.

/// `println!` that cannot panic: a line on stdout through [`io::stream::out`].
#[allow(unused_macros)]
macro_rules! outln {
    () => { $crate::io::stream::out(format_args!("")) };
    ($($arg:tt)*) => { $crate::io::stream::out(format_args!($($arg)*)) };
}

/// `eprintln!` that cannot panic: a line on stderr through [`io::stream::err`].
#[allow(unused_macros)]
macro_rules! errln {
    ($($arg:tt)*) => { $crate::io::stream::err(format_args!($($arg)*)) };
}

#[cfg(feature = "cli")]
pub mod cli;
pub mod display;
pub mod error;
#[doc(hidden)] // the fuzz targets' entry points (fuzz/), not an API
pub mod fuzz;
pub mod gpu;
pub mod io;
pub mod light;
pub mod material;
pub mod physics;
pub mod reference;
pub mod render;
pub mod scene;
#[cfg(feature = "cli")]
pub(crate) mod view;

pub use error::{Error, Result};
