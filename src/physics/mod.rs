//! The physics, apart from the GPU: height fields in physical units, the Taylor-term precomputation, and an
//! exact CPU reference of Stam's diffraction BRDF. Pure Rust, testable without Vulkan.
//!
//! Conventions (every check relies on them; model.md §1 has the derivations):
//! - Patch frame: x along image columns (left to right), y along image rows (top to bottom), z the surface
//!   normal. Lengths in µm, wavelengths in nm at the interfaces and µm inside formulas.
//! - ω_i, ω_r: unit vectors from the surface towards the light and the viewer,
//!   (sin θ cos φ, sin θ sin φ, cos θ), angles in degrees. (u, v, w) = −ω_i − ω_r; k = 2π/λ.
//! - `power` = |P(u/λ, v/λ)|², the coherence-windowed DTFT of exp(i·k·w·h), 1 for a flat mirror at specular.
//! - `reflectance` = C(ω_i, ω_r)·power, the thesis's relative reflectance ρ_λ (model.md §1.5).

pub mod baked;
pub mod chebyshev;
pub mod cie_tables;
pub mod coherence;
pub mod colour;
pub mod exact;
pub mod extend;
pub mod formats;
pub mod generate;
pub mod heightfield;
pub mod illuminant;
pub mod optics;
pub mod sh;
pub mod sincos;
pub mod sky;
pub mod spectrum;
pub mod taylor;
