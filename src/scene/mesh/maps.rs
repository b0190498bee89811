//! A surface's maps: a pigment map (an sRGB PNG whose colour multiplies the material's pigment) and a normal map
//! (a linear PNG in tangent space, OpenGL's convention: red along the tangent, green along n × tangent — up the
//! image on a plane — blue along the normal), each with its mip chain built here (the pigment averaged in linear
//! light, the normal as vectors the shader renormalises). `glsl/include/maps.glsl` reads them; `render::maps`
//! uploads them.

use std::path::Path;
use std::sync::Arc;

use crate::error::{Error, Result};

/// The widest edge a map may have, texels (16384 is what most GPUs sample; `render::maps` checks the device's).
pub const MAX_MAP_EDGE: u32 = 16384;
/// The most bytes a map's PNG may take on disk.
pub const MAX_MAP_BYTES: u64 = 256 << 20;

/// What a map's texels mean.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    /// sRGB-encoded colour (sampled through an sRGB format: filtered in linear light).
    Pigment,
    /// A tangent-space normal, each component c stored as (c + 1)/2.
    Normal,
}

/// One map: RGBA8 texels, level 0 first, each level half the one before (at least 1), rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub kind: MapKind,
    pub width: u32,
    pub height: u32,
    pub levels: Vec<Vec<[u8; 4]>>,
    /// Where it was read from (for messages).
    pub name: String,
    /// The file it was read from (None: made in memory).
    pub path: Option<std::path::PathBuf>,
}

/// An object's maps (none by default).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceMaps {
    pub pigment: Option<Arc<Texture>>,
    pub normal: Option<Arc<Texture>>,
}

impl SurfaceMaps {
    /// `SurfaceUniforms::maps`: 1 where each map is present.
    pub fn flags(&self) -> [f32; 4] {
        [f32::from(u8::from(self.pigment.is_some())), f32::from(u8::from(self.normal.is_some())), 0.0, 0.0]
    }

    /// The files the maps were read from.
    pub fn files(&self) -> impl Iterator<Item = &std::path::Path> {
        [&self.pigment, &self.normal].into_iter().flatten().filter_map(|t| t.path.as_deref())
    }

    pub fn is_empty(&self) -> bool {
        self.pigment.is_none() && self.normal.is_none()
    }

    /// The maps with their rows upside down: what an OBJ's UVs (v up, from the image's bottom row) need to read
    /// an image stored top row first.
    pub fn flipped(&self) -> Self {
        let flip = |t: &Option<Arc<Texture>>| t.as_ref().map(|t| Arc::new(t.flipped()));
        Self { pigment: flip(&self.pigment), normal: flip(&self.normal) }
    }
}

impl Texture {
    /// Reads a PNG map (8 or 16 bits, grey or colour, with or without alpha; the alpha is ignored).
    pub fn load(path: &Path, kind: MapKind) -> Result<Self> {
        let what = match kind {
            MapKind::Pigment => "pigment map",
            MapKind::Normal => "normal map",
        };
        let bytes = crate::io::input::read(path, MAX_MAP_BYTES, what)?;
        Ok(Self { path: Some(path.to_path_buf()), ..Self::decode(path, &bytes, kind)? })
    }

    /// Decodes a PNG map's bytes (`path` names it in messages).
    pub fn decode(path: &Path, bytes: &[u8], kind: MapKind) -> Result<Self> {
        let mut reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), image::ImageFormat::Png);
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_MAP_EDGE);
        limits.max_image_height = Some(MAX_MAP_EDGE);
        limits.max_alloc = Some(4 * u64::from(MAX_MAP_EDGE) * u64::from(MAX_MAP_EDGE));
        reader.limits(limits);
        let image = reader.decode().map_err(|e| {
            Error::input(path, format!("not a readable PNG map (at most {MAX_MAP_EDGE} texels a side): {e}"))
        })?;
        let rgba = image.to_rgba8();
        let (width, height) = rgba.dimensions();
        let texels: Vec<[u8; 4]> = rgba.pixels().map(|p| [p[0], p[1], p[2], 255]).collect();
        if kind == MapKind::Normal {
            if let Some(i) = texels.iter().position(|t| t[2] < 128) {
                let (x, y) = (i as u32 % width, i as u32 / width);
                return Err(Error::input(
                    path,
                    format!(
                        "texel ({x}, {y}) of the normal map has blue {} < 128: its normal points into the surface (a \
                         tangent-space normal map's blue is at least 128)",
                        texels[i][2]
                    ),
                ));
            }
        }
        Ok(Self::with_mips(kind, width, height, texels, path.display().to_string()))
    }

    /// A map from its level-0 texels, with its mip chain.
    pub fn with_mips(kind: MapKind, width: u32, height: u32, texels: Vec<[u8; 4]>, name: String) -> Self {
        let mut levels = vec![texels];
        let (mut w, mut h) = (width, height);
        while w > 1 || h > 1 {
            let next = halve(levels.last().expect("level 0"), (w, h), kind);
            levels.push(next);
            (w, h) = ((w / 2).max(1), (h / 2).max(1));
        }
        Self { kind, width, height, levels, name, path: None }
    }

    /// Level `l`'s width and height.
    pub fn level_extent(&self, l: usize) -> (u32, u32) {
        ((self.width >> l).max(1), (self.height >> l).max(1))
    }

    fn flipped(&self) -> Self {
        let levels = (0..self.levels.len())
            .map(|l| {
                let (w, _) = self.level_extent(l);
                self.levels[l].chunks_exact(w as usize).rev().flatten().copied().collect()
            })
            .collect();
        Self { levels, ..self.clone() }
    }
}

/// sRGB 8-bit → linear.
fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let e = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (e * 255.0).round() as u8
}

/// The next mip level of `level` (`w`×`h`): each texel the mean of the 2×2 (or 2×1, 1×2) it covers; a pigment
/// averaged in linear light.
fn halve(level: &[[u8; 4]], (w, h): (u32, u32), kind: MapKind) -> Vec<[u8; 4]> {
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let (sx, sy) = (if w > 1 { 2 } else { 1 }, if h > 1 { 2 } else { 1 });
    let mut out = Vec::with_capacity((nw * nh) as usize);
    for y in 0..nh {
        for x in 0..nw {
            let mut sum = [0f32; 3];
            for dy in 0..sy {
                for dx in 0..sx {
                    let t = level[((y * sy + dy) * w + x * sx + dx) as usize];
                    for c in 0..3 {
                        sum[c] += match kind {
                            MapKind::Pigment => srgb_to_linear(t[c]),
                            MapKind::Normal => f32::from(t[c]),
                        };
                    }
                }
            }
            let n = (sx * sy) as f32;
            let texel = sum.map(|s| match kind {
                MapKind::Pigment => linear_to_srgb(s / n),
                MapKind::Normal => (s / n).round() as u8,
            });
            out.push([texel[0], texel[1], texel[2], 255]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mips_average_pigment_in_linear_light_and_halve_to_one_texel() {
        let t = Texture::with_mips(MapKind::Pigment, 4, 2, [[0, 0, 0, 255], [255; 4]].repeat(4), "t".into());
        assert_eq!(t.levels.len(), 3);
        assert_eq!(t.level_extent(2), (1, 1));
        // Half black, half white: linear 0.5, which sRGB writes as 188.
        assert_eq!(t.levels[1][0][0], 188);
        assert_eq!(t.levels[2][0][0], 188);
    }

    #[test]
    fn flipping_turns_rows_over_at_every_level() {
        let rows = [[[1, 1, 1, 255]; 2], [[2, 2, 2, 255]; 2]].concat();
        let t = Texture::with_mips(MapKind::Normal, 2, 2, rows, "t".into());
        let f = SurfaceMaps { pigment: None, normal: Some(Arc::new(t)) }.flipped();
        assert_eq!(f.normal.unwrap().levels[0][0], [2, 2, 2, 255]);
    }

    #[test]
    fn a_normal_map_pointing_into_the_surface_is_refused() {
        let mut png = Vec::new();
        let img = image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 60]));
        img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
        let e = Texture::decode(Path::new("n.png"), &png, MapKind::Normal).unwrap_err().to_string();
        assert!(e.contains("points into the surface"), "{e}");
        assert!(Texture::decode(Path::new("n.png"), &png, MapKind::Pigment).is_ok());
    }
}
