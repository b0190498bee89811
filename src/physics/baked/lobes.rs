//! What the table's build and its degree estimate share: a patch's tiling cell with the amplitudes
//! A_k = DFT(exp(i·κ·h))(k) of its FFT, the wavelengths with their colour weights under an illuminant, and the
//! coherence window's taps on the tiling lattice (the reference's taps, `physics::exact`).

use std::sync::Arc;

use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

use crate::physics::heightfield::HeightField;
use crate::physics::illuminant::Illuminant;
use crate::physics::sincos::phases;
use crate::physics::spectrum::Sampling;

/// Wavelengths (µm) and their weights (x̄S, ȳS, z̄S)·Δλ / Σ ȳSΔλ under the illuminant S: Σ_λ |P|²·weight is XYZ
/// relative to a mirror under S, as `spectrum::reflectance_to_xyz` sums it.
pub(super) struct Spectral {
    pub(super) lambda_um: Vec<f64>,
    pub(super) weight: Vec<[f64; 3]>,
}

impl Spectral {
    pub(super) fn new(step_nm: f64, illuminant: &Illuminant) -> Self {
        let sampling = Sampling::visible_under(step_nm, *illuminant);
        let weights = sampling.wavelengths().map(|l| {
            let s = sampling.weights_at(l);
            [s[0], s[1], s[2]].map(|c| c * s[3] * step_nm)
        });
        Self::of_weights(&sampling, weights, sampling.y_norm())
    }

    /// `sampling`'s wavelengths with `weights` over `norm`, those that weigh nothing left out.
    fn of_weights(sampling: &Sampling, weights: impl Iterator<Item = [f64; 3]>, norm: f64) -> Self {
        let (mut lambda_um, mut weight) = (Vec::new(), Vec::new());
        for (l, w) in sampling.wavelengths().zip(weights) {
            if w.iter().any(|&c| c != 0.0) {
                lambda_um.push(l * 1e-3);
                weight.push(w.map(|c| c / norm));
            }
        }
        Self { lambda_um, weight }
    }

    /// [`Self::new`] with each wavelength weighing its bin's integral ([`Sampling::binned_weights`]), normalised
    /// by the 1 nm tables' Σ ȳS: a mirror's colour is the light's at any step (a [`super::TablePlan::mass_only`]
    /// table's).
    pub(super) fn binned(step_nm: f64, illuminant: &Illuminant) -> Self {
        let sampling = Sampling::visible_under(step_nm, *illuminant);
        let norm = Sampling::visible_under(1.0, *illuminant).y_norm();
        Self::of_weights(&sampling, sampling.binned_weights().into_iter(), norm)
    }

    /// The wavelengths and weights a table of `plan` sums: binned for a [`super::TablePlan::mass_only`] table.
    pub(super) fn of_plan(plan: &super::TablePlan) -> Self {
        if plan.mass_only {
            Self::binned(plan.lambda_step_nm, &plan.illuminant)
        } else {
            Self::new(plan.lambda_step_nm, &plan.illuminant)
        }
    }
}

/// The patch's tiling cell and its FFT plans.
pub(super) struct Cell {
    pub(super) px: usize,
    pub(super) py: usize,
    /// Tiling strides: full-patch bin = stride × cell bin.
    pub(super) tx: i64,
    pub(super) ty: i64,
    heights: Vec<f64>,
    /// Distinct heights and each pixel's index among them, where they are few (an 8-bit scan has ≤ 256): the
    /// phases exp(i·κ·h) are then computed once per distinct height.
    distinct: Option<(Vec<f64>, Vec<u32>)>,
    fx: Arc<dyn Fft<f64>>,
    fy: Arc<dyn Fft<f64>>,
}

impl Cell {
    pub(super) fn new(hf: &HeightField, (px, py): (usize, usize)) -> Self {
        // Centred on the whole patch's mean, as the reference centres it.
        let mean = hf.mean();
        let heights: Vec<f64> = hf.corner(px, py).heights_um.iter().map(|h| h - mean).collect();
        let mut values = heights.clone();
        values.sort_by(f64::total_cmp);
        values.dedup();
        let distinct = (values.len() * 8 <= heights.len()).then(|| {
            let index = heights.iter().map(|h| values.partition_point(|v| v < h) as u32).collect();
            (values, index)
        });
        let mut planner = FftPlanner::new();
        Self {
            px,
            py,
            tx: (hf.nx / px) as i64,
            ty: (hf.ny / py) as i64,
            heights,
            distinct,
            fx: planner.plan_fft_inverse(px),
            fy: planner.plan_fft_inverse(py),
        }
    }

    /// A_k for every cell bin, row-major in FFT order (index k mod n), normalised so that a flat patch has
    /// A_0 = 1: the centred inverse DFT of exp(i·κ·h) of `physics::taylor` (+i exponent, 1/N²). (A buffer
    /// reused from call to call, instead of a fresh one, made a 1000² patch's build 9 % slower.)
    pub(super) fn amplitudes(&self, kappa: f64, scratch: &mut Vec<Complex64>) -> Vec<Complex64> {
        self.amplitudes_at(kappa, None, scratch)
    }

    /// [`Self::amplitudes`] where only the cell columns `columns` (ascending) are read: the others hold their
    /// rows' transforms alone (the transform along v, a column at a time, is left out where nobody reads it).
    pub(super) fn amplitudes_at(
        &self,
        kappa: f64,
        columns: Option<&[usize]>,
        scratch: &mut Vec<Complex64>,
    ) -> Vec<Complex64> {
        let (px, py) = (self.px, self.py);
        let norm = 1.0 / (px * py) as f64;
        let mut a = Vec::new();
        match &self.distinct {
            Some((values, index)) => {
                phases(kappa, norm, values, scratch);
                a.extend(index.iter().map(|&i| scratch[i as usize]));
            }
            None => phases(kappa, norm, &self.heights, &mut a),
        }
        self.fx.process(&mut a);
        let all: Vec<usize>;
        let columns = match columns {
            Some(c) => c,
            None => {
                all = (0..px).collect();
                &all
            }
        };
        scratch.resize(columns.len() * py, Complex64::default());
        for r in 0..py {
            for (j, &c) in columns.iter().enumerate() {
                scratch[j * py + r] = a[r * px + c];
            }
        }
        if !columns.is_empty() {
            self.fy.process(scratch);
        }
        for (j, &c) in columns.iter().enumerate() {
            for r in 0..py {
                a[r * px + c] = scratch[j * py + r];
            }
        }
        a
    }

    /// The centred bin of FFT index `i` of an `n`-point axis (DC at ⌊n/2⌋ in the centred array, so indices
    /// from n − ⌊n/2⌋ on are negative frequencies).
    pub(super) fn bin(i: usize, n: usize) -> i64 {
        if i < n - n / 2 {
            i as i64
        } else {
            i as i64 - n as i64
        }
    }
}

/// The window's taps at `s` bins of the whole patch, as the reference takes them: the tiling lattice's bins (every
/// `stride`-th) within `radius` of the nearest bin and inside the patch's `pixels`-bin spectrum, as (cell index in
/// FFT order of a `cells`-bin cell, weight exp(−½((j − s)/σ)²)).
pub(super) fn lattice_taps(
    s: f64,
    pixels: usize,
    stride: i64,
    radius: i64,
    sigma: f64,
    cells: usize,
) -> Vec<(usize, f64)> {
    let half = (pixels / 2) as i64;
    let (lo, hi) = (-half, pixels as i64 - 1 - half);
    let nearest = (s + 0.5).floor() as i64;
    let first = -(-(nearest - radius).max(lo)).div_euclid(stride);
    let last = (nearest + radius).min(hi).div_euclid(stride);
    (first..=last)
        .map(|k| {
            let d = (k * stride) as f64 - s;
            (k.rem_euclid(cells as i64) as usize, (-0.5 * d * d / (sigma * sigma)).exp())
        })
        .collect()
}
