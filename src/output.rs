//! Writing frames to files: 8-bit sRGB PNG (display-referred) and 32-bit float OpenEXR (linear, scene-referred).

use std::path::Path;

use crate::error::{Error, Result};

/// Checks, before any expensive work, that `path` names a PNG in a folder that exists.
pub fn check_png_path(path: &Path) -> Result<()> {
    check_path(path, "png")
}

/// Checks, before any expensive work, that `path` names an OpenEXR file in a folder that exists.
pub fn check_exr_path(path: &Path) -> Result<()> {
    check_path(path, "exr")
}

/// Checks an output path before any work: the extension, not a folder, not an existing special file (a
/// device, a pipe), in a folder that exists. The write itself is atomic ([`write_file`]).
pub fn check_path(path: &Path, extension: &str) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref() != Some(extension) {
        return Err(Error::output(path, format!("the output must be a .{extension} file")));
    }
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(Error::output(path, "it is a folder"));
        }
        if !meta.is_file() {
            return Err(Error::output(path, "it exists and is not a regular file"));
        }
    }
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::output(path, format!("the folder {} does not exist", parent.display())));
    }
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file in the same folder, flushed to disk, then renamed over
/// it: a full disk or a failed write reports the error and leaves an existing file as it was.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    crate::cache::write_atomic(path, bytes).map_err(|e| Error::output(path, e))
}

/// Encodes an image in memory in `format`.
fn encode(path: &Path, img: image::DynamicImage, format: image::ImageFormat) -> Result<Vec<u8>> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, format).map_err(|e| Error::output(path, e))?;
    Ok(bytes.into_inner())
}

/// Writes tightly packed RGBA8 (sRGB-encoded, top row first) as a PNG.
pub fn write_png_rgba8(path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    check_png_path(path)?;
    let img = image::RgbaImage::from_raw(width, height, rgba8.to_vec())
        .ok_or_else(|| Error::output(path, "image data does not match its size"))?;
    write_file(path, &encode(path, img.into(), image::ImageFormat::Png)?)
}

/// Writes 16-bit grey (top row first) as a PNG.
pub fn write_png_gray16(path: &Path, width: u32, height: u32, grey: Vec<u16>) -> Result<()> {
    check_png_path(path)?;
    let img = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(width, height, grey)
        .ok_or_else(|| Error::output(path, "image data does not match its size"))?;
    write_file(path, &encode(path, img.into(), image::ImageFormat::Png)?)
}

/// Writes linear RGB (from RGBA float pixels, top row first) as an OpenEXR file with 32-bit float R, G, B.
pub fn write_exr_rgb(path: &Path, width: u32, height: u32, rgba: &[f32]) -> Result<()> {
    check_exr_path(path)?;
    let rgb: Vec<f32> = rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let img = image::Rgb32FImage::from_raw(width, height, rgb)
        .ok_or_else(|| Error::output(path, "image data does not match its size"))?;
    write_file(path, &encode(path, img.into(), image::ImageFormat::OpenExr)?)
}
