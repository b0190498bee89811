//! Equirectangular environment maps: linear sRGB radiance from every direction, its luminance in cd/m² (the sun and
//! the sky in their true ratio). Layout (+y up, twice as wide as high): column x covers the azimuth from −180° at
//! the left to +180° at the right (0 along +z, +90° along +x: [`crate::physics::sky::direction`]'s), row y the
//! elevation from +90° at the top; a texel holds the mean radiance over its patch of sphere, of solid angle
//! Δφ·(sin e_top − sin e_bottom) ([`panorama_uv`] and `glsl/include/panorama.glsl` read it alike).
//!
//! [`EnvironmentMap::of_sky`] renders the built-in clear sky into one: the sky at each texel's centre, the sun's disc
//! spread over the texels it covers with its energy kept exactly, and below the horizon a uniform Lambertian ground
//! of the given albedo lit by that sun and sky.

use std::path::Path;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::physics::colour::{into_gamut, xyz_to_linear_srgb};
use crate::physics::optics::SUN_SOLID_ANGLE;
use crate::physics::sky::{sun_angular_radius, Sky};

/// The widest map accepted (16384×8192 texels, 1.5 GiB of f32 RGB).
pub const MAX_WIDTH: u32 = 16384;
/// The brightest texel a map may hold, in its units: far beyond any sky (the sun at noon is 1.6·10⁹ cd/m²), and far
/// enough below f32's 3.4·10³⁸ that the sums over a map's texels and their products with the BRDF stay finite.
pub const MAX_RADIANCE: f32 = 1e20;
/// The largest turn a map takes, degrees (either way; any turn is one of ±180°, but f32 trigonometry of larger
/// angles loses the map).
pub const MAX_ROTATION_DEG: f64 = 1e6;
/// The widest map a scene may load from a file (8192×4096 texels: 384 MiB of f32 RGB, 512 MiB as the GPU's
/// RGBA).
pub const MAX_FILE_WIDTH: u32 = 8192;
/// The largest environment file read, bytes (an uncompressed 8192×4096 f32 RGBA EXR with its header).
pub const MAX_FILE_BYTES: u64 = 600 << 20;
/// Sub-samples per axis a texel beside the sun is split into to find how much of the disc it covers.
const SUN_SUBSAMPLES: u32 = 16;
/// Rings of the quadrature that gives the ground its illuminance.
const GROUND_RINGS: usize = 90;
/// Rings of the quadrature that projects the sky on the SH basis: Hosek–Wilkie's bright circumsolar region needs
/// more than the Preetham sky did (measured against 512 rings, sun 37° high: 64 rings 5.7e-4 of the largest
/// coefficient, 192 rings ~8e-5, 6 ms in a release build — a viewer dragging the sun recomputes it every frame).
const SH_RINGS: usize = 192;

/// An equirectangular map of linear sRGB radiance (luminance in cd/m²), rows top (zenith) first.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[f32; 3]>,
}

/// The texture coordinates of the unit direction `d` in an equirectangular map turned by `rotation` radians about
/// +y (the texel at azimuth φ shows at φ + rotation): u from the azimuth, not yet wrapped into [0, 1) (a sampler
/// wraps it), v from the elevation, 0 at the zenith (`panorama_uv` in glsl/include/panorama.glsl, its twin).
pub fn panorama_uv(d: DVec3, rotation: f64) -> [f64; 2] {
    let azimuth = d.x.atan2(d.z) - rotation;
    let elevation = d.y.clamp(-1.0, 1.0).asin();
    [azimuth / std::f64::consts::TAU + 0.5, 0.5 - elevation / std::f64::consts::PI]
}

/// The unit direction through the point (`x`, `y`) of a `width`×`width/2` map, in texels from its top left corner.
pub fn direction_at(x: f64, y: f64, width: u32) -> DVec3 {
    let height = f64::from(width / 2);
    let azimuth = (x / f64::from(width) - 0.5) * 360.0;
    let elevation = 90.0 - y / height * 180.0;
    crate::physics::sky::direction(elevation, azimuth)
}

/// The solid angle of a texel of row `row` of a `width`×`width/2` map, sr.
pub fn texel_solid_angle(row: u32, width: u32) -> f64 {
    let height = f64::from(width / 2);
    let elevation = |y: f64| (90.0 - y / height * 180.0).to_radians();
    let band = elevation(f64::from(row)).sin() - elevation(f64::from(row) + 1.0).sin();
    std::f64::consts::TAU / f64::from(width) * band
}

impl EnvironmentMap {
    /// Loads an equirectangular HDR map from an OpenEXR (`.exr`) or Radiance (`.hdr`) file: linear RGB (alpha
    /// dropped). Refused, in one line: another extension, an unreadable file, a map that is not twice as wide
    /// as high, narrower than 8 or wider than [`MAX_FILE_WIDTH`] texels, or with a texel that is not a finite,
    /// non-negative number (the first one is named).
    pub fn load(path: &Path) -> Result<Self> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let format = match ext.as_deref() {
            Some("exr") => image::ImageFormat::OpenExr,
            Some("hdr") => image::ImageFormat::Hdr,
            _ => return Err(Error::input(path, "is not an environment map: expected a .exr or .hdr file")),
        };
        let bytes = crate::io::input::read(path, MAX_FILE_BYTES, "environment")?;
        let mut reader = image::ImageReader::with_format(std::io::Cursor::new(&bytes), format);
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_FILE_WIDTH);
        limits.max_image_height = Some(MAX_FILE_WIDTH / 2);
        limits.max_alloc = Some(1 << 30);
        reader.limits(limits.clone());
        let (width, height) = reader.into_dimensions().map_err(|e| match e {
            image::ImageError::Limits(_) => Error::input(
                path,
                format!(
                    "is larger than the {MAX_FILE_WIDTH}×{} texels an environment map may have",
                    MAX_FILE_WIDTH / 2
                ),
            ),
            e => Error::input(path, format!("cannot be read as {format:?}: {e}")),
        })?;
        Self::check_shape(width, height).map_err(|e| Error::input(path, e))?;
        let mut reader = image::ImageReader::with_format(std::io::Cursor::new(&bytes), format);
        reader.limits(limits);
        let decoded = reader.decode().map_err(|e| Error::input(path, format!("cannot be decoded: {e}")))?;
        let rgb: Vec<[f32; 3]> = decoded.into_rgb32f().pixels().map(|p| p.0).collect();
        let map = Self { width, height, rgb };
        map.check_texels().map_err(|e| Error::input(path, e))?;
        Ok(map)
    }

    /// Equirectangular: twice as wide as high, 8 to [`MAX_FILE_WIDTH`] texels wide.
    fn check_shape(width: u32, height: u32) -> std::result::Result<(), String> {
        if width != 2 * height {
            return Err(format!(
                "is {width}×{height} texels: an equirectangular (latitude–longitude) map is twice as wide as high"
            ));
        }
        if !(8..=MAX_FILE_WIDTH).contains(&width) {
            return Err(format!("is {width} texels wide: an environment map may be 8 to {MAX_FILE_WIDTH} wide"));
        }
        Ok(())
    }

    /// Refuses an `intensity` and a `rotation_deg` the map cannot take, in the words of `[light]`'s keys (the same
    /// limits for a scene's map and `map --environment`): an intensity that is not positive and finite, or that
    /// would take the brightest texel beyond [`MAX_RADIANCE`]; a rotation beyond ±[`MAX_ROTATION_DEG`].
    pub fn check_scale(&self, intensity: f64, rotation_deg: f64) -> std::result::Result<(), String> {
        let number = crate::error::number;
        if !(intensity.is_finite() && intensity > 0.0) {
            return Err(format!("the environment's intensity {} must be a positive, finite factor", number(intensity)));
        }
        let brightest = self.rgb.iter().flatten().fold(0.0f32, |m, &c| m.max(c));
        if f64::from(brightest) * intensity > f64::from(MAX_RADIANCE) {
            return Err(format!(
                "the environment's intensity {}: the map's brightest texel ({brightest:.3e}) times it is {:.1e}, beyond \
                 {MAX_RADIANCE:.0e}",
                number(intensity),
                f64::from(brightest) * intensity
            ));
        }
        if !(rotation_deg.is_finite() && rotation_deg.abs() <= MAX_ROTATION_DEG) {
            return Err(format!(
                "the environment's rotation {}° must be an angle within ±{MAX_ROTATION_DEG:e}°",
                number(rotation_deg)
            ));
        }
        Ok(())
    }

    /// Every texel a finite, non-negative radiance no brighter than [`MAX_RADIANCE`].
    fn check_texels(&self) -> std::result::Result<(), String> {
        let bad = |c: f32| !(c.is_finite() && c >= 0.0);
        if let Some(t) = self.rgb.iter().find(|t| t.iter().all(|&c| !bad(c)) && t.iter().any(|&c| c > MAX_RADIANCE)) {
            let count = self.rgb.iter().filter(|t| t.iter().any(|&c| c > MAX_RADIANCE)).count();
            return Err(format!(
                "has {count} texel(s) brighter than {MAX_RADIANCE:.0e} (one is {:?}; the sun at noon is 1.6e9 cd/m²): \
                 a damaged file, or units that need scaling down",
                t
            ));
        }
        let count = self.rgb.iter().filter(|t| t.iter().any(|&c| bad(c))).count();
        match self.rgb.iter().position(|t| t.iter().any(|&c| bad(c))) {
            None => Ok(()),
            Some(i) => {
                let (x, y) = (i as u32 % self.width, i as u32 / self.width);
                Err(format!(
                    "has {count} texel(s) that are not finite, non-negative radiances, the first at ({x}, {y}): {:?}",
                    self.rgb[i]
                ))
            }
        }
    }

    /// The largest texel luminance, and the direction of its texel's centre.
    pub fn brightest(&self) -> (f64, DVec3) {
        let (i, y) = self
            .rgb
            .iter()
            .map(|&t| crate::physics::spectrum::luminance(t))
            .enumerate()
            .fold((0, f64::MIN), |best, (i, y)| if y > best.1 { (i, y) } else { best });
        let (x, row) = (i as u32 % self.width, i as u32 / self.width);
        (y, direction_at(f64::from(x) + 0.5, f64::from(row) + 0.5, self.width))
    }

    /// The map's irradiance (E/π, nine SH coefficients, linear RGB) with its radiance times `scale` and turned
    /// by `rotation_deg` about +y (a texel at azimuth φ lights from φ + rotation): every texel counted at its
    /// centre with its solid angle.
    pub fn irradiance(&self, scale: f64, rotation_deg: f64) -> crate::physics::sh::Irradiance {
        let turn = glam::DQuat::from_rotation_y(rotation_deg.to_radians());
        let cells = (0..self.height).flat_map(move |row| {
            let omega = texel_solid_angle(row, self.width);
            (0..self.width).map(move |x| {
                let dir = turn * direction_at(f64::from(x) + 0.5, f64::from(row) + 0.5, self.width);
                let [r, g, b] = self.rgb[(row * self.width + x) as usize].map(f64::from);
                (dir, omega, DVec3::new(r, g, b) * scale)
            })
        });
        crate::physics::sh::Irradiance::of_cells(cells)
    }

    /// The clear sky `sky` without its sun as a `width`×`width/2` map over a ground of `ground_albedo` (0–1).
    pub fn of_sky(sky: &Sky, width: u32, ground_albedo: f64) -> Result<Self> {
        // No wider than a scene loads: a sky made to be loaded again says the same limit `gen sky --width` does.
        if width < 8 || width % 2 != 0 || width > MAX_FILE_WIDTH {
            return Err(Error::setting(
                "width",
                format!(
                    "an environment map's width must be even and between 8 and {MAX_FILE_WIDTH} texels, got {width}"
                ),
            ));
        }
        if !(ground_albedo.is_finite() && (0.0..=1.0).contains(&ground_albedo)) {
            return Err(Error::setting(
                "ground_albedo",
                format!("the ground's albedo must lie between 0 and 1, got {}", crate::error::number(ground_albedo)),
            ));
        }
        let height = width / 2;
        let light = sky_light(sky, ground_albedo);
        let xyz: Vec<DVec3> = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| light(direction_at(f64::from(x) + 0.5, f64::from(y) + 0.5, width)))
            .collect();
        Ok(Self::from_xyz(width, xyz))
    }

    /// [`Self::of_sky`] with the sun's disc added to the texels it covers (its energy kept exactly).
    pub fn of_sky_and_sun(sky: &Sky, width: u32, ground_albedo: f64) -> Result<Self> {
        let mut map = Self::of_sky(sky, width, ground_albedo)?;
        let sun = into_gamut(xyz_to_linear_srgb(sky.sun_xyz())).as_vec3().to_array();
        for (i, weight) in sun_weights(sky.sun, width) {
            for (t, s) in map.rgb[i].iter_mut().zip(sun) {
                *t += s * weight as f32;
            }
        }
        Ok(map)
    }

    fn from_xyz(width: u32, xyz: Vec<DVec3>) -> Self {
        // (Into the gamut: Preetham's sky and the sun's disc within a degree of the horizon are redder than sRGB's
        // primaries, and a negative texel would subtract light.)
        let rgb = xyz.iter().map(|&v| into_gamut(xyz_to_linear_srgb(v)).as_vec3().to_array()).collect();
        Self { width, height: width / 2, rgb }
    }

    /// The illuminance (lux, the luminance-weighted sum) the map's upper half gives a horizontal surface.
    pub fn horizontal_illuminance(&self) -> f64 {
        let mut lux = 0.0;
        for y in 0..self.height {
            for x in 0..self.width {
                let dir = direction_at(f64::from(x) + 0.5, f64::from(y) + 0.5, self.width);
                if dir.y > 0.0 {
                    let [r, g, b] = self.rgb[(y * self.width + x) as usize].map(f64::from);
                    let luminance = 0.2126 * r + 0.7152 * g + 0.0722 * b;
                    lux += luminance * dir.y * texel_solid_angle(y, self.width);
                }
            }
        }
        lux
    }

    /// The radiance towards `d` (unit, world) as a linearly filtered sampler reads the map turned by `rotation`
    /// radians about +y (`create_panorama_sampler`: wrapping in azimuth, clamped at the poles; the shaders' lookup).
    pub fn bilinear(&self, d: DVec3, rotation: f64) -> DVec3 {
        let [u, v] = panorama_uv(d, rotation);
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let fx = u.rem_euclid(1.0) * w - 0.5;
        let fy = v * h - 0.5;
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let at = |x: f64, y: f64| {
            let xi = (x as i64).rem_euclid(i64::from(self.width)) as u32;
            let yi = (y.max(0.0) as u32).min(self.height - 1);
            let [r, g, b] = self.rgb[(yi * self.width + xi) as usize].map(f64::from);
            DVec3::new(r, g, b)
        };
        let top = at(x0, y0) * (1.0 - tx) + at(x0 + 1.0, y0) * tx;
        let bottom = at(x0, y0 + 1.0) * (1.0 - tx) + at(x0 + 1.0, y0 + 1.0) * tx;
        top * (1.0 - ty) + bottom * ty
    }

    /// RGBA f32 (alpha 1), for the image writers.
    pub fn to_rgba(&self) -> Vec<f32> {
        self.rgb.iter().flat_map(|&[r, g, b]| [r, g, b, 1.0]).collect()
    }
}

/// The light of `sky` without its sun, CIE XYZ (Y in cd/m²) towards each unit direction: the sky above the
/// horizon, below it a uniform Lambertian ground of `ground_albedo` lit by the sun and the sky (radiance
/// albedo·illuminance/π).
pub fn sky_light(sky: &Sky, ground_albedo: f64) -> impl Fn(DVec3) -> DVec3 + '_ {
    let (sun_light, sky_light) = sky.horizontal_illuminance_xyz(GROUND_RINGS);
    let ground = (sun_light + sky_light) * (ground_albedo / std::f64::consts::PI);
    move |dir: DVec3| if dir.y > 0.0 { sky.xyz(dir) } else { ground }
}

/// The irradiance (E/π as nine SH coefficients, linear sRGB) of `sky` and its ground, without the sun, in units
/// of the sun's luminance: what the pigment of a scene whose sun has radiance 1 gets from the sky.
pub fn sky_irradiance(sky: &Sky, ground_albedo: f64) -> crate::physics::sh::Irradiance {
    let light = sky_light(sky, ground_albedo);
    let sun = sky.sun_xyz().y;
    crate::physics::sh::Irradiance::of(|dir| into_gamut(xyz_to_linear_srgb(light(dir))) / sun, SH_RINGS)
}

/// The sun's disc over the texels of a `width`-wide map: (texel index, the share of the sun's radiance it
/// holds), so that Σ share·Ω_texel = Ω_sun exactly. Texels near the sun are split into sub-samples and each
/// gets the fraction inside the disc; where the disc is narrower than the sub-samples and none falls inside,
/// the texel that holds its centre takes it all.
fn sun_weights(sun: DVec3, width: u32) -> Vec<(usize, f64)> {
    let height = width / 2;
    let radius = sun_angular_radius();
    let cos_radius = radius.cos();
    let texel = std::f64::consts::TAU / f64::from(width);
    let elevation = sun.y.clamp(-1.0, 1.0).asin().to_degrees();
    let azimuth = sun.x.atan2(sun.z).to_degrees();
    let centre = (
        ((azimuth / 360.0 + 0.5) * f64::from(width)).floor().clamp(0.0, f64::from(width - 1)) as i64,
        ((90.0 - elevation) / 180.0 * f64::from(height)).floor().clamp(0.0, f64::from(height - 1)) as i64,
    );
    // Texels within the disc's radius (plus one) of the centre texel, wider near the poles.
    let reach_y = (radius / texel).ceil() as i64 + 1;
    let cos_elevation = (1.0 - sun.y * sun.y).max(0.0).sqrt().max(1e-3);
    let reach_x = (radius / texel / cos_elevation).ceil().min(f64::from(width)) as i64 + 1;
    let mut weights = Vec::new();
    for dy in -reach_y..=reach_y {
        let y = centre.1 + dy;
        if !(0..i64::from(height)).contains(&y) {
            continue;
        }
        for dx in -reach_x..=reach_x {
            let x = (centre.0 + dx).rem_euclid(i64::from(width));
            let inside = (0..SUN_SUBSAMPLES * SUN_SUBSAMPLES)
                .filter(|k| {
                    let (sx, sy) = (f64::from(k % SUN_SUBSAMPLES) + 0.5, f64::from(k / SUN_SUBSAMPLES) + 0.5);
                    let n = f64::from(SUN_SUBSAMPLES);
                    direction_at(x as f64 + sx / n, y as f64 + sy / n, width).dot(sun) >= cos_radius
                })
                .count();
            if inside > 0 {
                let index = (y as u32 * width + x as u32) as usize;
                weights.push((index, inside as f64 / f64::from(SUN_SUBSAMPLES * SUN_SUBSAMPLES), y as u32));
            }
        }
    }
    if weights.is_empty() {
        weights.push(((centre.1 as u32 * width + centre.0 as u32) as usize, 1.0, centre.1 as u32));
    }
    let covered: f64 = weights.iter().map(|&(_, w, row)| w * texel_solid_angle(row, width)).sum();
    weights.into_iter().map(|(i, w, _)| (i, w * SUN_SOLID_ANGLE / covered)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No texel of a sky map is negative or non-finite, for either model, at any elevation the models accept —
    /// the horizon included, where both skies and the sun's reddened disc leave sRGB's gamut (before: Preetham's sky
    /// at turbidity 2 with the sun 0.5° high held 34 negative texels down to −2290 cd/m², its sun −34 834).
    #[test]
    fn sky_maps_hold_no_negative_light_at_any_elevation() {
        use crate::physics::sky::{SkyModel, GROUND_ALBEDO};
        for model in [SkyModel::HosekWilkie, SkyModel::Preetham] {
            for t in [model.turbidity_range().0, 3.0, 10.0] {
                for elevation in [0.0, 0.1, 0.5, 1.0, 2.0, 5.0, 30.0, 90.0] {
                    let sky = Sky::at_of_model(model, t, elevation, 40.0, GROUND_ALBEDO).unwrap();
                    let map = EnvironmentMap::of_sky_and_sun(&sky, 256, GROUND_ALBEDO).unwrap();
                    let bad = map.rgb.iter().flatten().filter(|v| !(v.is_finite() && **v >= 0.0)).count();
                    assert_eq!(bad, 0, "{model:?}, turbidity {t}, sun {elevation}°");
                    let sh = sky_irradiance(&sky, GROUND_ALBEDO);
                    assert!(sh.coefficients.iter().all(|c| c.is_finite()));
                }
            }
        }
    }

    #[test]
    fn texels_cover_the_sphere_and_directions_follow_the_layout() {
        let width = 64;
        let total: f64 = (0..width / 2).map(|row| texel_solid_angle(row, width) * f64::from(width)).sum();
        assert!((total - 4.0 * std::f64::consts::PI).abs() < 1e-12, "{total}");
        assert!((direction_at(32.0, 0.0, width) - DVec3::Y).length() < 1e-12, "top: the zenith");
        assert!((direction_at(32.0, 16.0, width) - DVec3::Z).length() < 1e-12, "centre: +z on the horizon");
        assert!((direction_at(48.0, 16.0, width) - DVec3::X).length() < 1e-12, "three quarters: +x");
    }

    /// The map keeps the sky's light: the sun's disc exactly (Σ share·Ω = Ω_sun, wherever the disc falls and
    /// however it compares with a texel), and the illuminance of a horizontal surface within 1 % of the sky's
    /// own quadrature; the ground is the Lambertian albedo·E/π.
    #[test]
    fn a_sky_map_keeps_the_sun_and_the_sky_light() {
        for (width, elevation, azimuth) in
            [(64, 35.0, 10.0), (512, 60.0, -120.0), (2048, 20.0, 179.9), (512, 89.5, 0.0)]
        {
            let sky = Sky::at(3.0, elevation, azimuth).unwrap();
            let weights = sun_weights(sky.sun, width);
            let omega: f64 = weights.iter().map(|&(i, w)| w * texel_solid_angle(i as u32 / width, width)).sum();
            assert!((omega / SUN_SOLID_ANGLE - 1.0).abs() < 1e-12, "{width}: {omega}");
            let map = EnvironmentMap::of_sky_and_sun(&sky, width, 0.0).unwrap();
            let (sun, sky_lux) = sky.horizontal_illuminance(GROUND_RINGS);
            let lux = map.horizontal_illuminance();
            let tolerance = if width >= 512 { 0.01 } else { 0.05 };
            assert!(
                (lux / (sun + sky_lux) - 1.0).abs() < tolerance,
                "{width}, {elevation}°: {lux} vs {}",
                sun + sky_lux
            );
        }
        let sky = Sky::at(2.0, 45.0, 0.0).unwrap();
        let map = EnvironmentMap::of_sky_and_sun(&sky, 64, 0.2).unwrap();
        let (sun, sky_lux) = sky.horizontal_illuminance(GROUND_RINGS);
        let [r, g, b] = map.rgb[map.rgb.len() - 1].map(f64::from);
        let ground = crate::physics::colour::linear_srgb_to_xyz(DVec3::new(r, g, b)).y;
        assert!((ground / (0.2 * (sun + sky_lux) / std::f64::consts::PI) - 1.0).abs() < 1e-5, "{ground}");
    }

    /// The sky's nine SH coefficients against the irradiance summed over the sphere, at normals up, down, towards
    /// the sun, away from it and sideways: Hosek–Wilkie's sky measured within 2.7 % facing up or sideways, 5.1 %
    /// facing down under a sun 20° high (the horizon's edge is detail beyond l = 2), 2.6 % under a sun 50° or 80°
    /// high (its circumsolar brightness is sharper than Preetham's, which was within 1.2 %).
    #[test]
    fn the_sky_irradiance_in_nine_numbers_is_close_to_the_sum() {
        for (t, elevation) in [(2.0, 20.0), (3.0, 50.0), (6.0, 80.0)] {
            let sky = Sky::at(t, elevation, 30.0).unwrap();
            let sh = sky_irradiance(&sky, 0.2);
            let light = sky_light(&sky, 0.2);
            let sun = sky.sun_xyz().y;
            let normals = [DVec3::Y, -DVec3::Y, sky.sun, -sky.sun, crate::physics::sky::direction(0.0, 120.0)];
            for n in normals {
                let exact = crate::physics::sh::sphere_cells(360)
                    .map(|(w, omega)| xyz_to_linear_srgb(light(w)) / sun * (n.dot(w).max(0.0) * omega))
                    .sum::<DVec3>()
                    / std::f64::consts::PI;
                let rel = (sh.over_pi(n) - exact).length() / exact.length();
                let tolerance = if elevation < 45.0 { 0.07 } else { 0.03 };
                assert!(rel < tolerance, "T {t}, sun {elevation}°, normal {n:.2}: {rel:.3e}");
            }
        }
    }

    /// A scratch folder for this test process.
    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("diffract-env-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn write(path: &Path, width: u32, height: u32, rgb: &[[f32; 3]]) {
        let rgba: Vec<f32> = rgb.iter().flat_map(|&[r, g, b]| [r, g, b, 1.0]).collect();
        crate::io::output::write_exr_rgb(path, width, height, &rgba).unwrap();
    }

    /// A map read back is the map written; its irradiance is that of a uniform map (E/π = L·scale at every
    /// normal, to the quadrature's 1e-3) and turns with it (light from the +z half lights +x after a 90° turn).
    #[test]
    fn maps_load_and_light_by_their_texels() {
        let dir = scratch("load");
        let path = dir.join("map.exr");
        let rgb: Vec<[f32; 3]> = (0..32 * 16).map(|i| [i as f32, 0.5, 2.0]).collect();
        write(&path, 32, 16, &rgb);
        let map = EnvironmentMap::load(&path).unwrap();
        assert_eq!((map.width, map.height, &map.rgb), (32, 16, &rgb));
        let uniform = EnvironmentMap { width: 64, height: 32, rgb: vec![[1.0, 0.5, 0.25]; 64 * 32] };
        let e = uniform.irradiance(2.0, 37.0);
        for n in [DVec3::Y, -DVec3::Y, DVec3::X, DVec3::new(0.3, -0.5, 0.81).normalize()] {
            // Texel centres stand for their rows: the quadratic harmonics sum to zero within 5e-4 at 32 rows.
            assert!((e.over_pi(n) - DVec3::new(2.0, 1.0, 0.5)).length() < 2e-3, "{n}: {}", e.over_pi(n));
        }
        // Bright where the azimuth is within 90° of +z (columns 16–47 of 64).
        let front = EnvironmentMap {
            width: 64,
            height: 32,
            rgb: (0..64 * 32).map(|i| if (16..48).contains(&(i % 64)) { [1.0; 3] } else { [0.0; 3] }).collect(),
        };
        let (still, turned) = (front.irradiance(1.0, 0.0), front.irradiance(1.0, 90.0));
        assert!(still.over_pi(DVec3::Z).x > 0.8 && still.over_pi(-DVec3::Z).x < 0.2);
        assert!((turned.over_pi(DVec3::X).x - still.over_pi(DVec3::Z).x).abs() < 1e-9);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A Radiance file written and read back keeps every texel within RGBE's resolution (8-bit mantissas: 1 %).
    #[test]
    fn hdr_files_round_trip_within_rgbe() {
        let dir = scratch("hdr");
        let path = dir.join("map.hdr");
        let rgb: Vec<[f32; 3]> = (0..32 * 16).map(|i| [1e-3 * (i + 1) as f32, 7.5, 2e4 + i as f32]).collect();
        let rgba: Vec<f32> = rgb.iter().flat_map(|&[r, g, b]| [r, g, b, 1.0]).collect();
        crate::io::output::write_hdr_rgb(&path, 32, 16, &rgba).unwrap();
        let map = EnvironmentMap::load(&path).unwrap();
        assert_eq!((map.width, map.height), (32, 16));
        for (got, want) in map.rgb.iter().zip(&rgb) {
            // RGBE shares one exponent: each channel within 1 % of the texel's largest.
            let largest = want.iter().fold(0.0f32, |m, &c| m.max(c));
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() <= 0.01 * largest, "{got:?} vs {want:?}");
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// One line for each way a map can be wrong: its extension, its shape, its size, its texels.
    #[test]
    fn bad_maps_are_refused_in_one_line() {
        let dir = scratch("bad");
        let refused = |name: &str, needle: &str| {
            let e = EnvironmentMap::load(&dir.join(name)).unwrap_err().to_string();
            assert!(e.contains(needle) && !e.contains('\n'), "{name}: {e}");
        };
        std::fs::write(dir.join("map.png"), b"not a map").unwrap();
        refused("map.png", ".exr or .hdr");
        refused("missing.exr", "missing.exr");
        write(&dir.join("wide.exr"), 24, 8, &[[1.0; 3]; 24 * 8]);
        refused("wide.exr", "twice as wide as high");
        write(&dir.join("tiny.exr"), 4, 2, &[[1.0; 3]; 8]);
        refused("tiny.exr", "8 to 8192");
        for (name, bad) in [("nan.exr", f32::NAN), ("negative.exr", -1.0), ("inf.exr", f32::INFINITY)] {
            let mut rgb = vec![[1.0; 3]; 16 * 8];
            rgb[3 * 16 + 5][1] = bad;
            write(&dir.join(name), 16, 8, &rgb);
            refused(name, "the first at (5, 3)");
        }
        // A Radiance header that claims 16384×8192 texels: refused from the header, before any decoding.
        std::fs::write(dir.join("huge.hdr"), b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n").unwrap();
        refused("huge.hdr", "larger than the 8192×4096 texels");
        std::fs::write(dir.join("garbage.hdr"), b"#?RADIANCE\nnonsense").unwrap();
        refused("garbage.hdr", "cannot be read");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_sizes_and_albedos_are_refused() {
        let sky = Sky::at(3.0, 30.0, 0.0).unwrap();
        for width in [0, 6, 65, MAX_WIDTH + 2] {
            assert!(EnvironmentMap::of_sky(&sky, width, 0.2).unwrap_err().to_string().contains("width"));
        }
        for albedo in [-0.1, 1.5, f64::NAN] {
            assert!(EnvironmentMap::of_sky(&sky, 64, albedo).unwrap_err().to_string().contains("albedo"));
        }
    }
}
