//! A measured patch extended beyond its size without a period (`extend_um`; model.md §5.3, which says what it keeps
//! and what it assumes): a random-phase field with the cut-out's Hann-windowed power spectrum on the extended grid,
//! remapped to the cut-out's own height distribution (histogram matching), from a fixed seed. The scans in
//! `assets/afm` are 6.5 µm cut-outs: tiled to a scene's 65 µm they add a period no snake has.

use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;

use crate::error::{Error, Result};
use crate::physics::heightfield::{check_dims, HeightField};

/// The largest extension, µm: a patch of at most `heightfield::MAX_PIXELS` at the cut-out's pixel in any case.
pub const MAX_EXTEND_UM: f64 = 1000.0;
/// The seed of the random phases: an extension is the same field on every run.
pub const EXTEND_SEED: u64 = 1;

/// `patch` (or one cell of it, where it is a tiling: [`HeightField::tiling_cell`]) extended to `size_um` × `size_um`
/// without a period, the same field on every run ([`EXTEND_SEED`]).
pub fn extend(patch: &HeightField, size_um: f64) -> Result<HeightField> {
    extended(&patch.tiling_cell(), size_um, EXTEND_SEED)
}

/// `cell` (a cut-out, or one period of a tiling: [`HeightField::tiling_cell`]) extended to `size_um` × `size_um`
/// without periodicity (see the module's note), at the cell's own pixel size.
pub fn extended(cell: &HeightField, size_um: f64, seed: u64) -> Result<HeightField> {
    let (cw, ch) = cell.size_um();
    if !(size_um.is_finite() && size_um <= MAX_EXTEND_UM) {
        return Err(Error::setting("extend_um", format!("{size_um} µm: an extension lies within {MAX_EXTEND_UM} µm")));
    }
    if size_um < cw.max(ch) {
        return Err(Error::setting(
            "extend_um",
            format!("{size_um} µm is smaller than the patch ({cw:.3} × {ch:.3} µm): an extension grows it"),
        ));
    }
    let (nx, ny) = ((size_um / cell.dx_um).round() as u64, (size_um / cell.dy_um).round() as u64);
    check_dims(nx, ny).map_err(|e| Error::HeightField(format!("extending to {size_um} µm: {e}")))?;
    let (nx, ny) = (nx as usize, ny as usize);
    let power = windowed_power(cell);
    let mut rng = fastrand::Rng::with_seed(seed);
    let mut gauss = move || {
        // Box–Muller: a standard normal from two uniforms.
        let (u, v) = (1.0 - rng.f64(), rng.f64());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    let signed = |k: usize, n: usize| if k <= n / 2 { k as f64 } else { k as f64 - n as f64 };
    let mut field = vec![Complex64::default(); nx * ny];
    for ky in 0..ny {
        // Bin k of the extended grid is at the cell's fractional bin k·(cell's n)/(extended n).
        let v = signed(ky, ny) * cell.ny as f64 / ny as f64;
        for kx in 0..nx {
            let u = signed(kx, nx) * cell.nx as f64 / nx as f64;
            let amplitude = power.at(u, v).sqrt();
            field[ky * nx + kx] = Complex64::new(gauss(), gauss()) * amplitude;
        }
    }
    field[0] = Complex64::default();
    let mut planner = FftPlanner::<f64>::new();
    let (fx, fy) = (planner.plan_fft_inverse(nx), planner.plan_fft_inverse(ny));
    crate::physics::taylor::ifft2(&mut field, nx, ny, &fx, &fy);
    let heights = matched(field.iter().map(|z| z.re).collect(), &cell.heights_um);
    HeightField::new(nx, ny, cell.dx_um, cell.dy_um, heights)
}

/// The cell's power spectrum through a separable Hann window, on its own grid (bins wrap, DC at 0).
struct Power {
    nx: usize,
    ny: usize,
    values: Vec<f64>,
}

impl Power {
    /// Bilinear between the cell's bins at fractional signed bin (u, v) (|u| ≤ nx/2, |v| ≤ ny/2), wrapping.
    fn at(&self, u: f64, v: f64) -> f64 {
        let wrap = |i: i64, n: usize| i.rem_euclid(n as i64) as usize;
        let (u0, v0) = (u.floor(), v.floor());
        let (tu, tv) = (u - u0, v - v0);
        let value =
            |du: i64, dv: i64| self.values[wrap(v0 as i64 + dv, self.ny) * self.nx + wrap(u0 as i64 + du, self.nx)];
        (value(0, 0) * (1.0 - tu) + value(1, 0) * tu) * (1.0 - tv) + (value(0, 1) * (1.0 - tu) + value(1, 1) * tu) * tv
    }
}

fn windowed_power(cell: &HeightField) -> Power {
    let (nx, ny) = (cell.nx, cell.ny);
    let hann = |i: usize, n: usize| {
        if n < 2 {
            1.0
        } else {
            0.5 - 0.5 * (std::f64::consts::TAU * (i as f64 + 0.5) / n as f64).cos()
        }
    };
    let h = cell.centred();
    let mut data: Vec<Complex64> =
        (0..nx * ny).map(|i| Complex64::new(h[i] * hann(i % nx, nx) * hann(i / nx, ny), 0.0)).collect();
    let mut planner = FftPlanner::<f64>::new();
    let (fx, fy) = (planner.plan_fft_forward(nx), planner.plan_fft_forward(ny));
    // (The 2D pass of `ifft2` with forward plans: the transform's direction is the plans'.)
    crate::physics::taylor::ifft2(&mut data, nx, ny, &fx, &fy);
    Power { nx, ny, values: data.iter().map(|z| z.norm_sqr()).collect() }
}

/// `values` with each replaced by the value of the same rank among `target` (quantiles interpolated where the
/// counts differ): the distribution of `target`, the order of `values`.
fn matched(values: Vec<f64>, target: &[f64]) -> Vec<f64> {
    let mut sorted_target = target.to_vec();
    sorted_target.sort_by(f64::total_cmp);
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let (n, m) = (values.len(), sorted_target.len());
    let mut out = vec![0.0; n];
    for (rank, &i) in order.iter().enumerate() {
        // The rank's quantile, mapped onto the target's sorted values.
        let q = (rank as f64 + 0.5) / n as f64 * m as f64 - 0.5;
        let lo = q.floor().clamp(0.0, (m - 1) as f64) as usize;
        let hi = (lo + 1).min(m - 1);
        let t = (q - lo as f64).clamp(0.0, 1.0);
        out[i] = sorted_target[lo] * (1.0 - t) + sorted_target[hi] * t;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cut-out of a grating of period 0.65 µm along x with a little noise, 6.5 µm across.
    fn grating_cell() -> HeightField {
        let (n, dx) = (100, 0.065);
        let mut rng = fastrand::Rng::with_seed(3);
        let h = (0..n * n)
            .map(|i| {
                let x = (i % n) as f64 * dx;
                0.1 + 0.05 * (std::f64::consts::TAU * x / 0.65).sin() + 0.01 * (rng.f64() - 0.5)
            })
            .collect();
        HeightField::new(n, n, dx, dx, h).unwrap()
    }

    /// Radially unaware power along the x axis of frequency (cycles/µm) of a field, its mean over the y bins
    /// near 0, normalised to sum 1: where its energy lies along the grating's axis.
    fn x_power(hf: &HeightField) -> Vec<(f64, f64)> {
        let p = windowed_power(hf);
        let mut out: Vec<(f64, f64)> =
            (1..hf.nx / 2).map(|k| (k as f64 / (hf.nx as f64 * hf.dx_um), p.values[k])).collect();
        let total: f64 = out.iter().map(|(_, v)| v).sum();
        out.iter_mut().for_each(|(_, v)| *v /= total);
        out
    }

    #[test]
    fn the_extension_keeps_the_heights_and_the_spectrum_and_has_no_period() {
        let cell = grating_cell();
        let big = extended(&cell, 65.0, EXTEND_SEED).unwrap();
        assert_eq!((big.nx, big.ny), (1000, 1000));
        // The height distribution is the cell's (quantiles within a hundredth of the range).
        let mut a = cell.heights_um.clone();
        let mut b = big.heights_um.clone();
        a.sort_by(f64::total_cmp);
        b.sort_by(f64::total_cmp);
        let range = a[a.len() - 1] - a[0];
        for q in [0.0, 0.01, 0.25, 0.5, 0.75, 0.99, 1.0] {
            let (x, y) = (a[((a.len() - 1) as f64 * q) as usize], b[((b.len() - 1) as f64 * q) as usize]);
            assert!((x - y).abs() < 0.01 * range, "quantile {q}: {x} against {y}");
        }
        // The grating's frequency (1/0.65 µm) holds most of the power along x in both.
        let peak = |spectrum: &[(f64, f64)]| {
            let near: f64 = spectrum.iter().filter(|(f, _)| (f - 1.0 / 0.65).abs() < 0.25).map(|(_, v)| v).sum();
            near
        };
        let (pc, pb) = (peak(&x_power(&cell)), peak(&x_power(&big)));
        assert!(pc > 0.8 && pb > 0.6, "the grating's share of the power: cell {pc}, extended {pb}");
        // No period: the extended field is not a tiling of anything smaller than itself, and a shift by the cell's
        // size does not map it onto itself (correlation well below a tiling's 1).
        assert_eq!(big.period_cell(), (big.nx, big.ny));
        let c = big.centred();
        let shift = cell.nx;
        let (mut xy, mut xx) = (0.0, 0.0);
        for r in 0..big.ny {
            for col in 0..big.nx - shift {
                xy += c[r * big.nx + col] * c[r * big.nx + col + shift];
                xx += c[r * big.nx + col] * c[r * big.nx + col];
            }
        }
        // The grating itself repeats every 10 periods of 0.65 µm = 6.5 µm; the phases are random, so the lines
        // wander: the correlation at the cell's shift is far from the tiling's 1.
        assert!(xy / xx < 0.5, "correlation at the cell's size {}", xy / xx);
        // The tiling's spectrum lies on every tenth bin (a lattice: 1/(6.5 µm) apart); the extension's fills the
        // bins between.
        let off_lattice = |hf: &HeightField| {
            let h = hf.centred();
            let mut data: Vec<Complex64> = h.iter().map(|&x| Complex64::new(x, 0.0)).collect();
            let mut planner = FftPlanner::<f64>::new();
            let (fx, fy) = (planner.plan_fft_forward(hf.nx), planner.plan_fft_forward(hf.ny));
            crate::physics::taylor::ifft2(&mut data, hf.nx, hf.ny, &fx, &fy);
            let total: f64 = data.iter().map(|z| z.norm_sqr()).sum();
            let off: f64 = (0..data.len())
                .filter(|i| (i % hf.nx) % 10 != 0 || (i / hf.nx) % 10 != 0)
                .map(|i| data[i].norm_sqr())
                .sum();
            off / total
        };
        let (tiled, free) = (off_lattice(&cell.tiled(10, 10).unwrap()), off_lattice(&big));
        assert!(tiled < 1e-20 && free > 0.5, "power off the tiling's lattice: tiled {tiled}, extended {free}");
        // The same seed gives the same field.
        assert_eq!(extended(&cell, 65.0, EXTEND_SEED).unwrap().heights_um, big.heights_um);
    }

    #[test]
    fn bad_extensions_are_refused() {
        let cell = grating_cell();
        assert!(extended(&cell, 3.0, 1).unwrap_err().to_string().contains("smaller than the patch"));
        assert!(extended(&cell, f64::NAN, 1).unwrap_err().to_string().contains("within"));
        assert!(extended(&cell, 5000.0, 1).unwrap_err().to_string().contains("within"));
    }
}
