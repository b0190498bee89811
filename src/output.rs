//! Writing frames to files: 8-bit sRGB PNG (display-referred) and 32-bit float OpenEXR (linear, scene-referred).

use std::path::Path;

use crate::error::{Error, Result};

/// Linear scene-referred RGBA floats → display-referred 8-bit sRGB RGBA after `exposure_ev` stops.
pub fn linear_to_rgba8(rgba: &[f32], exposure_ev: f64) -> Vec<u8> {
    rgba.chunks(4)
        .flat_map(|p| {
            let linear = glam::DVec3::new(p[0].into(), p[1].into(), p[2].into());
            let [r, g, b] = crate::physics::spectrum::display_encode(linear, exposure_ev);
            [r, g, b, 255]
        })
        .collect()
}

/// Checks, before any expensive work, that `path` names a PNG in a folder that exists.
pub fn check_png_path(path: &Path) -> Result<()> {
    check_path(path, "png")
}

/// Checks, before any expensive work, that `path` names an OpenEXR file in a folder that exists.
pub fn check_exr_path(path: &Path) -> Result<()> {
    check_path(path, "exr")
}

fn check_path(path: &Path, extension: &str) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref() != Some(extension) {
        return Err(Error::output(path, format!("the output must be a .{extension} file")));
    }
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::output(path, format!("the folder {} does not exist", parent.display())));
    }
    Ok(())
}

/// Writes tightly packed RGBA8 (sRGB-encoded, top row first) as a PNG.
pub fn write_png_rgba8(path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    check_png_path(path)?;
    let img = image::RgbaImage::from_raw(width, height, rgba8.to_vec())
        .ok_or_else(|| Error::output(path, "image data does not match its size"))?;
    img.save_with_format(path, image::ImageFormat::Png).map_err(|e| Error::output(path, e))
}

/// Writes linear RGB (from RGBA float pixels, top row first) as an OpenEXR file with 32-bit float R, G, B.
pub fn write_exr_rgb(path: &Path, width: u32, height: u32, rgba: &[f32]) -> Result<()> {
    check_exr_path(path)?;
    let rgb: Vec<f32> = rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let img = image::Rgb32FImage::from_raw(width, height, rgb)
        .ok_or_else(|| Error::output(path, "image data does not match its size"))?;
    img.save_with_format(path, image::ImageFormat::OpenExr).map_err(|e| Error::output(path, e))
}
