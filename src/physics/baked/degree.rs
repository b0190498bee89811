//! The degree in w of a baked table (model.md §3.5, "Its degree in w"): its Chebyshev coefficients fall like
//! Bessel functions J_d(Ω_λ·ρ) of the structure's height range, so
//! - **nodes** (`nodes_for`): enough Chebyshev nodes in w that what an interpolant on them cannot see stays below a
//!   quarter of [`INVISIBLE`] in every texel and channel;
//! - **the estimate** ([`estimate`]), before the build: the tail at every lobe centre in the table's (u, v) box (and
//!   the midpoints between lobes where they interfere), which sizes the table's memory;
//! - **the certificate** (`certify`), on the built table: per texel and channel the smallest degree within the
//!   tolerance × the texel's brightest value + [`INVISIBLE`]; where memory or [`MAX_TERMS`] keeps fewer, it says
//!   by how much the table misses.

use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::error::{Error, Result};
use crate::io::progress::Progress;
use crate::physics::baked::lobes::{lattice_taps, Cell, Spectral};
use crate::physics::baked::{
    Grid, TablePlan, INVISIBLE, MAX_TABLE_BYTES, MAX_TERMS, PROBE_LAMBDA_STEP_NM, TABLE_LAMBDA_STEP_NM,
};
use crate::physics::chebyshev;
use crate::physics::coherence::CoherenceWindow;
use crate::physics::heightfield::HeightField;
use crate::physics::illuminant::Illuminant;

/// Most Chebyshev nodes in w a build samples (a structure needing more is far deeper than the wavelengths it is
/// lit with, e.g. the Elaphe scan at 16× its height over every view).
pub const MAX_NODES: usize = 96;
/// Most sample positions per axis of the estimate: beyond it (a large patch that is no tiling, where every bin is
/// a lobe centre) the estimate samples a regular grid and says so.
pub(crate) const MAX_PROBE_AXIS: usize = 192;
/// Lobes whose centres lie within this many window widths σ outside the table's box still reach into it.
const PROBE_REACH_SIGMAS: f64 = 3.0;

/// Per degree n = 0..=M, the largest relative excess max(0, Σ_{d≥n}|a_d| − floor)/peak over the functions added:
/// a series truncated to n terms is within excess\[n\]·peak + floor of each of them.
#[derive(Clone, Debug, PartialEq)]
pub struct Tails {
    pub excess: Vec<f64>,
}

impl Tails {
    pub fn new(nodes: usize) -> Self {
        Self { excess: vec![0.0; nodes + 1] }
    }

    /// Adds a function by its Chebyshev coefficients, its brightest value and the absolute error it may keep.
    pub fn add(&mut self, coef: &[f64], peak: f64, floor: f64) {
        let m = coef.len().min(self.excess.len() - 1);
        let mut tail = 0.0;
        for n in (0..=m).rev() {
            if n < m {
                tail += coef[n].abs();
            }
            let over = tail - floor;
            if over > 0.0 {
                let relative = if peak > 0.0 { over / peak } else { f64::INFINITY };
                self.excess[n] = self.excess[n].max(relative);
            }
        }
    }

    pub fn merge(mut self, other: Self) -> Self {
        for (a, b) in self.excess.iter_mut().zip(other.excess) {
            *a = a.max(b);
        }
        self
    }

    /// The fewest terms (at least 1) whose excess is within `tolerance`; None where even every node's is not.
    pub fn needed(&self, tolerance: f64) -> Option<usize> {
        (1..self.excess.len()).find(|&n| self.excess[n] <= tolerance)
    }
}

/// The build's nodes in w and what they cannot see.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nodes {
    pub count: usize,
    /// Per channel (X, Y, Z), a bound on the M-point interpolant's error in any texel: 2·Σ_{d≥M}|a_d|.
    pub unseen: [f64; 3],
}

/// The fewest nodes (at least `at_least`, and 2) whose unseen error is below INVISIBLE/4 in every channel, for
/// w ∈ `w`:
/// Σ_λ weight_λ · 2 · 2·gain²·Σ_{d≥M}|J_d(Ω_λ·ρ)| (the Chebyshev coefficients of e^{iωρt} are 2·i^d·J_d(ωρ),
/// the interpolant's error at most twice the tail). Refused beyond [`MAX_NODES`].
pub(crate) fn nodes_for(
    hf: &HeightField,
    window: &CoherenceWindow,
    cell: (usize, usize),
    w: (f64, f64),
    illuminant: &Illuminant,
    at_least: usize,
) -> Result<Nodes> {
    let (h0, h1) = hf.range();
    let rho = 0.5 * (w.1 - w.0);
    let gain = lattice_gain(window.sigma_x, (hf.nx / cell.0) as f64, window.radius_x)
        * lattice_gain(window.sigma_y, (hf.ny / cell.1) as f64, window.radius_y);
    let spectral = Spectral::new(TABLE_LAMBDA_STEP_NM, illuminant);
    let unseen = |m: usize| {
        let mut u = [0.0; 3];
        for (lambda, weight) in spectral.lambda_um.iter().zip(&spectral.weight) {
            let x = 2.0 * std::f64::consts::PI * (h1 - h0) / lambda * rho;
            let bound = 4.0 * gain * gain * chebyshev::bessel_tail(x, m);
            for (u, wt) in u.iter_mut().zip(weight) {
                *u += wt * bound;
            }
        }
        u
    };
    (at_least.max(2)..=MAX_NODES)
        .map(|count| Nodes { count, unseen: unseen(count) })
        .find(|n| n.unseen.iter().all(|&u| u <= 0.25 * INVISIBLE))
        .ok_or_else(|| {
            Error::Precision(format!(
                "the baked table cannot follow this structure in w: heights spanning {:.3} µm need more than \
                 {MAX_NODES} Chebyshev nodes over w ∈ [{:.2}, {:.2}]; check the heights, or evaluate single \
                 directions with `diffract brdf --method exact`",
                h1 - h0,
                w.0,
                w.1
            ))
        })
}

/// The most the window's taps on a tiling lattice of stride `stride` bins can add up to along one axis:
/// Σ_k exp(−½(k·stride/σ)²) over the taps within `radius`, the value at a lattice point, where this theta sum is
/// largest.
fn lattice_gain(sigma: f64, stride: f64, radius: i64) -> f64 {
    let mut sum = 1.0;
    let mut k = 1.0;
    while k * stride <= radius as f64 + 0.5 {
        let g = (-0.5 * (k * stride / sigma).powi(2)).exp();
        if g < 1e-30 {
            break;
        }
        sum += 2.0 * g;
        k += 1.0;
    }
    sum
}

/// The estimate of the terms in w a table needs, made before it is built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub terms: usize,
    /// The sample points it looked at (summed over its wavelengths), and whether they were every lobe centre
    /// (false: a regular grid, for a patch whose lattice is too fine to visit).
    pub points: usize,
    pub every_lobe: bool,
    /// The largest relative tail left at `terms` (as [`Tails::excess`]).
    pub tail: f64,
}

/// Where the estimate samples along one axis at one wavelength, and the window's taps there.
struct ProbeAxis {
    /// Patch length µm, pixels, tiling stride (bins) and cell pixels; window σ (bins) and radius (taps).
    length: f64,
    pixels: usize,
    stride: i64,
    cells: usize,
    sigma: f64,
    radius: i64,
    /// The table's range along this axis (u or v).
    range: (f64, f64),
}

impl ProbeAxis {
    /// Positions in bins of the whole patch: the lattice's lobe centres (and, with `midpoints`, the points half
    /// way between them) that reach the table's range at λ (µm); a regular grid where they are too many.
    fn positions(&self, lambda: f64, midpoints: bool) -> (Vec<f64>, bool) {
        let per_u = self.length / lambda;
        let half = (self.pixels / 2) as f64;
        let reach = PROBE_REACH_SIGMAS * self.sigma;
        let lo = (self.range.0 * per_u - reach).max(-half);
        let hi = (self.range.1 * per_u + reach).min(self.pixels as f64 - 1.0 - half);
        if hi < lo {
            return (Vec::new(), true);
        }
        let step = if midpoints { 0.5 } else { 1.0 } * self.stride as f64;
        let (first, last) = ((lo / step).ceil() as i64, (hi / step).floor() as i64);
        let count = (last - first + 1).max(0) as usize;
        if count <= MAX_PROBE_AXIS {
            return ((first..=last).map(|i| i as f64 * step).collect(), true);
        }
        let spacing = (hi - lo) / MAX_PROBE_AXIS as f64;
        ((0..MAX_PROBE_AXIS).map(|i| lo + (i as f64 + 0.5) * spacing).collect(), false)
    }

    /// The window's taps at `s` bins: lattice bins within the radius and the patch's band, as (cell index in FFT
    /// order, weight).
    fn taps(&self, s: f64) -> Vec<(usize, f64)> {
        lattice_taps(s, self.pixels, self.stride, self.radius, self.sigma, self.cells)
    }
}

/// The terms in w `plan`'s table will need, estimated at 5 nm steps and `plan.nodes` nodes: the fewest whose
/// tail of |P|² stays within the tolerance × its brightest value (+ what adds less than INVISIBLE to a colour)
/// at every lobe centre inside the table's box, and on the coherent path at the midpoints between neighbouring
/// lobes, where they interfere.
pub fn estimate(hf: &HeightField, plan: &TablePlan) -> Estimate {
    let cell = Cell::new(hf, plan.cell);
    let spectral = Spectral::new(PROBE_LAMBDA_STEP_NM, &plan.illuminant);
    let m = plan.nodes.count;
    let ws: Vec<f64> = chebyshev::nodes(m).into_iter().map(|t| plan.grid.w_of(t)).collect();
    let matrix = chebyshev::coefficient_matrix(m);
    let (lx, ly) = hf.size_um();
    let w = &plan.window;
    let axis = |length, pixels, stride, cells, sigma, radius, range| ProbeAxis {
        length,
        pixels,
        stride,
        cells,
        sigma,
        radius,
        range,
    };
    let ax = axis(lx, hf.nx, cell.tx, cell.px, w.sigma_x, w.radius_x, plan.domain.u);
    let ay = axis(ly, hf.ny, cell.ty, cell.py, w.sigma_y, w.radius_y, plan.domain.v);
    let midpoints = !plan.lattice;
    // A scan of a user's size (1000² samples: 10–30 s an estimate on two cores) shows its progress; the shipped
    // cut-outs take milliseconds.
    let bar = Progress::new_if(
        hf.nx * hf.ny >= PROGRESS_SAMPLES,
        format!("terms in w ∈ [{:.2}, {:.2}] over {}×{} samples", plan.grid.w.0, plan.grid.w.1, hf.nx, hf.ny),
        spectral.lambda_um.len(),
    );
    let (tails, points, every_lobe) = (0..spectral.lambda_um.len())
        .into_par_iter()
        .map(|l| {
            let _step = StepOnDrop(&bar);
            let lambda = spectral.lambda_um[l];
            // |P|² at this wavelength adds weight·|P|² per nm step to a colour: below this floor, nothing seen.
            let per_nm = spectral.weight[l].iter().fold(0.0f64, |a, &b| a.max(b)) / PROBE_LAMBDA_STEP_NM;
            let mut tails = Tails::new(m);
            if per_nm <= 0.0 {
                return (tails, 0, true);
            }
            let floor = INVISIBLE / per_nm;
            let ((xs, every_x), (ys, every_y)) = (ax.positions(lambda, midpoints), ay.positions(lambda, midpoints));
            let values = probe_values(&cell, &ax, &ay, &xs, &ys, &ws, lambda);
            let mut coef = vec![0.0; m];
            for v in values.chunks_exact(m) {
                let peak = v.iter().fold(0.0f64, |a, &b| a.max(b));
                for (c, row) in coef.iter_mut().zip(&matrix) {
                    *c = row.iter().zip(v).map(|(a, b)| a * b).sum();
                }
                tails.add(&coef, peak, floor);
            }
            (tails, xs.len() * ys.len(), every_x && every_y)
        })
        .reduce(|| (Tails::new(m), 0, true), |a, b| (a.0.merge(b.0), a.1 + b.1, a.2 && b.2));
    bar.finish();
    let terms = tails.needed(plan.tolerance).unwrap_or(m);
    Estimate { terms, points, every_lobe, tail: tails.excess[terms] }
}

/// Height fields of at least this many samples show the estimate's progress.
const PROGRESS_SAMPLES: usize = 250_000;

/// One step of a bar when dropped (a wavelength done, whichever way its closure returns).
struct StepOnDrop<'a>(&'a Progress);

impl Drop for StepOnDrop<'_> {
    fn drop(&mut self) {
        self.0.step();
    }
}

/// |P|² at every (x, y) position and node in w, `values[(j·|xs| + i)·M + c]`: P by the window's taps on the
/// lattice, separably (first along x for every spectrum row the y taps reach, then along y).
fn probe_values(
    cell: &Cell,
    ax: &ProbeAxis,
    ay: &ProbeAxis,
    xs: &[f64],
    ys: &[f64],
    ws: &[f64],
    lambda: f64,
) -> Vec<f64> {
    let m = ws.len();
    let mut values = vec![0.0; xs.len() * ys.len() * m];
    if values.is_empty() {
        return values;
    }
    let (tx, ty): (Vec<_>, Vec<_>) =
        (xs.iter().map(|&s| ax.taps(s)).collect(), ys.iter().map(|&s| ay.taps(s)).collect());
    let mut rows: Vec<usize> = ty.iter().flatten().map(|t| t.0).collect();
    rows.sort_unstable();
    rows.dedup();
    // The spectrum is transformed along y only at the columns the x taps read.
    let mut columns: Vec<usize> = tx.iter().flatten().map(|t| t.0).collect();
    columns.sort_unstable();
    columns.dedup();
    let px = cell.px;
    let mut scratch = Vec::new();
    let mut q = vec![Complex64::default(); rows.len() * xs.len()];
    for (c, &w) in ws.iter().enumerate() {
        let a = cell.amplitudes_at(2.0 * std::f64::consts::PI * w / lambda, Some(&columns), &mut scratch);
        for (r, &row) in rows.iter().enumerate() {
            let line = &a[row * px..][..px];
            for (i, taps) in tx.iter().enumerate() {
                q[r * xs.len() + i] = taps.iter().map(|&(k, g)| line[k] * g).sum();
            }
        }
        for (j, taps) in ty.iter().enumerate() {
            for i in 0..xs.len() {
                let p: Complex64 = taps
                    .iter()
                    .map(|&(k, g)| q[rows.binary_search(&k).expect("row collected above") * xs.len() + i] * g)
                    .sum();
                values[(j * xs.len() + i) * m + c] = p.norm_sqr();
            }
        }
    }
    values
}

/// What the build's own values prove about the table it keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Certificate {
    /// Terms kept, and the fewest the tolerance needs (None: not even every node's).
    pub terms: usize,
    pub needed: Option<usize>,
    /// Nodes in w the build sampled, and the largest bound on what they cannot see (any channel).
    pub nodes: usize,
    pub unseen: f64,
    /// In every texel and channel of the finest level, at every w of the interval, the kept series is within
    /// tail × the texel's brightest value + INVISIBLE of the exact colour the texel stands for.
    pub tail: f64,
    pub tolerance: f64,
}

impl Certificate {
    pub fn meets_tolerance(&self) -> bool {
        self.tail <= self.tolerance
    }

    /// The claim in words.
    pub fn describe(&self) -> String {
        let claim = format!(
            "{} terms in w: tail ≤ {:.1e} of each texel's brightest value + 1e-10 at every texel and w (certified from \
             {} nodes; tolerance {:.0e})",
            self.terms, self.tail, self.nodes, self.tolerance
        );
        match self.needed {
            Some(n) if n <= self.terms => claim,
            Some(n) => format!("{claim}; the tolerance needs {n} terms"),
            None => format!("{claim}; the tolerance cannot be met with {} nodes", self.nodes),
        }
    }
}

/// The most terms a table on `grid` may keep: what fits in [`MAX_TABLE_BYTES`], at most [`MAX_TERMS`] and the
/// build's `nodes`.
pub(crate) fn terms_that_fit(grid: &Grid, nodes: usize) -> usize {
    (1..=nodes.min(MAX_TERMS)).rev().find(|&n| grid.bytes(n) <= MAX_TABLE_BYTES).unwrap_or(1)
}

/// Turns the build's node values (`data[t·3M + c·3 + ch]`, M = `nodes.count`) into Chebyshev coefficients in
/// place (`data[t·3M + d·3 + ch]`) and certifies the degree kept: the fewest terms the tolerance needs in every
/// texel and channel, or `fit` ([`terms_that_fit`]) where that is fewer.
pub(crate) fn certify(data: &mut [f64], fit: usize, nodes: &Nodes, tolerance: f64) -> Result<Certificate> {
    let m = nodes.count;
    let matrix = chebyshev::coefficient_matrix(m);
    let floor = nodes.unseen.map(|u| INVISIBLE - u);
    let (tails, finite) = data
        .par_chunks_mut(3 * m)
        .fold(
            || (Tails::new(m), true, vec![0.0; m]),
            |(mut tails, mut finite, mut coef), texel| {
                for ch in 0..3 {
                    let peak = (0..m).map(|c| texel[c * 3 + ch].abs()).fold(0.0, f64::max);
                    for (c, row) in coef.iter_mut().zip(&matrix) {
                        *c = row.iter().enumerate().map(|(n, f)| f * texel[n * 3 + ch]).sum();
                    }
                    finite &= coef.iter().all(|c| c.is_finite());
                    tails.add(&coef, peak, floor[ch]);
                    for (d, &c) in coef.iter().enumerate() {
                        texel[d * 3 + ch] = c;
                    }
                }
                (tails, finite, coef)
            },
        )
        .map(|(tails, finite, _)| (tails, finite))
        .reduce(|| (Tails::new(m), true), |a, b| (a.0.merge(b.0), a.1 && b.1));
    if !finite {
        return Err(Error::Precision("the baked table has non-finite coefficients (a bug in diffract)".into()));
    }
    let needed = tails.needed(tolerance);
    let terms = needed.unwrap_or(m).min(fit.clamp(1, m));
    Ok(Certificate {
        terms,
        needed,
        nodes: m,
        unseen: nodes.unseen.iter().fold(0.0f64, |a, &b| a.max(b)),
        tail: tails.excess[terms],
        tolerance,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tails_report_the_excess_over_the_floor_relative_to_the_peak() {
        let mut t = Tails::new(4);
        // Coefficients 1, 0.1, 0.01, 0.001 of a function whose peak is 1: the tail from degree n is 0.111, 0.011,
        // 0.001 and 0.
        t.add(&[1.0, 0.1, 0.01, 0.001], 1.0, 0.0);
        assert!((t.excess[1] - 0.111).abs() < 1e-12 && (t.excess[3] - 0.001).abs() < 1e-12 && t.excess[4] == 0.0);
        assert_eq!(t.needed(0.005), Some(3));
        assert_eq!(t.needed(1e-6), Some(4));
        // A dark function within its floor adds nothing; one above it with no peak makes every degree fail.
        let mut dark = Tails::new(4);
        dark.add(&[1e-12, 1e-12, 0.0, 0.0], 1e-12, 1e-10);
        assert!(dark.excess.iter().all(|&e| e == 0.0));
        dark.add(&[0.0, 0.0, 0.0, 0.0], 0.0, -1.0);
        assert_eq!(dark.needed(0.1), None);
        let merged = t.merge(Tails { excess: vec![0.0, 0.0, 0.0, 0.5, 0.0] });
        assert_eq!(merged.needed(0.005), Some(4));
    }

    /// Node values of `texels` texels whose channels all follow exp(t·k) over w (t ∈ [−1, 1]), k per texel.
    fn exponential_texels(ks: &[f64], m: usize) -> Vec<f64> {
        let t = chebyshev::nodes(m);
        ks.iter().flat_map(|&k| t.iter().flat_map(move |&t| [(t * k).exp(); 3])).collect()
    }

    #[test]
    fn the_certificate_keeps_the_fewest_terms_that_meet_the_tolerance_or_says_what_it_misses() {
        let nodes = Nodes { count: 24, unseen: [0.0; 3] };
        // exp(k·t)'s Chebyshev coefficients are 2·I_d(k): for k = 2 the tail from degree 9 is ~1e-5 of the peak e².
        let mut data = exponential_texels(&[0.5, 2.0], 24);
        let c = certify(&mut data, 64, &nodes, 1e-4).unwrap();
        assert!(c.meets_tolerance() && c.terms == c.needed.unwrap() && (6..=12).contains(&c.terms), "{c:?}");
        // The coefficients are the series': I_0(2) = 2.2795853 for the second texel's constant term.
        assert!((data[3 * 24] - 2.279_585_302_336_067).abs() < 1e-12, "{}", data[3 * 24]);
        // Memory for 3 terms only: the certificate keeps 3, says the tolerance needs more, and the tail it leaves.
        let mut data = exponential_texels(&[0.5, 2.0], 24);
        let short = certify(&mut data, 3, &nodes, 1e-4).unwrap();
        assert_eq!((short.terms, short.needed), (3, c.needed));
        assert!(!short.meets_tolerance() && short.tail > 1e-3, "{short:?}");
        assert!(short.describe().contains(&format!("the tolerance needs {} terms", c.terms)), "{}", short.describe());
    }

    #[test]
    fn the_lattice_gain_is_one_for_a_sparse_lattice_and_the_gaussian_area_for_a_dense_one() {
        assert!((lattice_gain(0.64, 10.0, 6) - 1.0).abs() < 1e-20);
        let dense = lattice_gain(4.0, 1.0, 40);
        assert!((dense - (2.0 * std::f64::consts::PI).sqrt() * 4.0).abs() < 1e-9, "{dense}");
    }
}
