//! Directions and the geometric factors of Stam's BRDF, in the patch frame (model.md §1.1, §1.5, §1.9, §1.10).
//! `glsl/include/brdf.glsl` implements the same functions under the same names.

use glam::DVec3;

use crate::error::{Error, Result};

/// Refractive index of snake skin (model.md §1.9: "close to the measured value from snake sheds"); one source
/// with the shaders' (`shaders::interface`).
pub const SKIN_INDEX: f64 = crate::gpu::interface::SKIN_INDEX;
/// The sun's solid angle (0.53° across), sr: its diffuse contribution relative to its glint in a mirror; one
/// source with the shaders' (`shaders::interface`).
pub const SUN_SOLID_ANGLE: f64 = crate::gpu::interface::SUN_SOLID_ANGLE;

/// [`transmittance`] averaged over a uniform sky's incidences, cosine-weighted: ∫ (1 − R(c)) 2c dc over
/// c ∈ [0, 1] for exact Fresnel at n = [`SKIN_INDEX`] (one source with the shaders': `gpu::interface`; a test
/// integrates it).
pub const SKY_TRANSMITTANCE: f64 = crate::gpu::interface::SKY_TRANSMITTANCE;

/// Fresnel's reflectance of unpolarised light arriving from air at incidence cos θ = `cos_theta` on a dielectric
/// of index `n` (the mean of the s and p reflectances, exact; `fresnel_reflectance` in glsl/include/brdf.glsl):
/// R = (r_s² + r_p²)/2, r_s = (cos θ − n cos θ_t)/(cos θ + n cos θ_t), r_p = (n cos θ − cos θ_t)/(n cos θ +
/// cos θ_t), with Snell's n sin θ_t = sin θ. R₀ at normal incidence, 1 at grazing.
pub fn fresnel_reflectance(cos_theta: f64, n: f64) -> f64 {
    let c = cos_theta.clamp(0.0, 1.0);
    let cos_t = (1.0 - (1.0 - c * c) / (n * n)).sqrt();
    let rs = (c - n * cos_t) / (c + n * cos_t);
    let rp = (n * c - cos_t) / (n * c + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// The share of light that crosses the skin's surface at incidence cos θ: 1 − R, exact Fresnel
/// (`transmittance` in glsl/include/surface_shade.glsl).
pub fn transmittance(cos_theta: f64) -> f64 {
    1.0 - fresnel_reflectance(cos_theta, SKIN_INDEX)
}

/// [`SKY_TRANSMITTANCE`], as the shaders name it.
pub fn sky_transmittance() -> f64 {
    SKY_TRANSMITTANCE
}

/// How a pigment is lit beyond the directions: the share of the sun's disc that no shadow hides (0–1), and
/// whether the skin covers it (false: a matte material, lit and seen directly).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lit {
    pub sun_visible: f64,
    pub coated: bool,
}

impl Lit {
    /// In the open sun, under the skin.
    pub const OPEN: Self = Self { sun_visible: 1.0, coated: true };
}

/// The light the skin's pigment returns under the grating, linear RGB (the surface pass's non-diffracted term,
/// `pigment_rgb` in glsl/surface.frag.glsl). A Lambertian `albedo` under the skin's surface, lit through that
/// surface by the sun's disc (cos θ_i, the sun's radiance being the mirror glint's 1, times the share of it
/// `lit.sun_visible`) and by a sky of radiance `ambient` above the horizon with dark ground below — a surface
/// whose normal makes cos = `normal_up` with the world's up sees (1 + normal_up)/2 of it, which is what shades
/// the form of a body — and seen through it. Without the skin (`lit.coated` false) the albedo is lit and seen
/// directly.
pub fn pigment_rgb(omega_i: DVec3, omega_r: DVec3, normal_up: f64, albedo: DVec3, ambient: f64, lit: Lit) -> DVec3 {
    if omega_r.z <= 0.0 {
        return DVec3::ZERO;
    }
    let through = |t: f64| if lit.coated { t } else { 1.0 };
    let sun = SUN_SOLID_ANGLE / std::f64::consts::PI
        * omega_i.z.max(0.0)
        * lit.sun_visible
        * through(transmittance(omega_i.z));
    let sky = ambient * 0.5 * (1.0 + normal_up) * through(sky_transmittance());
    albedo * (through(transmittance(omega_r.z)) * (sun + sky))
}

/// The pigment lit by an environment whose irradiance over π at the shading normal is `sky_over_pi` (linear RGB,
/// `physics::sh::Irradiance::over_pi`): through the skin on the way in (averaged over the sky) and out unless
/// not `coated`, in the environment's own colours (`pigment_sky_rgb` in glsl/surface.frag.glsl).
pub fn pigment_sky_rgb(omega_r: DVec3, albedo: DVec3, sky_over_pi: DVec3, coated: bool) -> DVec3 {
    if omega_r.z <= 0.0 {
        return DVec3::ZERO;
    }
    let through = if coated { transmittance(omega_r.z) * sky_transmittance() } else { 1.0 };
    albedo * through * sky_over_pi
}

/// A unit vector from the surface towards the light or the viewer: (sin θ cos φ, sin θ sin φ, cos θ).
pub fn direction(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// Checks an inclination: 0 ≤ θ < 90° (90° lies on the horizon, where the BRDF's 1/cos θ_r diverges).
pub(crate) fn check_theta(what: &str, theta_deg: f64) -> Result<()> {
    if !(theta_deg.is_finite() && (0.0..90.0).contains(&theta_deg)) {
        return Err(Error::setting("theta", format!("{what} θ = {theta_deg}° is not above the horizon (0 ≤ θ < 90°)")));
    }
    Ok(())
}

/// Stam's (u, v, w) = −ω_i − ω_r.
pub fn uvw(omega_i: DVec3, omega_r: DVec3) -> DVec3 {
    -omega_i - omega_r
}

/// Fresnel's reflectance relative to normal incidence, R(θ)/R₀ ([`fresnel_reflectance`], exact), with
/// cos θ = H·ω_r (model.md §1.9). Unsquared on purpose: R is already the reflectance, Stam's F² (model.md §7.2
/// item 2).
pub fn fresnel_ratio(omega_i: DVec3, omega_r: DVec3, n: f64) -> f64 {
    let h = (omega_i + omega_r).normalize();
    fresnel_reflectance(h.dot(omega_r), n) / normal_reflectance(n)
}

/// The gain factor C(ω_i, ω_r) that turns |P|² into the relative reflectance ρ_λ (model.md §1.5):
/// C = (R/R₀)·(1 + ω_i·ω_r)² / (cos θ_r · w²). A flat mirror at normal incidence gets C = 1.
pub fn gain_factor(omega_i: DVec3, omega_r: DVec3) -> f64 {
    if omega_i.z <= 0.0 || omega_r.z <= 0.0 {
        return 0.0;
    }
    let w = uvw(omega_i, omega_r).z;
    let cos_sum = 1.0 + omega_i.dot(omega_r);
    fresnel_ratio(omega_i, omega_r, SKIN_INDEX) * cos_sum * cos_sum / (omega_r.z * w * w)
}

/// Fresnel reflectance at normal incidence of a dielectric of index `n` in air, R₀ = ((n − 1)/(n + 1))².
pub fn normal_reflectance(n: f64) -> f64 {
    ((n - 1.0) / (n + 1.0)).powi(2)
}

/// The factor that turns the relative reflectance ρ_λ (peak-normalised: a flat patch gives C at its mirror
/// direction) into Stam's BRDF in physical units, sr⁻¹: f = ρ_λ · R₀ · (k σ_s)² / (π cos θ_i), with k = 2π/λ and
/// σ_s = coherence/4 (both in µm).
///
/// Why this factor: the coherence window apodises the patch by exp(−|x|²/2σ_s²), so a flat patch's power is
/// |P|² = exp(−(k σ_s)²(u² + v²)), whose integral over (u, v) — the projected solid angle cos θ_r dω_r — is
/// π/(k σ_s)²; at the mirror direction C = (R/R₀)·cos θ_i. With this factor a flat mirror reflects the fraction R
/// of the incident flux whatever the coherence length (∫ f cos θ_r dω_r = R; tests/physics.rs), and a lobe's
/// energy no longer falls as the coherence grows: it is Stam's k²F²/(4π²A) with A the window's effective area
/// 4πσ_s² (the apodisation's (∫g)²/∫g²). 0 where the light is not above the surface.
pub fn brdf_per_sr_scale(lambda_um: f64, coherence_um: f64, cos_theta_i: f64) -> f64 {
    if cos_theta_i <= 0.0 {
        return 0.0;
    }
    let k_sigma = std::f64::consts::TAU / lambda_um * coherence_um / 4.0;
    normal_reflectance(SKIN_INDEX) * k_sigma * k_sigma / (std::f64::consts::PI * cos_theta_i)
}

/// V-groove shadowing and masking in the patch frame (n = z), after Stam's appendix and Torrance–Sparrow:
/// min(1, 2(h·n)(ω_r·n)/(ω_r·h), 2(h·n)(ω_i·n)/(ω_r·h)).
pub fn shadow_mask(omega_i: DVec3, omega_r: DVec3) -> f64 {
    let h = (omega_i + omega_r).normalize();
    let eh = omega_r.dot(h).max(1e-12);
    (2.0 * h.z * omega_r.z / eh).min(2.0 * h.z * omega_i.z / eh).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirror_at_normal_incidence_has_unit_gain() {
        let z = direction(0.0, 0.0);
        assert!((gain_factor(z, z) - 1.0).abs() < 1e-15);
        assert_eq!(uvw(z, z), DVec3::new(0.0, 0.0, -2.0));
    }

    /// Exact Fresnel against values computed independently (mpmath, 30 digits, from the s and p amplitudes) for
    /// n = 1.5: R₀ = 0.04; 0.0502399 at 45°, 0.0891867 at 60° and 0.6740532 at 86° (Schlick's approximation gives
    /// 0.0421, 0.0700 and 0.7087: 16 % and 21 % low, 5 % high); at Brewster's angle r_p vanishes, so R = r_s²/2.
    #[test]
    fn fresnel_is_exact() {
        let at = |deg: f64| fresnel_reflectance(deg.to_radians().cos(), 1.5);
        assert!((at(0.0) - 0.04).abs() < 1e-15);
        for (deg, expected) in
            [(45.0, 0.050_239_911_012_236), (60.0, 0.089_186_712_802_213), (86.0, 0.674_053_187_926_252)]
        {
            assert!((at(deg) - expected).abs() < 1e-12, "{deg}°: {} vs {expected}", at(deg));
        }
        let brewster = 1.5f64.atan();
        let cos_t = brewster.sin(); // θ_t = 90° − θ_B
        let rs = (brewster.cos() - 1.5 * cos_t) / (brewster.cos() + 1.5 * cos_t);
        assert!((fresnel_reflectance(brewster.cos(), 1.5) - rs * rs / 2.0).abs() < 1e-15);
        assert!((at(90.0) - 1.0).abs() < 1e-15);
        // The ratio at the half vector: H = z, cos θ = cos 60°.
        let (wi, wr) = (direction(60.0, 0.0), direction(60.0, 180.0));
        assert!((fresnel_ratio(wi, wr, 1.5) - 0.089_186_712_802_213 / 0.04).abs() < 1e-10);
    }

    /// The shared constant is the cosine-weighted mean of 1 − R over the hemisphere (0.908222040657649 by mpmath);
    /// here by Gauss–Legendre-free midpoint rule on 200 000 cells.
    #[test]
    fn the_sky_transmittance_is_the_mean_over_the_hemisphere() {
        let n = 200_000;
        let mean: f64 = (0..n)
            .map(|i| {
                let c = (f64::from(i) + 0.5) / f64::from(n);
                transmittance(c) * 2.0 * c / f64::from(n)
            })
            .sum();
        assert!((mean - SKY_TRANSMITTANCE).abs() < 1e-9, "{mean} vs {SKY_TRANSMITTANCE}");
        assert!((SKY_TRANSMITTANCE - 0.908_222_040_657_649).abs() < 1e-14);
    }

    #[test]
    fn grazing_angles_stay_finite() {
        for theta in [89.0, 89.9, 89.99] {
            let (wi, wr) = (direction(theta, 0.0), direction(theta, 0.0));
            let c = gain_factor(wi, wr);
            assert!(c.is_finite() && c > 0.0, "θ = {theta}: {c}");
        }
        assert!(check_theta("view", 90.0).is_err());
        assert!(check_theta("view", -1.0).is_err());
        assert!(check_theta("view", 89.99).is_ok());
    }
}
