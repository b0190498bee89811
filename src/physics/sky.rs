//! A clear sky and its sun, in physical units: the analytic daylight model of Preetham, Shirley and Smits
//! (*A Practical Analytic Model for Daylight*, SIGGRAPH 1999), whose published coefficients (their Appendix A.2)
//! are the numbers below, and the sun's disc as a 5778 K black body dimmed by the same paper's Rayleigh and
//! aerosol extinction. Directions are world vectors with +y up, as in scenes.
//!
//! - **Sky**: the luminance Y and chromaticity (x, y) of each direction above the horizon follow Perez et al.'s
//!   distribution F(θ, γ) = (1 + A·e^{B/cos θ})·(1 + C·e^{Dγ} + E·cos²γ), normalised to the zenith's values:
//!   Y = Y_z·F(θ, γ)/F(0, θ_s), with θ the angle from the zenith, γ the angle from the sun and the five
//!   coefficients of each quantity linear in the turbidity T. Y_z is in kcd/m² (here converted to cd/m²).
//! - **Sun**: spectral radiance L_λ = B_λ(5778 K)·τ_R(λ)·τ_a(λ), W·m⁻²·sr⁻¹·nm⁻¹: the black body of the sun's
//!   effective temperature (over the sun's disc, [`crate::physics::optics::SUN_SOLID_ANGLE`], it gives 1.36 kW/m²
//!   above the atmosphere, the solar constant), through Rayleigh scattering τ_R = exp(−0.008735·λ^−4.08·m) and
//!   aerosols (Ångström) τ_a = exp(−β·λ^−1.3·m), β = 0.04608·T − 0.04586, λ in µm, for the relative air mass m
//!   of the sun's zenith angle (Kasten's formula, as Preetham et al. use it). Ozone, water vapour and mixed-gas
//!   absorption, which their appendix adds from tables, are left out (they remove a few per cent, mostly in the
//!   red and near infrared).
//!
//! Luminances are photometric (cd/m², 683 lm/W with the CIE 1931 ȳ), so the sun and the sky keep their physical
//! ratio. Validity: Preetham et al. fitted turbidities 2 to 10 (their Fig. 2: exceptionally clear air to light
//! haze); below 2 the Perez luminance goes negative near the zenith (Zotti et al. 2007). Both are refused outside
//! [`TURBIDITY_RANGE`], as is a sun below the horizon.

use glam::DVec3;

use crate::error::{Error, Result};
use crate::gpu::interface::{TABLE_LAMBDA_MIN_NM, TABLE_ROWS};
use crate::physics::cie_tables::cie1931_xyz;
use crate::physics::optics::SUN_SOLID_ANGLE;

/// The turbidities the model accepts (Preetham et al.'s fitted range).
pub const TURBIDITY_RANGE: (f64, f64) = (2.0, 10.0);
/// The sun's effective temperature, K: its black body over the sun's disc gives the solar constant.
pub const SUN_TEMPERATURE_K: f64 = 5778.0;
/// Lumens per watt at 555 nm: turns ∫ L_λ ȳ dλ into cd/m².
pub const LUMINOUS_EFFICACY: f64 = 683.0;
/// The sun's angular radius, rad (0.533° across: the solid angle [`SUN_SOLID_ANGLE`]).
pub fn sun_angular_radius() -> f64 {
    (1.0 - SUN_SOLID_ANGLE / std::f64::consts::TAU).acos()
}

/// Perez's five coefficients (A … E) of one quantity at turbidity `t`: (slope, intercept) pairs of Preetham et
/// al.'s Appendix A.2.
fn perez(t: f64, lines: [(f64, f64); 5]) -> [f64; 5] {
    lines.map(|(slope, intercept)| slope * t + intercept)
}

const PEREZ_Y: [(f64, f64); 5] =
    [(0.1787, -1.4630), (-0.3554, 0.4275), (-0.0227, 5.3251), (0.1206, -2.5771), (-0.0670, 0.3703)];
const PEREZ_X: [(f64, f64); 5] =
    [(-0.0193, -0.2592), (-0.0665, 0.0008), (-0.0004, 0.2125), (-0.0641, -0.8989), (-0.0033, 0.0452)];
const PEREZ_SMALL_Y: [(f64, f64); 5] =
    [(-0.0167, -0.2608), (-0.0950, 0.0092), (-0.0079, 0.2102), (-0.0441, -1.6537), (-0.0109, 0.0529)];
/// The zenith chromaticity: x_z = (T², T, 1)·M·(θ_s³, θ_s², θ_s, 1).
const ZENITH_X: [[f64; 4]; 3] =
    [[0.00166, -0.00375, 0.00209, 0.0], [-0.02903, 0.06377, -0.03202, 0.00394], [0.11693, -0.21196, 0.06052, 0.25886]];
const ZENITH_Y: [[f64; 4]; 3] =
    [[0.00275, -0.00610, 0.00317, 0.0], [-0.04214, 0.08970, -0.04153, 0.00516], [0.15346, -0.26756, 0.06670, 0.26688]];

/// F(θ, γ) for `cos_theta` > 0.
fn perez_f(c: &[f64; 5], cos_theta: f64, gamma: f64) -> f64 {
    (1.0 + c[0] * (c[1] / cos_theta).exp()) * (1.0 + c[2] * (c[3] * gamma).exp() + c[4] * gamma.cos().powi(2))
}

/// A clear sky for one sun and turbidity.
#[derive(Clone, Debug, PartialEq)]
pub struct Sky {
    pub turbidity: f64,
    /// Unit vector towards the sun (world, +y up).
    pub sun: DVec3,
    /// The sun's zenith angle θ_s, rad.
    theta_s: f64,
    coef_y: [f64; 5],
    coef_x: [f64; 5],
    coef_small_y: [f64; 5],
    /// The zenith's luminance (cd/m²) and chromaticity.
    pub zenith: (f64, f64, f64),
}

impl Sky {
    /// The sky with the sun towards `sun` (any length; its elevation must be 0°–90°) at `turbidity`.
    pub fn new(turbidity: f64, sun: DVec3) -> Result<Self> {
        let (lo, hi) = TURBIDITY_RANGE;
        if !(turbidity.is_finite() && (lo..=hi).contains(&turbidity)) {
            return Err(Error::setting(
                "turbidity",
                format!(
                    "the turbidity must lie between {lo} (exceptionally clear) and {hi} (light haze), the range \
                 Preetham et al. fitted their sky to; got {}",
                    crate::error::number(turbidity)
                ),
            ));
        }
        let sun = sun.try_normalize().filter(|d| d.is_finite()).ok_or_else(|| {
            Error::setting("sun direction", "the sun's direction must be a finite, non-zero vector".into())
        })?;
        if sun.y < 0.0 {
            return Err(Error::setting(
                "sun direction",
                format!(
                    "the sun is {:.2}° below the horizon: the clear-sky model is for daylight (elevation 0°–90°)",
                    -sun.y.asin().to_degrees()
                ),
            ));
        }
        let theta_s = sun.y.clamp(-1.0, 1.0).acos();
        let t = turbidity;
        let chi = (4.0 / 9.0 - t / 120.0) * (std::f64::consts::PI - 2.0 * theta_s);
        let luminance = ((4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192) * 1e3;
        let chroma = |m: &[[f64; 4]; 3]| {
            let th = [theta_s.powi(3), theta_s.powi(2), theta_s, 1.0];
            let row = |r: &[f64; 4]| r.iter().zip(th).map(|(a, b)| a * b).sum::<f64>();
            t * t * row(&m[0]) + t * row(&m[1]) + row(&m[2])
        };
        Ok(Self {
            turbidity,
            sun,
            theta_s,
            coef_y: perez(t, PEREZ_Y),
            coef_x: perez(t, PEREZ_X),
            coef_small_y: perez(t, PEREZ_SMALL_Y),
            zenith: (luminance, chroma(&ZENITH_X), chroma(&ZENITH_Y)),
        })
    }

    /// The sky with the sun at `elevation_deg` above the horizon and `azimuth_deg` (0 along +z, 90 along +x).
    pub fn at(turbidity: f64, elevation_deg: f64, azimuth_deg: f64) -> Result<Self> {
        if !(elevation_deg.is_finite() && azimuth_deg.is_finite() && (0.0..=90.0).contains(&elevation_deg)) {
            return Err(Error::setting(
                "sun elevation",
                format!(
                    "the sun's elevation must lie between 0° and 90° (and its azimuth be finite); got {}°, {}°",
                    crate::error::number(elevation_deg),
                    crate::error::number(azimuth_deg)
                ),
            ));
        }
        Self::new(turbidity, direction(elevation_deg, azimuth_deg))
    }

    /// The sky's luminance (cd/m²) and chromaticity (x, y) towards `dir` (unit, world); None at or below the
    /// horizon.
    pub fn yxy(&self, dir: DVec3) -> Option<(f64, f64, f64)> {
        if dir.y <= 0.0 {
            return None;
        }
        let gamma = dir.dot(self.sun).clamp(-1.0, 1.0).acos();
        let relative = |c: &[f64; 5]| perez_f(c, dir.y, gamma) / perez_f(c, 1.0, self.theta_s);
        let (yz, xz, small_yz) = self.zenith;
        Some((yz * relative(&self.coef_y), xz * relative(&self.coef_x), small_yz * relative(&self.coef_small_y)))
    }

    /// The sky's CIE XYZ towards `dir` (Y: luminance in cd/m²); zero at or below the horizon.
    pub fn xyz(&self, dir: DVec3) -> DVec3 {
        self.yxy(dir).map_or(DVec3::ZERO, |(y, cx, cy)| DVec3::new(cx / cy * y, y, (1.0 - cx - cy) / cy * y))
    }

    /// The relative optical air mass towards the sun (Kasten's formula, as Preetham et al. use it).
    pub fn air_mass(&self) -> f64 {
        let deg = self.theta_s.to_degrees();
        1.0 / (self.theta_s.cos() + 0.15 * (93.885 - deg).powf(-1.253))
    }

    /// The sun disc's spectral radiance at `lambda_nm`, W·m⁻²·sr⁻¹·nm⁻¹ (see the module's note).
    pub fn sun_spectral_radiance(&self, lambda_nm: f64) -> f64 {
        let um = lambda_nm * 1e-3;
        let m = self.air_mass();
        let beta = 0.04608 * self.turbidity - 0.04586;
        let rayleigh = (-0.008735 * um.powf(-4.08) * m).exp();
        let aerosol = (-beta * um.powf(-1.3) * m).exp();
        planck(lambda_nm, SUN_TEMPERATURE_K) * rayleigh * aerosol
    }

    /// The sun disc's CIE XYZ (Y: luminance in cd/m²), from its spectrum and the CIE 1931 observer at 1 nm.
    pub fn sun_xyz(&self) -> DVec3 {
        spectrum_xyz(|l| self.sun_spectral_radiance(l))
    }

    /// The illuminance on a horizontal surface, lux: (from the sun's disc, from the sky), the sky's by the
    /// midpoint rule on `rings` rings × 4·`rings` cells of the upper hemisphere ([`crate::physics::sh::sphere_cells`]).
    pub fn horizontal_illuminance(&self, rings: usize) -> (f64, f64) {
        let (sun, sky) = self.horizontal_illuminance_xyz(rings);
        (sun.y, sky.y)
    }

    /// [`Self::horizontal_illuminance`] as CIE XYZ (Y in lux): the colour of the light a horizontal surface gets.
    pub fn horizontal_illuminance_xyz(&self, rings: usize) -> (DVec3, DVec3) {
        let sun = self.sun_xyz() * SUN_SOLID_ANGLE * self.sun.y;
        // The sphere's first `rings` rings of 2·`rings` are the upper hemisphere.
        let sky = crate::physics::sh::sphere_cells(2 * rings)
            .take(rings * 4 * rings)
            .map(|(dir, omega)| self.xyz(dir) * (dir.y * omega));
        (sun, sky.sum())
    }
}

/// The unit vector at `elevation_deg` above the horizon and `azimuth_deg` (0 along +z, 90 along +x), +y up.
pub fn direction(elevation_deg: f64, azimuth_deg: f64) -> DVec3 {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    DVec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
}

/// Planck's spectral radiance of a black body, W·m⁻²·sr⁻¹·nm⁻¹.
pub fn planck(lambda_nm: f64, temperature_k: f64) -> f64 {
    const H: f64 = 6.626_070_15e-34;
    const C: f64 = 299_792_458.0;
    const K: f64 = 1.380_649e-23;
    let l = lambda_nm * 1e-9;
    2.0 * H * C * C / l.powi(5) / ((H * C / (l * K * temperature_k)).exp_m1()) * 1e-9
}

/// CIE XYZ of a spectral radiance (W·m⁻²·sr⁻¹·nm⁻¹) over the 1 nm CIE 1931 table: Y in cd/m².
pub fn spectrum_xyz(radiance: impl Fn(f64) -> f64) -> DVec3 {
    (0..TABLE_ROWS)
        .map(|i| {
            let lambda = TABLE_LAMBDA_MIN_NM + i as f64;
            DVec3::from(cie1931_xyz()[i]) * radiance(lambda)
        })
        .sum::<DVec3>()
        * LUMINOUS_EFFICACY
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(t: f64, elevation: f64) -> Sky {
        Sky::at(t, elevation, 30.0).unwrap()
    }

    #[test]
    fn the_zenith_has_the_zenith_values_and_the_sky_is_symmetric_about_the_sun() {
        let s = sky(3.0, 40.0);
        let (y, x, small_y) = s.yxy(DVec3::Y).unwrap();
        assert!((y / s.zenith.0 - 1.0).abs() < 1e-12 && (x - s.zenith.1).abs() < 1e-12);
        assert!((small_y - s.zenith.2).abs() < 1e-12);
        // Mirrored across the sun's vertical plane (azimuth 30°): the same sky.
        let (a, b) = (direction(25.0, 30.0 + 50.0), direction(25.0, 30.0 - 50.0));
        assert!((s.xyz(a) - s.xyz(b)).length() < 1e-9 * s.xyz(a).length());
        // Brighter beside the sun than a quarter turn away at the same height; nothing below the horizon.
        assert!(s.xyz(direction(40.0, 35.0)).y > 3.0 * s.xyz(direction(40.0, 120.0)).y);
        assert_eq!(s.xyz(direction(-5.0, 0.0)), DVec3::ZERO);
    }

    /// Preetham et al.'s zenith luminance for a clear sky (T = 2, sun 60° high): (4.0453·2 − 4.9710)·tan χ −
    /// 0.2155·2 + 2.4192 kcd/m², χ = (4/9 − 2/120)(π − 2·30°).
    #[test]
    fn the_zenith_luminance_is_the_papers_formula() {
        let chi = (4.0 / 9.0 - 2.0 / 120.0) * (std::f64::consts::PI - 2.0 * 30f64.to_radians());
        let expected = ((4.0453 * 2.0 - 4.9710) * chi.tan() - 0.2155 * 2.0 + 2.4192) * 1e3;
        let s = sky(2.0, 60.0);
        assert!((s.zenith.0 - expected).abs() < 1e-9 * expected, "{} vs {expected}", s.zenith.0);
        // A clear sky's zenith: a few kcd/m², bluer than daylight white (x < 0.3127).
        assert!((4e3..9e3).contains(&s.zenith.0) && s.zenith.1 < 0.3127, "{:?}", s.zenith);
    }

    /// Over the accepted range the sky is positive, finite and of plausible chromaticity everywhere above the
    /// horizon; outside it, one clear refusal.
    #[test]
    fn the_accepted_range_is_physical_and_the_rest_is_refused() {
        for t in [2.0, 3.0, 6.0, 10.0] {
            for elevation in [0.0, 5.0, 30.0, 60.0, 90.0] {
                let s = sky(t, elevation);
                for e in [0.5, 5.0, 30.0, 60.0, 89.9] {
                    for a in (0..360).step_by(15) {
                        let (y, x, small_y) = s.yxy(direction(e, f64::from(a))).unwrap();
                        assert!(y.is_finite() && y > 0.0, "T {t}, sun {elevation}°, at ({e}°, {a}°): Y = {y}");
                        assert!((0.15..0.5).contains(&x) && (0.15..0.5).contains(&small_y), "({x}, {small_y})");
                    }
                }
            }
        }
        for t in [1.9, 10.5, f64::NAN] {
            assert!(Sky::at(t, 30.0, 0.0).unwrap_err().to_string().contains("turbidity"));
        }
        for e in [-1.0, 91.0, f64::INFINITY] {
            assert!(Sky::at(3.0, e, 0.0).unwrap_err().to_string().contains("elevation"));
        }
        assert!(Sky::new(3.0, DVec3::new(0.0, -1.0, 0.2)).unwrap_err().to_string().contains("below the horizon"));
        assert!(Sky::new(3.0, DVec3::ZERO).is_err());
    }

    /// The sun: its black body gives the solar constant over its disc (1361 W/m² above the atmosphere, to the
    /// 0.5 % of the effective temperature's definition); the Rayleigh optical depth at 550 nm is the standard
    /// atmosphere's 0.097 (Bucholtz 1995: 0.0973); at noon under a clear sky its luminance is the textbook
    /// 1.6·10⁹ cd/m² (±15 %: ozone and water are left out), and sun and sky light a horizontal surface in the ratio
    /// of a clear day (the sky 10–25 % of the total).
    #[test]
    fn the_sun_has_its_physical_size_and_brightness() {
        let constant: f64 = (100..100_000).map(|nm| planck(f64::from(nm), SUN_TEMPERATURE_K)).sum::<f64>();
        assert!((constant * SUN_SOLID_ANGLE / 1361.0 - 1.0).abs() < 0.01, "{}", constant * SUN_SOLID_ANGLE);
        let zenith_sun = sky(2.0, 90.0);
        assert!((zenith_sun.air_mass() - 1.0).abs() < 1e-3, "{}", zenith_sun.air_mass());
        let rayleigh_depth = 0.008735 * 0.55f64.powf(-4.08);
        assert!((rayleigh_depth - 0.0973).abs() < 0.003, "{rayleigh_depth}");
        let noon = zenith_sun.sun_xyz().y;
        assert!((noon / 1.6e9 - 1.0).abs() < 0.15, "{noon:.3e} cd/m²");
        let share = |t: f64, elevation: f64| {
            let (sun, sky_lux) = sky(t, elevation).horizontal_illuminance(90);
            sky_lux / (sun + sky_lux)
        };
        for elevation in [50.0, 80.0] {
            // Measured: 25 % and 19 % at T = 2; 31 % and 27 % at 3; 53 % and 49 % at 6.
            assert!((0.10..0.30).contains(&share(2.0, elevation)), "{}", share(2.0, elevation));
            assert!(share(2.0, elevation) < share(3.0, elevation) && share(3.0, elevation) < share(6.0, elevation));
        }
        assert!((0.26..0.27).contains(&sun_angular_radius().to_degrees()), "{}", sun_angular_radius().to_degrees());
    }
}
