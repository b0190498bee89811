//! A material: the settings that trade speed for accuracy ([`Settings`], declared once in `settings.rs`, with the
//! approaches and where the sky is evaluated), and the patch prepared for the GPU under them ([`Material`]: Taylor
//! terms or the baked table, the coherence window, the wavelengths, the uniform block).

mod prepare;
mod settings;

pub use prepare::*;
pub use settings::*;
