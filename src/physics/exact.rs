//! The exact CPU reference of the diffraction BRDF (model.md §1.2–§1.7), in f64: what every test reads the shaders
//! against (the profiler's reference image, built from it, is `reference::exact_image`). `power` is |P(u/λ, v/λ)|²
//! with P the coherence-windowed DTFT of p = exp(i·k·w·h) ([`crate::physics::coherence`]), 1 at specular for a flat
//! patch; `reflectance` = C·power ([`crate::physics::optics::gain_factor`]); `brdf_sr` the BRDF in sr⁻¹.
//!
//! Two methods share the lookup and the window: [`Method::Exact`] evaluates the DFT coefficients of p itself at the
//! window's bins by a separable direct sum (no Taylor series, no FFT: an independent check on the precomputation);
//! [`Method::Taylor`] sums the precomputed terms, c_n = (k w)ⁿ/n! built incrementally, exactly as the shaders do
//! (but in f64).

use glam::DVec3;
use rustfft::num_complex::Complex64;

use crate::error::{Error, Result};
use crate::physics::coherence::{CoherenceWindow, Lookup};
use crate::physics::heightfield::HeightField;
use crate::physics::optics;
use crate::physics::taylor::{HeightStats, TaylorPlan, TaylorTerms};

/// How P is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    Exact,
    Taylor,
    /// The Taylor sum with f32 terms and f32 arithmetic, in the shaders' order: what a GPU computes.
    TaylorF32,
}

/// One evaluation: a wavelength and a pair of directions (angles in degrees).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Query {
    pub lambda_nm: f64,
    pub theta_i: f64,
    pub phi_i: f64,
    pub theta_r: f64,
    pub phi_r: f64,
}

impl Query {
    pub fn omega_i(&self) -> DVec3 {
        optics::direction(self.theta_i, self.phi_i)
    }

    pub fn omega_r(&self) -> DVec3 {
        optics::direction(self.theta_r, self.phi_r)
    }

    pub fn uvw(&self) -> DVec3 {
        optics::uvw(self.omega_i(), self.omega_r())
    }

    /// Refuses directions below the horizon and wavelengths outside 100 nm–10 µm.
    pub fn check(&self) -> Result<()> {
        optics::check_theta("light", self.theta_i)?;
        optics::check_theta("view", self.theta_r)?;
        if !(self.phi_i.is_finite() && self.phi_r.is_finite()) {
            return Err(Error::setting("phi", "azimuths must be finite".into()));
        }
        if !(self.lambda_nm.is_finite() && (100.0..=10_000.0).contains(&self.lambda_nm)) {
            return Err(Error::setting(
                "lambda_nm",
                format!("λ = {} nm is outside 100 nm–10 µm", crate::error::number(self.lambda_nm)),
            ));
        }
        Ok(())
    }
}

/// The result of one query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub query: Query,
    pub uvw: DVec3,
    pub power: f64,
    pub reflectance: f64,
    /// Stam's BRDF in physical units, sr⁻¹: `reflectance` times [`optics::brdf_per_sr_scale`] (energy-conserving
    /// in the coherence length; what a frame lit by an environment needs).
    pub brdf_sr: f64,
    /// False where (u/λ, v/λ) lies beyond the frequencies the height field samples: P is 0 there.
    pub in_band: bool,
}

/// A patch prepared for evaluation.
pub struct Reference {
    nx: usize,
    ny: usize,
    lx_um: f64,
    ly_um: f64,
    heights: Vec<f64>,
    window: CoherenceWindow,
    terms: Option<TaylorTerms>,
    plan: Option<TaylorPlan>,
    f32_arithmetic: bool,
}

impl Reference {
    /// Prepares `hf` for `method`. For Taylor, N comes from `plan` (see [`Reference::plan_for`]).
    pub fn new(hf: &HeightField, window: CoherenceWindow, method: Method, plan: Option<TaylorPlan>) -> Result<Self> {
        let (lx_um, ly_um) = hf.size_um();
        let (terms, plan) = match method {
            Method::Exact => (None, None),
            Method::Taylor | Method::TaylorF32 => {
                let plan = plan.ok_or_else(|| Error::Invalid("the Taylor method needs a plan".into()))?;
                (Some(TaylorTerms::compute(hf, plan.order, None)?), Some(plan))
            }
        };
        let f32_arithmetic = method == Method::TaylorF32;
        Ok(Self { nx: hf.nx, ny: hf.ny, lx_um, ly_um, heights: hf.centred(), window, terms, plan, f32_arithmetic })
    }

    /// The Taylor plan for a set of queries: N from the shortest wavelength and largest |w| among them.
    pub fn plan_for(
        hf: &HeightField,
        window: &CoherenceWindow,
        queries: &[Query],
        tolerance: f64,
        order: Option<usize>,
    ) -> Result<TaylorPlan> {
        let lambda_min = queries.iter().map(|q| q.lambda_nm).fold(f64::INFINITY, f64::min);
        let w_max = queries.iter().map(|q| q.uvw().z.abs()).fold(0.0, f64::max);
        if queries.is_empty() {
            return Err(Error::setting("queries", "no wavelengths or views to evaluate".into()));
        }
        TaylorPlan::new(lambda_min * 1e-3, w_max, &HeightStats::of(hf), window_gain(window, hf), tolerance, order)
    }

    pub fn plan(&self) -> Option<&TaylorPlan> {
        self.plan.as_ref()
    }

    /// P for wavenumber·w = `kw` (µm⁻¹) at `at`.
    pub fn amplitude(&self, at: Lookup, kw: f64) -> Complex64 {
        self.amplitude_in(&self.window, at, kw)
    }

    /// [`Self::amplitude`] under `window` instead of the reference's own.
    fn amplitude_in(&self, window: &CoherenceWindow, at: Lookup, kw: f64) -> Complex64 {
        let taps = window.taps(at, self.nx, self.ny);
        match &self.terms {
            Some(terms) if self.f32_arithmetic => taylor_sum_f32(terms, &taps, kw),
            Some(terms) => taylor_sum(terms, &taps, kw),
            None => self.exact_sum(&taps, kw),
        }
    }

    fn exact_sum(&self, taps: &[(usize, usize, f64)], kw: f64) -> Complex64 {
        self.exact_coefficients(taps, kw).iter().zip(taps).map(|(c, t)| c * t.2).sum()
    }

    /// The DFT coefficients of exp(i·k·w·h) (times 1/(nx·ny)) at the bins of `taps` (their weights unused).
    fn exact_coefficients(&self, taps: &[(usize, usize, f64)], kw: f64) -> Vec<Complex64> {
        if taps.is_empty() {
            return Vec::new();
        }
        let (nx, ny) = (self.nx, self.ny);
        let mut cols: Vec<usize> = taps.iter().map(|t| t.0).collect();
        cols.sort_unstable();
        cols.dedup();
        let (hx, hy) = (nx / 2, ny / 2);
        let twiddle = |n: usize| -> Vec<Complex64> {
            (0..n).map(|m| Complex64::from_polar(1.0, 2.0 * std::f64::consts::PI * m as f64 / n as f64)).collect()
        };
        let (tx, ty) = (twiddle(nx), twiddle(ny));
        // Bin j (centred index i = j + ⌊N/2⌋) at sample x has phase e^{+2πi j x / N}: index (j·x) mod N.
        let bin = |i: usize, half: usize, n: usize| (i as i64 - half as i64).rem_euclid(n as i64) as usize;
        // rows[r][c] = Σ_x p[r][x] e^{+2πi jx x/Nx} for each needed column bin.
        let mut rows = vec![Complex64::default(); ny * cols.len()];
        for r in 0..ny {
            let line = &self.heights[r * nx..][..nx];
            let p: Vec<Complex64> = line.iter().map(|&h| Complex64::from_polar(1.0, kw * h)).collect();
            for (ci, &c) in cols.iter().enumerate() {
                let j = bin(c, hx, nx);
                rows[r * cols.len() + ci] = p.iter().enumerate().map(|(x, v)| v * tx[(j * x) % nx]).sum();
            }
        }
        let norm = 1.0 / (nx * ny) as f64;
        taps.iter()
            .map(|&(c, r, _)| {
                let ci = cols.binary_search(&c).expect("column collected above");
                let j = bin(r, hy, ny);
                let coef: Complex64 = (0..ny).map(|y| rows[y * cols.len() + ci] * ty[(j * y) % ny]).sum();
                coef * norm
            })
            .collect()
    }

    /// The spectrum's coefficients (no window) at the bins of `taps`: the Taylor sum Σ_n c_n F_n, or the exact DFT.
    fn coefficients(&self, taps: &[(usize, usize, f64)], kw: f64) -> Vec<Complex64> {
        match &self.terms {
            Some(terms) => taps.iter().map(|&(x, y, _)| taylor_sum(terms, &[(x, y, 1.0)], kw)).collect(),
            None => self.exact_coefficients(taps, kw),
        }
    }

    /// |P|² at `at` blurred by a Gaussian of standard deviation `blur` (x, y) bins, in closed form: with the
    /// window's Gaussians g_j of σ bins, ∫ |Σ_j F_j g_j|² ⊛ h = Σ_j Σ_k F_j F_k* · e^(−|j−k|²/4σ²) · p ·
    /// e^(−|s − (j+k)/2|²/2(σ²/2 + σ_h²)) per axis, p = √((σ²/2)/(σ²/2 + σ_h²)): the coherent intensity of the
    /// material's window, spread as an incoherent source of the blur's width spreads it.
    fn blurred_intensity(&self, at: Lookup, kw: f64, blur: (f64, f64)) -> f64 {
        let (sigma_x, sigma_y) = (self.window.sigma_x, self.window.sigma_y);
        // Per axis: the bins whose pairs count, and the pairs' weights.
        let axis = |s: f64, sigma: f64, blur: f64, n: usize| -> (Vec<usize>, Vec<(usize, usize, f64)>) {
            let spread = (0.5 * sigma * sigma + blur * blur).sqrt();
            let reach = ((-2.0 * crate::physics::coherence::FULL_WINDOW_CUTOFF.ln()).sqrt() * (spread + sigma))
                .ceil()
                .min(n as f64) as i64;
            let bins: Vec<(usize, f64)> = CoherenceWindow::axis_taps(s, 1.0, reach, n)
                .map(|t| t.0)
                .map(|i| (i, i as f64 - (n / 2) as f64))
                .collect();
            let p = (0.5 * sigma * sigma).sqrt() / spread;
            let mut pairs = Vec::new();
            for (a, &(_, j)) in bins.iter().enumerate() {
                for (b, &(_, k)) in bins.iter().enumerate() {
                    let apart = (-(j - k) * (j - k) / (4.0 * sigma * sigma)).exp();
                    let off = s - 0.5 * (j + k);
                    let weight = apart * p * (-off * off / (2.0 * spread * spread)).exp();
                    if weight > crate::physics::coherence::FULL_WINDOW_CUTOFF {
                        pairs.push((a, b, weight));
                    }
                }
            }
            (bins.iter().map(|b| b.0).collect(), pairs)
        };
        let (xs, px) = axis(at.sx, sigma_x, blur.0, self.nx);
        let (ys, py) = axis(at.sy, sigma_y, blur.1, self.ny);
        let taps: Vec<(usize, usize, f64)> = ys.iter().flat_map(|&y| xs.iter().map(move |&x| (x, y, 1.0))).collect();
        let f = self.coefficients(&taps, kw);
        let at = |a: usize, b: usize| f[b * xs.len() + a];
        let mut sum = 0.0;
        for &(ya, yb, wy) in &py {
            for &(xa, xb, wx) in &px {
                sum += (at(xa, ya) * at(xb, yb).conj()).re * wx * wy;
            }
        }
        sum
    }

    /// Evaluates every query (in parallel), in order.
    pub fn evaluate(&self, queries: &[Query]) -> Result<Vec<Sample>> {
        for q in queries {
            q.check()?;
        }
        use rayon::prelude::*;
        Ok(queries.par_iter().map(|q| self.sample(q)).collect())
    }

    /// The colour of one pair of directions by full wavelength sampling (the CPU twin of `diffraction_xyz` in
    /// glsl/include/approaches.glsl for FLSS): XYZ relative to a D65 mirror, times C and the V-groove shadowing.
    pub fn flss_xyz(&self, omega_i: DVec3, omega_r: DVec3, sampling: &crate::physics::spectrum::Sampling) -> DVec3 {
        self.flss_xyz_in(&self.window, omega_i, omega_r, sampling)
    }

    fn flss_xyz_in(
        &self,
        window: &CoherenceWindow,
        omega_i: DVec3,
        omega_r: DVec3,
        sampling: &crate::physics::spectrum::Sampling,
    ) -> DVec3 {
        if omega_i.z <= 0.0 || omega_r.z <= 0.0 {
            return DVec3::ZERO;
        }
        let uvw = optics::uvw(omega_i, omega_r);
        crate::physics::spectrum::reflectance_to_xyz(sampling, |lambda_nm| self.intensity_in(window, uvw, lambda_nm))
            * optics::gain_factor(omega_i, omega_r)
            * optics::shadow_mask(omega_i, omega_r)
    }

    /// [`Self::flss_xyz`] with every lobe widened by a Gaussian of `variance` in (u, v), as a lamp's shorter
    /// coherence widens the baked read (`light::lamp::widening_variance`, model.md §3.13): the intensity of the
    /// material's window blurred (in closed form: `blurred_intensity`) by that Gaussian in (u, v) at every
    /// wavelength — the spread an incoherent source of the lamp's width gives, which keeps each lobe's energy.
    pub fn flss_xyz_widened(
        &self,
        omega_i: DVec3,
        omega_r: DVec3,
        sampling: &crate::physics::spectrum::Sampling,
        variance: f64,
    ) -> DVec3 {
        if omega_i.z <= 0.0 || omega_r.z <= 0.0 {
            return DVec3::ZERO;
        }
        let uvw = optics::uvw(omega_i, omega_r);
        let intensity = |lambda_nm: f64| {
            let lambda_um = lambda_nm * 1e-3;
            let at = Lookup::new(uvw.x, uvw.y, lambda_um, self.lx_um, self.ly_um);
            if !at.in_band(self.nx, self.ny) {
                return 0.0;
            }
            // The blur in bins: (u, v) → frequency u/λ → bins u·L/λ.
            let blur = variance.sqrt() / lambda_um;
            let kw = 2.0 * std::f64::consts::PI / lambda_um * uvw.z;
            self.blurred_intensity(at, kw, (blur * self.lx_um, blur * self.ly_um))
        };
        crate::physics::spectrum::reflectance_to_xyz(sampling, intensity)
            * optics::gain_factor(omega_i, omega_r)
            * optics::shadow_mask(omega_i, omega_r)
    }

    /// [`Self::flss_xyz`] under each of `samplings` (one wavelength grid, several lights), the spectrum computed
    /// once.
    pub fn flss_xyz_bands<const N: usize>(
        &self,
        omega_i: DVec3,
        omega_r: DVec3,
        samplings: &[crate::physics::spectrum::Sampling; N],
    ) -> [DVec3; N] {
        if omega_i.z <= 0.0 || omega_r.z <= 0.0 || N == 0 {
            return [DVec3::ZERO; N];
        }
        let uvw = optics::uvw(omega_i, omega_r);
        let first = &samplings[0];
        let spectrum: Vec<f64> = first.wavelengths().map(|l| self.intensity(uvw, l)).collect();
        let factor = optics::gain_factor(omega_i, omega_r) * optics::shadow_mask(omega_i, omega_r);
        std::array::from_fn(|k| {
            let sampling = &samplings[k];
            debug_assert!(sampling.step_nm == first.step_nm && sampling.count == first.count);
            let at = |l: f64| spectrum[((l - first.lambda_min_nm) / first.step_nm).round() as usize];
            crate::physics::spectrum::reflectance_to_xyz(sampling, at) * factor
        })
    }

    /// |P(u/λ, v/λ; k·w)|² at one wavelength (nm), 0 outside the band the patch resolves.
    fn intensity(&self, uvw: DVec3, lambda_nm: f64) -> f64 {
        self.intensity_in(&self.window, uvw, lambda_nm)
    }

    fn intensity_in(&self, window: &CoherenceWindow, uvw: DVec3, lambda_nm: f64) -> f64 {
        let lambda_um = lambda_nm * 1e-3;
        let at = Lookup::new(uvw.x, uvw.y, lambda_um, self.lx_um, self.ly_um);
        if !at.in_band(self.nx, self.ny) {
            return 0.0;
        }
        self.amplitude_in(window, at, 2.0 * std::f64::consts::PI / lambda_um * uvw.z).norm_sqr()
    }

    /// Σ_λ |P(u/λ, v/λ; k·w)|² weighted into XYZ relative to a D65 mirror, before the gain and the shadowing:
    /// the quantity the baked table stores (`BakedTable::xyz`), at any (u, v, w).
    pub fn spectral_xyz(&self, uvw: DVec3, sampling: &crate::physics::spectrum::Sampling) -> DVec3 {
        crate::physics::spectrum::reflectance_to_xyz(sampling, |lambda_nm| self.intensity(uvw, lambda_nm))
    }

    fn sample(&self, q: &Query) -> Sample {
        let uvw = q.uvw();
        let lambda_um = q.lambda_nm * 1e-3;
        let at = Lookup::new(uvw.x, uvw.y, lambda_um, self.lx_um, self.ly_um);
        let in_band = at.in_band(self.nx, self.ny);
        let k = 2.0 * std::f64::consts::PI / lambda_um;
        let power = if in_band { self.amplitude(at, k * uvw.z).norm_sqr() } else { 0.0 };
        let reflectance = optics::gain_factor(q.omega_i(), q.omega_r()) * power;
        Sample::new(*q, power, reflectance, in_band, &self.window)
    }
}

impl Sample {
    /// A sample of `query` whose power and relative reflectance are known, with its BRDF in sr⁻¹ under `window`.
    pub fn new(query: Query, power: f64, reflectance: f64, in_band: bool, window: &CoherenceWindow) -> Self {
        let scale = optics::brdf_per_sr_scale(query.lambda_nm * 1e-3, window.coherence_um, query.omega_i().z);
        Self { query, uvw: query.uvw(), power, reflectance, brdf_sr: reflectance * scale, in_band }
    }
}

/// Σ_taps g · Σ_n c_n F_n[tap], with c_0 = 1 and c_n = c_{n−1}·kw/n.
fn taylor_sum(terms: &TaylorTerms, taps: &[(usize, usize, f64)], kw: f64) -> Complex64 {
    let nx = terms.nx;
    let mut p = Complex64::default();
    let mut c = 1.0;
    for (n, layer) in terms.layers.iter().enumerate() {
        if n > 0 {
            c *= kw / n as f64;
        }
        let windowed: Complex64 = taps.iter().map(|&(x, y, g)| layer[y * nx + x] * g).sum();
        p += windowed * c;
    }
    p
}

/// The same sum as the GPU does it (`taylor_sum` in glsl/include/taylor.glsl): f32 texels, weights and
/// coefficients c_n computed incrementally in f32 first, then per tap Σ_n c_n F_n, weighted and accumulated.
fn taylor_sum_f32(terms: &TaylorTerms, taps: &[(usize, usize, f64)], kw: f64) -> Complex64 {
    let nx = terms.nx;
    let kw = kw as f32;
    let mut c = vec![1.0f32; terms.layers.len()];
    for n in 1..c.len() {
        c[n] = c[n - 1] * kw / n as f32;
    }
    let (mut re, mut im) = (0.0f32, 0.0f32);
    for &(x, y, g) in taps {
        let (mut ar, mut ai) = (0.0f32, 0.0f32);
        for (layer, cn) in terms.layers.iter().zip(&c) {
            let t = layer[y * nx + x];
            ar += cn * t.re as f32;
            ai += cn * t.im as f32;
        }
        re += g as f32 * ar;
        im += g as f32 * ai;
    }
    Complex64::new(f64::from(re), f64::from(im))
}

/// The largest sum of window weights over lookup positions (it scales the truncation and rounding bounds).
pub fn window_gain(window: &CoherenceWindow, hf: &HeightField) -> f64 {
    let axis = |sigma: f64, radius: i64, n: usize| {
        [0.0, 0.25, 0.5]
            .iter()
            .map(|&s| CoherenceWindow::axis_taps(s, sigma, radius, n).map(|t| t.1).sum::<f64>())
            .fold(0.0, f64::max)
    };
    axis(window.sigma_x, window.radius_x, hf.nx) * axis(window.sigma_y, window.radius_y, hf.ny)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small random height field (seeded), wide enough that its spectrum's bins overlap under the window.
    fn patch() -> HeightField {
        let mut rng = fastrand::Rng::with_seed(3);
        let (nx, ny) = (24, 16);
        HeightField::new(nx, ny, 0.1, 0.1, (0..nx * ny).map(|_| 0.1 * rng.f64()).collect()).unwrap()
    }

    #[test]
    fn the_blurred_intensity_is_the_windows_intensity_spread_by_the_gaussian() {
        let hf = patch();
        let (lx, ly) = hf.size_um();
        // σ of about a bin, so neighbouring bins interfere: their cross terms must survive the blur.
        let window = CoherenceWindow::new(lx, ly, 2.5, None).unwrap();
        let reference = Reference::new(&hf, window, Method::Exact, None).unwrap();
        let kw = 9.0;
        for (sx, sy) in [(0.0, 0.0), (1.3, -0.4), (-2.7, 3.1)] {
            let at = Lookup { sx, sy };
            let sharp = reference.amplitude(at, kw).norm_sqr();
            let unblurred = reference.blurred_intensity(at, kw, (0.0, 0.0));
            assert!((unblurred - sharp).abs() <= 1e-12 * sharp.max(1e-12), "({sx}, {sy}): {unblurred} vs {sharp}");
            // Against the blur done by quadrature: |P|² over a fine grid of offsets, weighted by the Gaussian.
            let (bx, by) = (0.7, 0.4);
            let (mut sum, mut weights) = (0.0, 0.0);
            for i in -100..=100 {
                for j in -100..=100 {
                    let (dx, dy) = (f64::from(i) * 0.06 * bx, f64::from(j) * 0.06 * by);
                    let w = (-0.5 * ((dx / bx).powi(2) + (dy / by).powi(2))).exp();
                    sum += w * reference.amplitude(Lookup { sx: sx + dx, sy: sy + dy }, kw).norm_sqr();
                    weights += w;
                }
            }
            let blurred = reference.blurred_intensity(at, kw, (bx, by));
            let quadrature = sum / weights;
            assert!((blurred / quadrature - 1.0).abs() < 1e-5, "({sx}, {sy}): {blurred} vs {quadrature}");
        }
    }
}
