//! Spectral integration into colour (model.md §1.8, with the thesis's errors of §7.2 items 7–9 fixed):
//! X = Σ_λ ρ(λ)·x̄(λ)·S(λ)·Δλ / Σ_λ ȳ(λ)·S(λ)·Δλ (likewise Y, Z) with the CIE 1931 2° observer and S the light's
//! illuminant (D65 unless a scene names another, [`crate::physics::illuminant`]), so a perfect mirror integrates to the
//! illuminant's white point with Y = 1; then XYZ → linear sRGB (IEC 61966-2-1, not the thesis's CIE-RGB matrix),
//! exposure 2^EV, and the sRGB transfer function. The display's white is D65: a mirror under illuminant A looks
//! orange, as a photograph without white balance shows it.
//! `glsl/include/spectrum.glsl` implements the same functions under the same names.

use glam::DVec3;

use crate::gpu::interface::{TABLE_LAMBDA_MAX_NM, TABLE_LAMBDA_MIN_NM, TABLE_ROWS};
use crate::physics::cie_tables::cie1931_xyz;
use crate::physics::colour::xyz_to_linear_srgb;
use crate::physics::illuminant::Illuminant;

/// The visible range the renderer integrates over, nm (model.md §5.2).
pub const VISIBLE_MIN_NM: f64 = TABLE_LAMBDA_MIN_NM;
pub const VISIBLE_MAX_NM: f64 = TABLE_LAMBDA_MAX_NM;

/// (x̄, ȳ, z̄, S/100) at `lambda_nm` under `illuminant`, linearly interpolated in the 1 nm tables; zero outside
/// 380–780 nm. S is the illuminant averaged over the `step_nm` the wavelengths are sampled at (its 1 nm rows
/// within ±step/2, the rows on the edges half): a sample stands for its step, so a lamp's narrow lines (the
/// F-series' mercury lines at 436 and 546 nm) count at the nearest sample instead of falling between samples.
pub(crate) fn spectrum_at(lambda_nm: f64, illuminant: &Illuminant, step_nm: f64) -> [f64; 4] {
    if !(TABLE_LAMBDA_MIN_NM..=TABLE_LAMBDA_MAX_NM).contains(&lambda_nm) {
        return [0.0; 4];
    }
    let x = lambda_nm - TABLE_LAMBDA_MIN_NM;
    let i = (x.floor() as usize).min(TABLE_ROWS - 2);
    let t = x - i as f64;
    let cmf = |k: usize| cie1931_xyz()[k];
    let (a, b) = (cmf(i), cmf(i + 1));
    let [xb, yb, zb] = [0, 1, 2].map(|c| a[c] + (b[c] - a[c]) * t);
    [xb, yb, zb, illuminant_over_step(illuminant, lambda_nm, step_nm) / 100.0]
}

/// The illuminant's mean over [λ − step/2, λ + step/2] from its 1 nm rows (rows on an edge count half), within
/// 380–780 nm; its interpolated value for steps of 1 nm or less.
fn illuminant_over_step(illuminant: &Illuminant, lambda_nm: f64, step_nm: f64) -> f64 {
    if step_nm <= 1.0 {
        return illuminant.power(lambda_nm);
    }
    let half = 0.5 * step_nm;
    let (lo, hi) = ((lambda_nm - half).max(TABLE_LAMBDA_MIN_NM), (lambda_nm + half).min(TABLE_LAMBDA_MAX_NM));
    let (mut sum, mut weight) = (0.0, 0.0);
    let mut m = lo.ceil();
    while m <= hi {
        let w = if (m - lo).abs() < 1e-9 || (hi - m).abs() < 1e-9 { 0.5 } else { 1.0 };
        sum += w * illuminant.power(m);
        weight += w;
        m += 1.0;
    }
    if weight > 0.0 {
        sum / weight
    } else {
        illuminant.power(lambda_nm)
    }
}

/// The table as the GPU reads it for `sampling`: (x̄, ȳ, z̄, S/100) per nm from 380 to 780 as f32 vec4s, S
/// averaged over the sampling's step as [`Sampling::weights_at`] does.
pub(crate) fn gpu_table(sampling: &Sampling) -> Vec<[f32; 4]> {
    (0..TABLE_ROWS).map(|k| sampling.weights_at(TABLE_LAMBDA_MIN_NM + k as f64).map(|v| v as f32)).collect()
}

/// Evenly spaced wavelengths: `lambda_min_nm + k·step` for k = 0..count, each weighing `step` nm, under the
/// light's `illuminant`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    pub lambda_min_nm: f64,
    pub step_nm: f64,
    pub count: usize,
    pub illuminant: Illuminant,
}

impl Sampling {
    /// Every `step_nm` from 380 nm up to 780 nm (inclusive when the step divides 400 nm), under D65.
    pub fn visible(step_nm: f64) -> Self {
        Self::visible_under(step_nm, Illuminant::d65())
    }

    /// Every `step_nm` from 380 nm up to 780 nm under `illuminant`.
    pub fn visible_under(step_nm: f64, illuminant: Illuminant) -> Self {
        let count = ((VISIBLE_MAX_NM - VISIBLE_MIN_NM) / step_nm + 1e-9).floor() as usize + 1;
        Self { lambda_min_nm: VISIBLE_MIN_NM, step_nm, count, illuminant }
    }

    /// (x̄, ȳ, z̄, S/100) at `lambda_nm` under this sampling's illuminant, averaged over its step.
    pub fn weights_at(&self, lambda_nm: f64) -> [f64; 4] {
        spectrum_at(lambda_nm, &self.illuminant, self.step_nm)
    }

    pub fn wavelengths(&self) -> impl Iterator<Item = f64> + '_ {
        (0..self.count).map(|k| self.lambda_min_nm + k as f64 * self.step_nm)
    }

    /// The normaliser Σ ȳ·S·Δλ of this sampling: a mirror then has Y = 1.
    pub fn y_norm(&self) -> f64 {
        self.wavelengths().map(|l| self.weights_at(l)[1] * self.weights_at(l)[3] * self.step_nm).sum()
    }

    /// Each wavelength's (x̄, ȳ, z̄)·S/100 integrated over its bin from the 1 nm rows (a row halfway between two
    /// wavelengths split between them), so that the weights sum to the 1 nm tables' integrals: a spectrally flat
    /// reflectance then has exactly the colour of the light, however coarse the step, where point samples of the
    /// colour-matching functions at 10 nm are 0.7 % off in blue under a band of D65. For sums that integrate further
    /// (the environment's moments), whose values change slowly with λ.
    pub fn binned_weights(&self) -> Vec<[f64; 3]> {
        let fine = Self { step_nm: 1.0, count: TABLE_ROWS, lambda_min_nm: TABLE_LAMBDA_MIN_NM, ..*self };
        let mut weights = vec![[0.0; 3]; self.count];
        for m in fine.wavelengths() {
            let at = fine.weights_at(m);
            let row = [0, 1, 2].map(|c| at[c] * at[3]);
            let x = (m - self.lambda_min_nm) / self.step_nm;
            let halfway = (x - x.floor() - 0.5).abs() < 1e-9;
            let bins =
                if halfway { [(x.floor(), 0.5), (x.floor() + 1.0, 0.5)] } else { [(x.round(), 1.0), (0.0, 0.0)] };
            for (bin, share) in bins {
                if share > 0.0 && bin >= 0.0 && (bin as usize) < self.count {
                    for (w, v) in weights[bin as usize].iter_mut().zip(row) {
                        *w += share * v;
                    }
                }
            }
        }
        weights
    }
}

/// The factor a frame's diffraction is multiplied by: 1 in relative units; in physical units (an
/// [`Illuminant::physical`] light) R₀·Ω_sun·(k₅₅₀ σ_s)²/π — the BRDF in sr⁻¹ (`optics::brdf_per_sr_scale`) times
/// the sun's irradiance Ω_sun·cos θ_i, per unit of the sun's radiance, at 550 nm, the rest of its (550/λ)² being in
/// the light's `spd` — times Σ ȳ·S′/Σ ȳ·S of `sampling`, which turns the sums' normaliser (of the weighted S′)
/// back into the light's own. The result: radiance relative to the sun's luminance, as the pigment has it.
pub fn diffraction_gain(sampling: &Sampling, coherence_um: f64) -> f64 {
    if !sampling.illuminant.physical {
        return 1.0;
    }
    let lambda_um = Illuminant::PHYSICAL_REFERENCE_NM * 1e-3;
    let scale = crate::physics::optics::brdf_per_sr_scale(lambda_um, coherence_um, 1.0);
    let own = Sampling { illuminant: sampling.illuminant.light(), ..*sampling };
    scale * crate::physics::optics::SUN_SOLID_ANGLE * sampling.y_norm() / own.y_norm()
}

/// The normaliser ∫ ȳ·S dλ over the 1 nm tables under `illuminant`: the constant for non-uniform samplings (NMM).
pub fn y_norm_continuous(illuminant: Illuminant) -> f64 {
    Sampling::visible_under(1.0, illuminant).y_norm()
}

/// XYZ of a spectral reflectance ρ(λ) under the sampling's illuminant, normalised so a mirror has Y = 1.
pub fn reflectance_to_xyz(sampling: &Sampling, rho: impl Fn(f64) -> f64) -> DVec3 {
    let mut xyz = DVec3::ZERO;
    for l in sampling.wavelengths() {
        let s = sampling.weights_at(l);
        xyz += DVec3::new(s[0], s[1], s[2]) * (rho(l) * s[3] * sampling.step_nm);
    }
    xyz / sampling.y_norm()
}

/// A white mirror's colour under `illuminant`, linear sRGB with Y = 1: what the light adds to a diffuse surface
/// (≈ (1, 1, 1) under D65, orange under A).
pub fn white_rgb(illuminant: Illuminant) -> DVec3 {
    xyz_to_linear_srgb(reflectance_to_xyz(&Sampling::visible_under(1.0, illuminant.light()), |_| 1.0))
}

/// Relative luminance Y of a linear sRGB texel or pixel (f32 channels: [`crate::physics::colour::luminance`]).
pub fn luminance(rgb: [f32; 3]) -> f64 {
    crate::physics::colour::luminance(DVec3::from(rgb.map(f64::from)))
}

/// The sRGB transfer function (IEC 61966-2-1) of one channel, clamped to [0, 1] (`display::tone`'s clip; the
/// shaders' `srgb_oetf` in display.glsl).
pub fn srgb_oetf(c: f64) -> f64 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mirror_under_d65_is_the_d65_white_point_and_srgb_white() {
        let white = reflectance_to_xyz(&Sampling::visible(1.0), |_| 1.0);
        // CIE D65 white point of the 2° observer: X = 0.95047, Z = 1.08883 (the tables truncated to 380–780 nm
        // give X to 5·10⁻⁵ and Z to 2.2·10⁻⁴).
        assert!(
            (white.x - 0.95047).abs() < 3e-4 && (white.y - 1.0).abs() < 1e-12 && (white.z - 1.08883).abs() < 3e-4,
            "{white}"
        );
        let rgb = xyz_to_linear_srgb(white);
        for c in rgb.to_array() {
            assert!((c - 1.0).abs() < 1e-3, "{rgb}");
        }
        let coarse = xyz_to_linear_srgb(reflectance_to_xyz(&Sampling::visible(5.0), |_| 1.0));
        for c in coarse.to_array() {
            assert!((c - 1.0).abs() < 2e-3, "5 nm sampling: {coarse}");
        }
    }

    /// Binned weights at any step sum to the 1 nm tables' integrals (each 1 nm row counted once), under a band of
    /// the environment's basis, whose edges point samples at 10 nm miss.
    #[test]
    fn binned_weights_sum_to_the_fine_integral() {
        let band = Illuminant::d65_band(0).physical();
        let fine = Sampling::visible_under(1.0, band);
        let integral = fine.wavelengths().fold([0.0; 3], |acc, l| {
            let w = fine.weights_at(l);
            [acc[0] + w[0] * w[3], acc[1] + w[1] * w[3], acc[2] + w[2] * w[3]]
        });
        for step in [2.0, 5.0, 10.0, 20.0, 7.0] {
            let sampling = Sampling::visible_under(step, band);
            let binned = sampling.binned_weights();
            assert_eq!(binned.len(), sampling.count);
            for c in 0..3 {
                let sum: f64 = binned.iter().map(|w| w[c]).sum();
                assert!((sum / integral[c] - 1.0).abs() < 1e-12, "{step} nm, channel {c}: {sum} vs {}", integral[c]);
            }
        }
    }

    #[test]
    fn a_lamps_lines_count_at_coarse_steps() {
        // F11's mercury lines sit between 5 nm samples: point-sampled, its white was off by 0.05 in x; averaged over
        // each step it keeps its chromaticity.
        let f11 = Illuminant::named("F11").unwrap();
        let xy = |step: f64| {
            let w = reflectance_to_xyz(&Sampling::visible_under(step, f11), |_| 1.0);
            (w.x / (w.x + w.y + w.z), w.y / (w.x + w.y + w.z))
        };
        let (fine, coarse) = (xy(1.0), xy(5.0));
        assert!((fine.0 - coarse.0).abs() < 2e-3 && (fine.1 - coarse.1).abs() < 2e-3, "{fine:?} vs {coarse:?}");
        let (x, y) = f11.xy(1);
        assert!((fine.0 - x).abs() < 1e-9 && (fine.1 - y).abs() < 1e-9, "1 nm steps are the table itself");
    }

    #[test]
    fn tables_match_published_values() {
        let d65 = Illuminant::d65();
        let s = spectrum_at(555.0, &d65, 1.0);
        assert!((s[1] - 1.0).abs() < 1e-3, "ȳ peaks at 1 near 555 nm: {s:?}");
        assert!((spectrum_at(560.0, &d65, 1.0)[3] - 1.0).abs() < 1e-12, "D65 is 100 at 560 nm");
        assert_eq!(spectrum_at(379.0, &d65, 1.0), [0.0; 4]);
        let mid = spectrum_at(550.5, &d65, 1.0);
        let (a, b) = (spectrum_at(550.0, &d65, 1.0), spectrum_at(551.0, &d65, 1.0));
        assert!((mid[0] - 0.5 * (a[0] + b[0])).abs() < 1e-15);
    }

    #[test]
    fn oetf_matches_the_standard() {
        assert_eq!(srgb_oetf(0.0), 0.0);
        assert!((srgb_oetf(1.0) - 1.0).abs() < 1e-12);
        assert!((srgb_oetf(0.18) - 0.46135).abs() < 1e-4);
    }

    #[test]
    fn sampling_counts() {
        assert_eq!(Sampling::visible(5.0).count, 81);
        assert_eq!(Sampling::visible(1.0).count, 401);
        assert_eq!(Sampling::visible(7.0).wavelengths().last().unwrap(), 779.0);
    }
}
