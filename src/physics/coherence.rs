//! The frequency lookup and the Gaussian coherence window (model.md §1.4).
//!
//! A view asks for P at the spatial frequency (u/λ, v/λ) in cycles/µm, which lies at the fractional bin
//! position s = (u·Lx/λ, v·Ly/λ) relative to DC. The surface is the periodic replica of the patch times a
//! Gaussian g of the spatial coherence (σ_s = coherence length / 4), so P is the line spectrum of the DFT
//! convolved with g's transform: P(s) = Σ_j F\[j\]·exp(−½·|(j − s)/σ|²) with σ = L/(2π σ_s) bins per axis.
//! The weight is 1 at a bin centre, so a flat patch gives exactly 1 at specular.
//!
//! Taps: the nearest bin n = round(s) and `radius` bins either side, per axis; bins outside the sampled
//! range (beyond Nyquist) contribute nothing. `glsl/include/taylor.glsl` uses the same rules.

use crate::error::{Error, Result};

/// The coherence length of filtered sunlight, µm (Mandel & Wolf, via model.md §1.4): 4σ_s = 65 µm.
pub const DEFAULT_COHERENCE_UM: f64 = 65.0;
/// The reference window reaches out to where the Gaussian weight falls below this: beyond it the taps change
/// no f64 sum.
pub const FULL_WINDOW_CUTOFF: f64 = 1e-17;
/// The shortest coherence length accepted, µm: below a couple of wavelengths the Gaussian window no longer
/// models partial coherence (white light's temporal coherence is about 1 µm, filtered sunlight's spatial 65 µm).
pub const MIN_COHERENCE_UM: f64 = 1.0;
/// The longest, µm (1 m, a laser's): beyond it the window is one bin wide whatever the patch.
pub const MAX_COHERENCE_UM: f64 = 1e6;

/// The coherence length a light of angular radius `angular_radius` (rad) gives, µm: the sun's
/// [`DEFAULT_COHERENCE_UM`] scaled by the van Cittert–Zernike law L ∝ 1/α (model.md §1.13), so that a light's
/// lobes are α/α_sun as wide as the sun's. Refused where L would leave [`MIN_COHERENCE_UM`, `MAX_COHERENCE_UM`].
pub fn of_light(angular_radius: f64) -> Result<f64> {
    let sun = crate::physics::sky::sun_angular_radius();
    let coherence_um = DEFAULT_COHERENCE_UM * sun / angular_radius;
    if !(angular_radius > 0.0 && (MIN_COHERENCE_UM..=MAX_COHERENCE_UM).contains(&coherence_um)) {
        let (widest, narrowest) =
            (sun * DEFAULT_COHERENCE_UM / MIN_COHERENCE_UM, sun * DEFAULT_COHERENCE_UM / MAX_COHERENCE_UM);
        return Err(Error::setting(
            "light radius",
            format!(
                "a light {}° in angular radius is not within {:.2e}°–{:.1}°, the radii whose coherence lengths \
                 (65 µm × 0.267°/radius) lie within {MIN_COHERENCE_UM}–{MAX_COHERENCE_UM:e} µm",
                crate::error::number(angular_radius.to_degrees()),
                narrowest.to_degrees(),
                widest.to_degrees()
            ),
        ));
    }
    Ok(coherence_um)
}

/// The window for one patch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoherenceWindow {
    /// The coherence length it models, µm (σ_s = coherence/4).
    pub coherence_um: f64,
    /// CoherenceWindow width in bins along x and y.
    pub sigma_x: f64,
    pub sigma_y: f64,
    /// Taps either side of the nearest bin.
    pub radius_x: i64,
    pub radius_y: i64,
}

/// Where a query lands in the patch's spectrum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lookup {
    /// Fractional bin position relative to DC.
    pub sx: f64,
    pub sy: f64,
}

impl Lookup {
    /// s = (u·Lx/λ, v·Ly/λ) for lengths in µm and λ in µm.
    pub fn new(u: f64, v: f64, lambda_um: f64, lx_um: f64, ly_um: f64) -> Self {
        Self { sx: u * lx_um / lambda_um, sy: v * ly_um / lambda_um }
    }

    /// Whether the frequency lies inside the band the height field samples (|f| ≤ 1/(2·pixel)).
    pub fn in_band(&self, nx: usize, ny: usize) -> bool {
        self.sx.abs() <= nx as f64 / 2.0 && self.sy.abs() <= ny as f64 / 2.0
    }
}

impl CoherenceWindow {
    /// The window of a patch `lx_um`×`ly_um` for a coherence length in µm; `radius` taps either side of the
    /// nearest bin, or `None` for the full window (every tap heavier than [`FULL_WINDOW_CUTOFF`]).
    pub fn new(lx_um: f64, ly_um: f64, coherence_um: f64, radius: Option<u32>) -> Result<Self> {
        if !(MIN_COHERENCE_UM..=MAX_COHERENCE_UM).contains(&coherence_um) {
            return Err(Error::setting(
                "coherence_um",
                format!(
                    "the coherence length must lie between {MIN_COHERENCE_UM} and {MAX_COHERENCE_UM:e} µm, got {} µm",
                    crate::error::number(coherence_um)
                ),
            ));
        }
        let sigma_s = coherence_um / 4.0;
        let sigma_x = lx_um / (2.0 * std::f64::consts::PI * sigma_s);
        let sigma_y = ly_um / (2.0 * std::f64::consts::PI * sigma_s);
        let full = |sigma: f64| ((-2.0 * FULL_WINDOW_CUTOFF.ln()).sqrt() * sigma).ceil().clamp(1.0, 1e9) as i64;
        let (radius_x, radius_y) = match radius {
            Some(r) => (i64::from(r), i64::from(r)),
            None => (full(sigma_x), full(sigma_y)),
        };
        Ok(Self { coherence_um, sigma_x, sigma_y, radius_x, radius_y })
    }

    /// Taps along one axis for a patch of `n` bins: (array index in the centred spectrum, weight). Only bins
    /// the patch has are visited, so a window wider than the spectrum costs what the spectrum has, no more.
    pub fn axis_taps(s: f64, sigma: f64, radius: i64, n: usize) -> impl Iterator<Item = (usize, f64)> {
        let half = (n / 2) as i64;
        let (lo, hi) = (-half, n as i64 - 1 - half);
        // floor(s + 0.5), as the shaders round (GLSL's round() may go either way at .5); `as` saturates.
        let nearest = (s + 0.5).floor() as i64;
        let first = nearest.saturating_sub(radius).max(lo);
        let last = nearest.saturating_add(radius).min(hi);
        (first..=last).map(move |j| {
            let d = (j as f64 - s) / sigma;
            ((j + half) as usize, (-0.5 * d * d).exp())
        })
    }

    /// All taps of a lookup: (column, row, weight) in the centred spectrum of an `nx`×`ny` patch.
    pub fn taps(&self, at: Lookup, nx: usize, ny: usize) -> Vec<(usize, usize, f64)> {
        let xs: Vec<_> = Self::axis_taps(at.sx, self.sigma_x, self.radius_x, nx).collect();
        let mut out = Vec::with_capacity(xs.len() * (2 * self.radius_y as usize + 1).min(ny));
        for (iy, wy) in Self::axis_taps(at.sy, self.sigma_y, self.radius_y, ny) {
            for &(ix, wx) in &xs {
                out.push((ix, iy, wx * wy));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bin_centre_weights_its_bin_by_one() {
        let w = CoherenceWindow::new(65.0, 65.0, 65.0, Some(1)).unwrap();
        // σ = L/(2π·L/4) = 2/π bins when the patch is as wide as the coherence length (model.md §1.4: 0.6366).
        assert!((w.sigma_x - std::f64::consts::FRAC_2_PI).abs() < 1e-15);
        let taps = w.taps(Lookup { sx: 3.0, sy: -2.0 }, 16, 16);
        assert_eq!(taps.len(), 9);
        let centre = taps.iter().find(|t| t.0 == 8 + 3 && t.1 == 8 - 2).unwrap();
        assert_eq!(centre.2, 1.0);
        let edge = taps.iter().find(|t| t.0 == 8 + 4 && t.1 == 8 - 2).unwrap();
        assert!((edge.2 - 0.291).abs() < 1e-3, "model.md §1.4 edge weight");
    }

    #[test]
    fn taps_beyond_nyquist_are_dropped() {
        let w = CoherenceWindow::new(6.5, 6.5, 65.0, Some(2)).unwrap();
        // n = 8: bins −4..3. A lookup at 3.4 keeps bins 1..3 only.
        let xs: Vec<_> = CoherenceWindow::axis_taps(3.4, w.sigma_x, 2, 8).map(|t| t.0).collect();
        assert_eq!(xs, vec![5, 6, 7]);
    }

    /// The degree of coherence of a uniform disc of angular radius `alpha` (rad) between points `d` µm apart at
    /// `lambda` µm, integrated over the disc (polar quadrature), not from the closed form 2J₁(v)/v.
    fn disc_coherence(alpha: f64, d: f64, lambda: f64) -> f64 {
        let (nr, nphi) = (400, 400);
        let k = std::f64::consts::TAU / lambda;
        let mut sum = 0.0;
        for i in 0..nr {
            let r = alpha * (i as f64 + 0.5) / nr as f64;
            for j in 0..nphi {
                let phi = std::f64::consts::TAU * (j as f64 + 0.5) / nphi as f64;
                sum += (k * r * phi.cos() * d).cos() * r;
            }
        }
        sum * (alpha / nr as f64) * (std::f64::consts::TAU / nphi as f64) / (std::f64::consts::PI * alpha * alpha)
    }

    #[test]
    fn a_lights_coherence_follows_van_cittert_zernike() {
        let sun = crate::physics::sky::sun_angular_radius();
        let lambda = 0.55;
        // The disc's coherence first vanishes at v = kαd = 3.8317 (d = 0.61 λ/α), as 2J₁(v)/v does.
        let first_zero = 3.8317 * lambda / (std::f64::consts::TAU * sun);
        assert!(disc_coherence(sun, first_zero, lambda).abs() < 2e-3, "{}", disc_coherence(sun, first_zero, lambda));
        assert!(
            disc_coherence(sun, 0.9 * first_zero, lambda) > 0.02
                && disc_coherence(sun, 1.1 * first_zero, lambda) < -0.02
        );
        // Near d = 0 it is 1 − v²/8, which the window's exp(−d²/4σ_s²) matches when σ_s = λ/(√2·π·α).
        let sigma_s = lambda / (std::f64::consts::SQRT_2 * std::f64::consts::PI * sun);
        let d = 0.02 * lambda / sun;
        let ratio = (1.0 - disc_coherence(sun, d, lambda)) / (1.0 - (-d * d / (4.0 * sigma_s * sigma_s)).exp());
        assert!((ratio - 1.0).abs() < 2e-3, "curvature ratio {ratio}");
        // Mandel & Wolf's √(coherence area) λ/(√π α) for the sun at 550 nm is the thesis's 65 µm within 3 %; the
        // moment-matched 4σ_s is 4/√(2π) = 1.596 times it (model.md §1.13).
        let mandel_wolf = lambda / (std::f64::consts::PI.sqrt() * sun);
        eprintln!(
            "sun α = {:.4}°: √A_c = {mandel_wolf:.2} µm, 4σ_s matched = {:.1} µm",
            sun.to_degrees(),
            4.0 * sigma_s
        );
        assert!((mandel_wolf / DEFAULT_COHERENCE_UM - 1.0).abs() < 0.03, "{mandel_wolf}");
        assert!((4.0 * sigma_s / mandel_wolf - 4.0 / std::f64::consts::TAU.sqrt()).abs() < 1e-12);
        // The default is the sun's, and a light's length scales as 1/α.
        assert!((of_light(sun).unwrap() - DEFAULT_COHERENCE_UM).abs() < 1e-12);
        assert!((of_light(4.0 * sun).unwrap() - DEFAULT_COHERENCE_UM / 4.0).abs() < 1e-12);
        for bad in [0.0, -0.01, f64::NAN, f64::INFINITY, 20f64.to_radians(), 1e-9] {
            let e = of_light(bad).unwrap_err().to_string();
            assert!(e.contains("angular radius") && e.contains("µm"), "{bad}: {e}");
        }
    }

    #[test]
    fn the_windows_lobe_is_as_wide_as_a_disc_source_makes_it_when_matched() {
        // One grating order (a single bin) under the window: |P|² along s, in direction cosines u = s·λ/Lx; its
        // per-axis variance against the disc's (α²/4: a uniform disc's variance along one axis).
        let (lambda, lx) = (0.55, 50.0);
        for alpha_deg in [0.2666, 1.0, 3.0] {
            let alpha = f64::to_radians(alpha_deg);
            let matched = 2.0 * std::f64::consts::SQRT_2 * lambda / (std::f64::consts::PI * alpha);
            let w = CoherenceWindow::new(lx, lx, matched, None).unwrap();
            let (mut m0, mut m2) = (0.0, 0.0);
            for i in -20000..=20000 {
                let s = i as f64 * 1e-3;
                let p2: f64 = CoherenceWindow::axis_taps(s, w.sigma_x, w.radius_x, 4096)
                    .filter(|t| t.0 == 2048)
                    .map(|t| t.1 * t.1)
                    .sum();
                let u = s * lambda / lx;
                m0 += p2;
                m2 += p2 * u * u;
            }
            let (window, disc) = ((m2 / m0).sqrt(), alpha / 2.0);
            assert!((window / disc - 1.0).abs() < 1e-3, "{alpha_deg}°: window σ_u {window} vs disc {disc}");
        }
    }

    #[test]
    fn full_window_reaches_the_cutoff() {
        let w = CoherenceWindow::new(65.0, 65.0, 65.0, None).unwrap();
        let r = w.radius_x as f64 + 0.5;
        assert!((-0.5 * (r / w.sigma_x).powi(2)).exp() < FULL_WINDOW_CUTOFF);
    }
}
