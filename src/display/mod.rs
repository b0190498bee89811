//! From linear, scene-referred light to what a display shows: the exposure (set, or measured from a frame) and
//! the verdict on a frame that came out almost all black or white.

mod exposure;

pub use exposure::*;
