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

    #[test]
    fn full_window_reaches_the_cutoff() {
        let w = CoherenceWindow::new(65.0, 65.0, 65.0, None).unwrap();
        let r = w.radius_x as f64 + 0.5;
        assert!((-0.5 * (r / w.sigma_x).powi(2)).exp() < FULL_WINDOW_CUTOFF);
    }
}
