//! Equirectangular environment maps: light from every direction, as linear sRGB radiance whose luminance Y is
//! in cd/m² (physical units: the sun and the sky in their true ratio).
//!
//! Layout (the usual latitude–longitude map, +y up): a map is twice as wide as it is high; column x covers the
//! azimuth φ from −180° at the left edge to +180° at the right (φ = 0 along +z, +90° along +x, the azimuth of
//! [`crate::physics::sky::direction`]); row y covers the elevation from +90° (the zenith) at the top to −90° at
//! the bottom. A texel holds the mean radiance over its patch of sphere, whose solid angle is
//! Δφ·(sin e_top − sin e_bottom).
//!
//! [`EnvironmentMap::of_sky`] renders the built-in clear sky ([`crate::physics::sky`]) into one: the sky at each
//! texel's centre, the sun's disc spread over the texels it covers with its energy kept exactly (a disc narrower
//! than a texel lands in the texel that holds its centre), and below the horizon a uniform Lambertian ground of
//! the given albedo lit by that sun and sky.

use glam::DVec3;

use crate::error::{Error, Result};
use crate::physics::optics::SUN_SOLID_ANGLE;
use crate::physics::sky::{sun_angular_radius, Sky};
use crate::physics::spectrum::xyz_to_linear_srgb;

/// The widest map accepted (16384×8192 texels, 1.5 GiB of f32 RGB).
pub const MAX_WIDTH: u32 = 16384;
/// Sub-samples per axis a texel beside the sun is split into to find how much of the disc it covers.
const SUN_SUBSAMPLES: u32 = 16;
/// Rings of the quadrature that gives the ground its illuminance.
const GROUND_RINGS: usize = 90;
/// Rings of the quadrature that projects the sky on the SH basis (the sky is smooth on this scale; a viewer
/// dragging the sun recomputes it every frame).
const SH_RINGS: usize = 64;

/// An equirectangular map of linear sRGB radiance (luminance in cd/m²), rows top (zenith) first.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[f32; 3]>,
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
    /// The clear sky `sky` as a `width`×`width/2` map over a ground of `ground_albedo` (0–1).
    pub fn of_sky(sky: &Sky, width: u32, ground_albedo: f64) -> Result<Self> {
        if width < 8 || width % 2 != 0 || width > MAX_WIDTH {
            return Err(Error::Invalid(format!(
                "an environment map's width must be even and between 8 and {MAX_WIDTH} texels, got {width}"
            )));
        }
        if !(ground_albedo.is_finite() && (0.0..=1.0).contains(&ground_albedo)) {
            return Err(Error::Invalid(format!(
                "the ground's albedo must lie between 0 and 1, got {}",
                crate::error::number(ground_albedo)
            )));
        }
        let height = width / 2;
        let light = sky_light(sky, ground_albedo);
        let mut xyz: Vec<DVec3> = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| light(direction_at(f64::from(x) + 0.5, f64::from(y) + 0.5, width)))
            .collect();
        for (i, weight) in sun_weights(sky.sun, width) {
            xyz[i] += sky.sun_xyz() * weight;
        }
        let rgb = xyz.iter().map(|&v| xyz_to_linear_srgb(v).as_vec3().to_array()).collect();
        Ok(Self { width, height, rgb })
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
    crate::physics::sh::Irradiance::of(|dir| xyz_to_linear_srgb(light(dir)) / sun, SH_RINGS)
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
            let map = EnvironmentMap::of_sky(&sky, width, 0.0).unwrap();
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
        let map = EnvironmentMap::of_sky(&sky, 64, 0.2).unwrap();
        let (sun, sky_lux) = sky.horizontal_illuminance(GROUND_RINGS);
        let [r, g, b] = map.rgb[map.rgb.len() - 1].map(f64::from);
        let ground = 0.2126 * r + 0.7152 * g + 0.0722 * b;
        assert!((ground / (0.2 * (sun + sky_lux) / std::f64::consts::PI) - 1.0).abs() < 1e-5, "{ground}");
    }

    /// The sky's nine SH coefficients against the irradiance summed over the sphere, at normals up, down, towards
    /// the sun, away from it and sideways: measured within 2.4 % facing up or sideways, 6.6 % facing down under a
    /// sun 20° high (the horizon's edge is detail beyond l = 2), 1.2 % under a sun 50° or 80° high.
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
                let tolerance = if elevation < 45.0 { 0.07 } else { 0.015 };
                assert!(rel < tolerance, "T {t}, sun {elevation}°, normal {n:.2}: {rel:.3e}");
            }
        }
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
