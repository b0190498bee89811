//! The Taylor expansion of p = exp(i·k·w·h) and its precomputed Fourier terms (model.md §1.6, §2.1–§2.3):
//! P = Σ_n (k·w)ⁿ/n!·F_n, F_n the centred, normalised DFT of (i·h)ⁿ over the mean-centred heights (µm), in f64,
//! two real powers per complex FFT, the terms spread over the machine's cores. Its plan chooses the order N from
//! the series' tail bound (§2.2) and says where f32 cannot reach the tolerance (§2.3).

use std::sync::Arc;

use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

use crate::error::{Error, Result};
use crate::physics::heightfield::HeightField;

/// Default tolerance on the amplitude |P − P_N|, relative to the amplitude of a flat mirror at specular (1).
/// 1e-4 keeps the power of an order as weak as 10⁻⁴ of the specular peak within about 2 %, and f32 sums reach
/// it for the measured snake patches (x_max ≈ 6).
pub const DEFAULT_TOLERANCE: f64 = 1e-4;
/// The highest order diffract will expand to (x_max near 100 would need it; such a patch is mis-scaled).
pub const MAX_ORDER: usize = 200;
/// Memory the f64 terms may take (N+1 layers of Nx·Ny complex f64 values).
pub const MAX_TERMS_BYTES: u64 = 8 << 30;
/// The unit roundoff of f32.
pub const F32_UNIT_ROUNDOFF: f64 = 5.960_464_477_539_063e-8;
/// The unit roundoff of f64.
pub const F64_UNIT_ROUNDOFF: f64 = 1.110_223_024_625_156_5e-16;

/// The bound on |Σ_{n>N} (i·x)^n/n!| for |x| ≤ `x`.
pub(crate) fn truncation_tail(x: f64, order: usize) -> f64 {
    let n1 = order as f64 + 1.0;
    if n1 + 1.0 <= x {
        return f64::INFINITY;
    }
    // x^{N+1}/(N+1)! in logs, to stay finite for large N.
    let log_term = n1 * x.ln() - ln_factorial(order + 1);
    log_term.exp() * (n1 + 1.0) / (n1 + 1.0 - x)
}

/// ln(n!) summed exactly (n is at most a few hundred).
fn ln_factorial(n: usize) -> f64 {
    (2..=n).map(|k| (k as f64).ln()).sum()
}

/// What the plan needs to know of a patch's heights.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightStats {
    /// max |h − mean|, µm.
    pub max_deviation_um: f64,
    /// m_n = mean(|h − mean|^n) in µm^n for n = 0..=MAX_ORDER.
    pub moments: Vec<f64>,
}

impl HeightStats {
    pub fn of(hf: &HeightField) -> Self {
        // Moments are means over the patch: a tiling's are its cell's.
        let hf = hf.tiling_cell();
        let h: Vec<f64> = hf.centred().iter().map(|x| x.abs()).collect();
        let mut powers = vec![1.0; h.len()];
        let mut moments = Vec::with_capacity(MAX_ORDER + 1);
        for _ in 0..=MAX_ORDER {
            moments.push(powers.iter().sum::<f64>() / h.len() as f64);
            for (p, x) in powers.iter_mut().zip(&h) {
                *p *= x;
            }
        }
        Self { max_deviation_um: hf.max_deviation(), moments }
    }

    /// The worst case for a given deviation: every height at ±`max_deviation_um`.
    pub fn worst_case(max_deviation_um: f64) -> Self {
        Self { max_deviation_um, moments: (0..=MAX_ORDER).map(|n| max_deviation_um.powi(n as i32)).collect() }
    }

    /// The largest bound on a term, max_n κ^n/n!·m_n, for n = 0..=order.
    pub fn largest_term(&self, kappa: f64, order: usize) -> f64 {
        (0..=order.min(MAX_ORDER))
            .map(|n| {
                let m = self.moments[n];
                if m <= 0.0 || kappa <= 0.0 {
                    return if n == 0 { 1.0 } else { 0.0 };
                }
                (n as f64 * kappa.ln() - ln_factorial(n) + m.ln()).exp()
            })
            .fold(0.0, f64::max)
    }
}

/// How many terms a scene needs and what f32 can deliver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TaylorPlan {
    /// k_max·|w|_max·max|h − mean|.
    pub x_max: f64,
    /// Highest order N (the sum runs over n = 0..=N).
    pub order: usize,
    /// Bound on the amplitude error from truncation (includes the window gain).
    pub truncation_bound: f64,
    /// Estimated amplitude error of the same sum in f32.
    pub f32_error: f64,
    /// The same estimate for f64 (the CPU's Taylor sums cancel too, far less: it matters for deep structures).
    pub f64_error: f64,
    pub tolerance: f64,
}

impl TaylorPlan {
    /// Plans the expansion for the shortest wavelength `lambda_min_um`, the largest |w| and the patch's heights;
    /// `window_gain` is the largest sum of window weights. `order` forces N.
    pub fn new(
        lambda_min_um: f64,
        w_max: f64,
        heights: &HeightStats,
        window_gain: f64,
        tolerance: f64,
        order: Option<usize>,
    ) -> Result<Self> {
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(Error::setting("tolerance", format!("the tolerance must be positive, got {tolerance}")));
        }
        let max_deviation_um = heights.max_deviation_um;
        let kappa = 2.0 * std::f64::consts::PI / lambda_min_um * w_max.abs();
        let x_max = kappa * max_deviation_um;
        let order = match order {
            Some(n) if n > MAX_ORDER => {
                return Err(Error::setting("terms", format!("--terms {n} is above the limit {MAX_ORDER}")))
            }
            Some(n) => n,
            None => {
                (0..=MAX_ORDER).find(|&n| window_gain * truncation_tail(x_max, n) <= tolerance).ok_or_else(|| {
                    Error::Precision(format!(
                        "no Taylor order up to {MAX_ORDER} reaches the tolerance {tolerance:e} for x_max = {x_max:.1} \
                     (heights of {max_deviation_um:.3} µm around the mean at λ = {:.0} nm): check --height-um",
                        lambda_min_um * 1e3
                    ))
                })?
            }
        };
        let truncation_bound = window_gain * truncation_tail(x_max, order);
        let rounding = ((order + 1) as f64).sqrt() * window_gain * heights.largest_term(kappa, order);
        let (f32_error, f64_error) = (2.0 * F32_UNIT_ROUNDOFF * rounding, 2.0 * F64_UNIT_ROUNDOFF * rounding);
        Ok(Self { x_max, order, truncation_bound, f32_error, f64_error, tolerance })
    }

    /// Whether an f32 sum (the GPU's) can reach the tolerance.
    pub fn f32_suffices(&self) -> bool {
        self.f32_error <= self.tolerance
    }

    /// Whether an f64 sum (the CPU's Taylor method) can reach the tolerance: deep structures make the terms
    /// grow to κ^n·m_n/n! before they cancel, and f64 loses what lies below its unit roundoff of the largest.
    pub fn f64_suffices(&self) -> bool {
        self.f64_error <= self.tolerance
    }

    /// A one-line account for users.
    pub fn describe(&self) -> String {
        format!(
            "Taylor order N = {} for x_max = {:.3}: truncation bound {:.2e}, f32 rounding about {:.2e}, f64 about \
             {:.0e} (tolerance {:.1e}{})",
            self.order,
            self.x_max,
            self.truncation_bound,
            self.f32_error,
            self.f64_error,
            self.tolerance,
            match (self.f32_suffices(), self.f64_suffices()) {
                (true, _) => "",
                (false, true) => "; NOT reachable in f32",
                (false, false) => "; NOT reachable in f32 nor in f64",
            }
        )
    }
}

/// The precomputed terms F_0..=F_N of one patch, in f64.
#[derive(Clone, Debug)]
pub struct TaylorTerms {
    pub nx: usize,
    pub ny: usize,
    pub dx_um: f64,
    pub dy_um: f64,
    /// (min, max) of the heights before centring, µm.
    pub height_range_um: (f64, f64),
    pub max_deviation_um: f64,
    /// `layers[n]` = F_n, centred, row-major (`[row * nx + col]`).
    pub layers: Vec<Vec<Complex64>>,
}

impl TaylorTerms {
    /// Precomputes F_0..=F_order. `progress(done, total)` is called as terms finish.
    pub fn compute(hf: &HeightField, order: usize, progress: Option<&(dyn Fn(usize, usize) + Sync)>) -> Result<Self> {
        let (nx, ny) = (hf.nx, hf.ny);
        let count = order + 1;
        let bytes = (count as u64) * (nx * ny) as u64 * 16;
        if bytes > MAX_TERMS_BYTES {
            return Err(Error::TooLarge(format!(
                "{count} Taylor terms of a {nx}×{ny} patch need {:.1} GiB; use fewer terms or a smaller patch",
                bytes as f64 / (1u64 << 30) as f64
            )));
        }
        let h = hf.centred();
        let mut planner = FftPlanner::<f64>::new();
        let (fx, fy) = (planner.plan_fft_inverse(nx), planner.plan_fft_inverse(ny));
        use rayon::prelude::*;
        let done = std::sync::atomic::AtomicUsize::new(0);
        // Two real powers per complex FFT: the pair (n, n + 1) from one transform, pairs shared out to every core.
        let pairs: Vec<(Vec<Complex64>, Vec<Complex64>)> = (0..count)
            .step_by(2)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|n| {
                let pair = term_pair(&h, nx, ny, n, &fx, &fy);
                let d = done.fetch_add(2, std::sync::atomic::Ordering::Relaxed) + 2;
                if let Some(p) = progress {
                    p(d.min(count), count);
                }
                pair
            })
            .collect();
        let mut layers: Vec<Vec<Complex64>> = pairs.into_iter().flat_map(|(a, b)| [a, b]).collect();
        layers.truncate(count);
        Ok(Self {
            nx,
            ny,
            dx_um: hf.dx_um,
            dy_um: hf.dy_um,
            height_range_um: hf.range(),
            max_deviation_um: hf.max_deviation(),
            layers,
        })
    }

    /// The highest order N.
    pub fn order(&self) -> usize {
        self.layers.len() - 1
    }

    /// All layers as interleaved (re, im) f32, layer after layer: the RG32F 2D-array texture the GPU samples.
    pub fn to_f32_texels(&self, order: usize) -> Vec<f32> {
        let mut out = Vec::with_capacity((order + 1) * self.nx * self.ny * 2);
        for layer in &self.layers[..=order.min(self.order())] {
            for c in layer {
                out.push(c.re as f32);
                out.push(c.im as f32);
            }
        }
        out
    }
}

/// F_n and F_{n+1} from one complex FFT of h^n + i·h^{n+1}.
fn term_pair(
    h: &[f64],
    nx: usize,
    ny: usize,
    n: usize,
    fx: &Arc<dyn Fft<f64>>,
    fy: &Arc<dyn Fft<f64>>,
) -> (Vec<Complex64>, Vec<Complex64>) {
    let mut z: Vec<Complex64> = h.iter().map(|&x| Complex64::new(x.powi(n as i32), x.powi(n as i32 + 1))).collect();
    ifft2(&mut z, nx, ny, fx, fy);
    // For real a, IDFT(a)[−k] = conj(IDFT(a)[k]): split Z = A + iB into A and B.
    let norm = 1.0 / (nx * ny) as f64;
    let (i_n, i_n1) = (i_pow(n), i_pow(n + 1));
    let (hx, hy) = (nx / 2, ny / 2);
    let mut a = vec![Complex64::default(); nx * ny];
    let mut b = vec![Complex64::default(); nx * ny];
    for ky in 0..ny {
        let my = (ny - ky) % ny;
        for kx in 0..nx {
            let mx = (nx - kx) % nx;
            let zk = z[ky * nx + kx];
            let zm = z[my * nx + mx].conj();
            let ak = (zk + zm) * 0.5;
            let bk = (zk - zm) * Complex64::new(0.0, -0.5);
            // fftshift: bin k (0..N, wrapping) goes to index (k + ⌊N/2⌋) mod N, so DC lands at ⌊N/2⌋.
            let idx = ((ky + hy) % ny) * nx + (kx + hx) % nx;
            a[idx] = ak * i_n * norm;
            b[idx] = bk * i_n1 * norm;
        }
    }
    (a, b)
}

fn i_pow(n: usize) -> Complex64 {
    match n % 4 {
        0 => Complex64::new(1.0, 0.0),
        1 => Complex64::new(0.0, 1.0),
        2 => Complex64::new(-1.0, 0.0),
        _ => Complex64::new(0.0, -1.0),
    }
}

/// In-place unnormalised inverse 2D DFT (+i exponent) of a row-major `nx`×`ny` array.
pub(crate) fn ifft2(data: &mut [Complex64], nx: usize, ny: usize, fx: &Arc<dyn Fft<f64>>, fy: &Arc<dyn Fft<f64>>) {
    fx.process(data);
    if ny > 1 {
        let mut t = vec![Complex64::default(); nx * ny];
        transpose(data, &mut t, nx, ny);
        fy.process(&mut t);
        transpose(&t, data, ny, nx);
    }
}

/// `dst` (cols×rows) = transpose of `src` (rows of `cols` values).
fn transpose(src: &[Complex64], dst: &mut [Complex64], cols: usize, rows: usize) {
    const BLOCK: usize = 32; // cache-friendly tiles
    for r0 in (0..rows).step_by(BLOCK) {
        for c0 in (0..cols).step_by(BLOCK) {
            for r in r0..(r0 + BLOCK).min(rows) {
                for c in c0..(c0 + BLOCK).min(cols) {
                    dst[c * rows + r] = src[r * cols + c];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// F_n by the definition, O(N⁴): the check on the FFT, the pair trick and the centring.
    fn naive_term(h: &[f64], nx: usize, ny: usize, n: usize) -> Vec<Complex64> {
        let mut out = vec![Complex64::default(); nx * ny];
        let (hx, hy) = ((nx / 2) as i64, (ny / 2) as i64);
        for iy in 0..ny {
            for ix in 0..nx {
                let (jx, jy) = (ix as i64 - hx, iy as i64 - hy);
                let mut s = Complex64::default();
                for y in 0..ny {
                    for x in 0..nx {
                        let phase = 2.0
                            * std::f64::consts::PI
                            * (jx as f64 * x as f64 / nx as f64 + jy as f64 * y as f64 / ny as f64);
                        s += Complex64::new(0.0, h[y * nx + x]).powu(n as u32) * Complex64::from_polar(1.0, phase);
                    }
                }
                out[iy * nx + ix] = s / (nx * ny) as f64;
            }
        }
        out
    }

    #[test]
    fn fft_terms_match_a_naive_dft() {
        for (nx, ny) in [(8, 6), (7, 5), (5, 1), (1, 4)] {
            let heights: Vec<f64> = (0..nx * ny).map(|i| ((i * 37 % 11) as f64) * 0.03).collect();
            let hf = HeightField::new(nx, ny, 0.1, 0.1, heights).unwrap();
            let terms = TaylorTerms::compute(&hf, 4, None).unwrap();
            let h = hf.centred();
            for n in 0..=4 {
                let naive = naive_term(&h, nx, ny, n);
                for (a, b) in terms.layers[n].iter().zip(&naive) {
                    assert!((a - b).norm() < 1e-13, "{nx}×{ny} n={n}: {a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn flat_patch_has_only_dc() {
        let hf = HeightField::new(4, 4, 0.1, 0.1, vec![0.3; 16]).unwrap();
        let t = TaylorTerms::compute(&hf, 3, None).unwrap();
        assert_eq!(t.layers[0][2 * 4 + 2], Complex64::new(1.0, 0.0));
        assert!(t.layers.iter().flatten().map(|c| c.norm()).sum::<f64>() - 1.0 < 1e-15);
    }

    #[test]
    fn thesis_error_bounds_are_reproduced_by_the_lagrange_form() {
        // model.md §1.6: x_max = 1.5π, e^x·x^{N+1}/(N+1)! = 8.815e-8 at N = 25. Our tail bound is tighter.
        let x = 1.5 * std::f64::consts::PI;
        let lagrange = x.exp() * (26.0 * x.ln() - ln_factorial(26)).exp();
        assert!((lagrange / 8.8150e-8 - 1.0).abs() < 1e-3, "{lagrange}");
        assert!(truncation_tail(x, 25) < lagrange);
    }

    #[test]
    fn the_plan_picks_the_smallest_sufficient_order() {
        let plan = TaylorPlan::new(0.38, 2.0, &HeightStats::worst_case(0.19), 2.5, 1e-5, None).unwrap();
        assert!(plan.truncation_bound <= 1e-5);
        assert!(2.5 * truncation_tail(plan.x_max, plan.order - 1) > 1e-5);
        let forced = TaylorPlan::new(0.38, 2.0, &HeightStats::worst_case(0.19), 2.5, 1e-5, Some(3)).unwrap();
        assert!(forced.truncation_bound > 1e-5);
        assert!(
            TaylorPlan::new(0.38, 2.0, &HeightStats::worst_case(20.0), 2.5, 1e-5, None).is_err(),
            "20 µm heights are refused"
        );
    }

    #[test]
    fn moments_bound_every_bin_of_every_term() {
        let heights: Vec<f64> = (0..48).map(|i| ((i * 29 % 13) as f64) * 0.04).collect();
        let hf = HeightField::new(8, 6, 0.1, 0.1, heights).unwrap();
        let stats = HeightStats::of(&hf);
        let terms = TaylorTerms::compute(&hf, 8, None).unwrap();
        for (n, layer) in terms.layers.iter().enumerate() {
            let largest = layer.iter().map(|c| c.norm()).fold(0.0, f64::max);
            assert!(largest <= stats.moments[n] * (1.0 + 1e-12), "n={n}: {largest} > {}", stats.moments[n]);
        }
        assert!(stats.moments[4] <= stats.max_deviation_um.powi(4));
    }

    #[test]
    fn large_arguments_are_flagged_as_beyond_f32() {
        let tall = TaylorPlan::new(0.38, 2.0, &HeightStats::worst_case(0.5), 2.5, 1e-5, None).unwrap();
        assert!(!tall.f32_suffices(), "{tall:?}");
        let low = TaylorPlan::new(0.38, 2.0, &HeightStats::worst_case(0.01), 2.5, 1e-5, None).unwrap();
        assert!(low.f32_suffices(), "{low:?}");
    }
}
