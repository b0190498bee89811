//! From linear, scene-referred light to what a display shows: the exposure (set, or measured from a frame), the
//! tone curve, and the verdict on a frame that came out almost all black or white.

mod exposure;
pub mod tone;

pub use exposure::*;
pub use tone::Tone;
