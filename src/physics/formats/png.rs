//! Greyscale PNG height fields (8 or 16 bit; grey stored in RGB/RGBA counts, real colour is refused). A PNG has
//! no units: [`PngScale`] gives them, grey g becoming h = H·g/g_max.

use std::path::Path;

use crate::error::{Error, Result};
use crate::physics::heightfield::HeightField;

/// How a PNG's grey values become heights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PngScale {
    pub pixel_size_um: f64,
    /// The height of the brightest possible grey value (255 or 65535); black is 0.
    pub height_um: f64,
}

/// Reads a greyscale PNG from a file.
pub fn read(path: &Path, scale: PngScale) -> Result<HeightField> {
    crate::io::input::check_file(path)?;
    decode_png(path, scale, || {
        let file = std::fs::File::open(path).map_err(|e| Error::input(path, format!("cannot open: {e}")))?;
        Ok(std::io::BufReader::new(file))
    })
}

/// A greyscale PNG held in memory (`name` appears in messages): the measured scans built into the binary.
pub fn from_bytes(name: &Path, bytes: &[u8], scale: PngScale) -> Result<HeightField> {
    decode_png(name, scale, || Ok(std::io::Cursor::new(bytes)))
}

/// Decodes a greyscale PNG that `open` reads (twice: its size is checked before any pixel is allocated).
fn decode_png<R: std::io::BufRead + std::io::Seek>(
    path: &Path,
    scale: PngScale,
    open: impl Fn() -> Result<R>,
) -> Result<HeightField> {
    for (flag, v) in [("--pixel-size-um", scale.pixel_size_um), ("--height-um", scale.height_um)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::input(path, format!("{flag} must be a positive number of µm, got {v}")));
        }
    }
    let reader = image::ImageReader::new(open()?)
        .with_guessed_format()
        .map_err(|e| Error::input(path, format!("cannot read: {e}")))?;
    let (w, h) = reader.into_dimensions().map_err(|e| Error::input(path, format!("not a readable PNG: {e}")))?;
    crate::physics::heightfield::check_dims(u64::from(w), u64::from(h))
        .map_err(|e| Error::input(path, e.to_string()))?;
    let mut reader = image::ImageReader::new(open()?);
    reader.set_format(image::ImageFormat::Png);
    let img = reader.decode().map_err(|e| Error::input(path, format!("not a readable PNG: {e}")))?;
    let (w, h) = (img.width() as usize, img.height() as usize);
    let wide = matches!(
        img.color(),
        image::ColorType::L16 | image::ColorType::La16 | image::ColorType::Rgb16 | image::ColorType::Rgba16
    );
    let g_max = if wide { 65535.0 } else { 255.0 };
    let rgb: Vec<[u16; 3]> = match &img {
        image::DynamicImage::ImageLuma8(b) => b.pixels().map(|p| [p[0].into(); 3]).collect(),
        image::DynamicImage::ImageLumaA8(b) => b.pixels().map(|p| [p[0].into(); 3]).collect(),
        image::DynamicImage::ImageLuma16(b) => b.pixels().map(|p| [p[0]; 3]).collect(),
        image::DynamicImage::ImageLumaA16(b) => b.pixels().map(|p| [p[0]; 3]).collect(),
        image::DynamicImage::ImageRgb8(b) => b.pixels().map(|p| [p[0].into(), p[1].into(), p[2].into()]).collect(),
        image::DynamicImage::ImageRgba8(b) => b.pixels().map(|p| [p[0].into(), p[1].into(), p[2].into()]).collect(),
        image::DynamicImage::ImageRgb16(b) => b.pixels().map(|p| [p[0], p[1], p[2]]).collect(),
        image::DynamicImage::ImageRgba16(b) => b.pixels().map(|p| [p[0], p[1], p[2]]).collect(),
        other => return Err(Error::input(path, format!("unsupported PNG pixel type {:?}", other.color()))),
    };
    if let Some(i) = rgb.iter().position(|p| p[0] != p[1] || p[1] != p[2]) {
        return Err(Error::input(
            path,
            format!(
                "has real colour (pixel at column {}, row {} is {:?}); a height field must be grey",
                i % w,
                i / w,
                rgb[i]
            ),
        ));
    }
    let heights = rgb.iter().map(|p| scale.height_um * f64::from(p[0]) / g_max).collect();
    HeightField::new(w, h, scale.pixel_size_um, scale.pixel_size_um, heights)
        .map_err(|e| Error::input(path, e.to_string()))
}
