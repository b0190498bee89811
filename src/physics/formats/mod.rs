//! Height-field files: Gwyddion Simple Field (`gsf`, units from the file) and greyscale PNG (`png`, units from
//! the caller). Imports run one way: these readers build a [`HeightField`]; the height field knows no file format.

use std::path::Path;

use crate::error::{Error, Result};
use crate::physics::heightfield::HeightField;

pub mod gsf;
pub mod png;

use png::PngScale;

/// Loads a `.gsf` (units from the file) or a greyscale `.png` (units from `scale`).
pub fn load(path: &Path, scale: Option<PngScale>) -> Result<HeightField> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("gsf") => gsf::read(path),
        Some("png") => {
            let scale = scale.ok_or_else(|| {
                Error::input(path, "a PNG height field needs --pixel-size-um P and --height-um H (physical units)")
            })?;
            png::read(path, scale)
        }
        _ => Err(Error::input(path, "unknown height-field format (expected .gsf or .png)")),
    }
}
