//! The exact build of a baked table in f64 (model.md §3.5, "How it is built"): per wavelength (1 nm steps) and per
//! Chebyshev node in w, one FFT of the patch's tiling cell; then per texel the lattice path (lobes that do not
//! interfere, each texel's average of a lobe a product of error functions, in bands of texel rows that stay in
//! cache) or the coherent path (the windowed sum at sub-samples of each texel, separably, a batch of wavelengths
//! at a time); the node values become Chebyshev coefficients by a DCT per texel, and the degree kept is the one
//! [`crate::physics::baked::degree`]'s certificate proves on these very values.

use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::error::Result;
use crate::physics::baked::lobes::{lattice_taps, Cell, Spectral};
use crate::physics::baked::{degree, BakedTable, Grid, TablePlan, INVISIBLE};
use crate::physics::chebyshev;
use crate::physics::heightfield::HeightField;

/// Bytes of accumulators a band of texel rows may hold (about what a core's L2 cache keeps).
const BAND_BYTES: usize = 512 << 10;

/// Bytes the coherent path's sums along u may hold at once, over all threads: they bound the wavelengths a
/// batch takes (at most [`MAX_BATCH`]).
const BATCH_BYTES: usize = 256 << 20;
const MAX_BATCH: usize = 8;

/// One wavelength's taps along u and along v at the sub-samples: per sub-sample column its run, per sub-sample row
/// its (cell, weight)s.
type LambdaTaps = (Vec<Run>, Vec<Vec<(usize, f64)>>);

/// A sub-sample column's taps along u: consecutive cells (modulo the cell's width) from `start`, with `weights`.
struct Run {
    start: usize,
    weights: Vec<f64>,
}

impl Run {
    /// The taps `taps` (cell, weight) of a line of `cells` as a run; they are consecutive cells (`lattice_taps`).
    fn of(taps: &[(usize, f64)], cells: usize) -> Self {
        let start = taps.first().map_or(0, |t| t.0);
        debug_assert!(taps.iter().enumerate().all(|(j, t)| t.0 == (start + j) % cells));
        Self { start, weights: taps.iter().map(|t| t.1).collect() }
    }

    /// Σ weight·A over the run, in `doubled` (a line of A twice over), in the taps' order.
    fn sum(&self, doubled: &[Complex64]) -> Complex64 {
        doubled[self.start..self.start + self.weights.len()].iter().zip(&self.weights).map(|(a, &g)| a * g).sum()
    }
}

/// Whether a line of the spectrum (the cells of it that are read) carries anything: Σ|A| ≥ INVISIBLE·10⁻³ (an AFM
/// scan's lines all do; a 1D grating's one). The sum stops once it gets there (it only grows, so the answer is the whole sum's); |A| as
/// √|A|², not `norm`, whose overflow-safe hypot took 4 % of a build.
fn live(line: impl Iterator<Item = Complex64>) -> bool {
    let mut mass = 0.0;
    for c in line {
        mass += c.norm_sqr().sqrt();
        if mass >= INVISIBLE * 1e-3 {
            return true;
        }
    }
    false
}

/// Progress callback: (steps done, steps in all).
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// Texel edges, the window and band along one axis of the grid.
#[derive(Clone, Copy)]
struct Axis {
    origin: f64,
    texel: f64,
    count: usize,
    /// Patch length (µm), window width σ (bins), pixels and tiling stride along the axis, window radius (taps).
    length: f64,
    sigma: f64,
    pixels: usize,
    stride: i64,
    radius: i64,
}

impl Axis {
    /// u of the lookup's band edge at λ: |u| ≤ (N/2)·λ/L.
    fn band(&self, lambda: f64) -> f64 {
        0.5 * self.pixels as f64 * lambda / self.length
    }

    /// The lobe of full-patch bin `bin` at λ, exp(−(u − centre)²/σ_u²), on the texels within `reach` (in σ_u)
    /// of its centre: (first texel, weights). Box weights average it over each texel (clipped to the band);
    /// point weights take its value at the texel's centre (zero out of band).
    fn lobe(&self, bin: i64, lambda: f64, reach: f64, point: bool) -> (usize, Vec<f64>) {
        let per_bin = lambda / self.length;
        let (centre, sigma_u) = (bin as f64 * per_bin, self.sigma * per_bin);
        let band = self.band(lambda);
        let reach = reach * sigma_u;
        let first = ((centre - reach - self.origin) / self.texel).floor().max(0.0) as usize;
        let last = (((centre + reach - self.origin) / self.texel).ceil().max(0.0) as usize).min(self.count);
        let scale = 0.5 * std::f64::consts::PI.sqrt() * sigma_u / self.texel;
        let weights = (first..last.max(first))
            .map(|a| {
                let (e0, e1) = (self.origin + a as f64 * self.texel, self.origin + (a + 1) as f64 * self.texel);
                if point {
                    let u = 0.5 * (e0 + e1);
                    let d = (u - centre) / sigma_u;
                    return if u.abs() <= band { (-d * d).exp() } else { 0.0 };
                }
                let (e0, e1) = (e0.max(-band), e1.min(band));
                if e1 <= e0 {
                    return 0.0;
                }
                scale * erf_difference((e0 - centre) / sigma_u, (e1 - centre) / sigma_u)
            })
            .collect();
        (first, weights)
    }

    /// The window's taps at each sub-sample position (s per texel) at λ, as the reference takes them: full-patch
    /// bins on the tiling lattice within `radius` of the nearest bin and inside the patch's spectrum, as (cell
    /// index in FFT order, weight); empty where the lookup itself is out of band.
    fn taps(&self, lambda: f64, s: usize, cells: usize) -> Vec<Vec<(usize, f64)>> {
        let band = self.band(lambda);
        (0..self.count * s)
            .map(|i| {
                let u = self.origin + (i as f64 + 0.5) / s as f64 * self.texel;
                if u.abs() > band {
                    return Vec::new();
                }
                lattice_taps(u * self.length / lambda, self.pixels, self.stride, self.radius, self.sigma, cells)
            })
            .collect()
    }
}

/// erf(b) − erf(a) for a ≤ b without cancellation in the tails.
fn erf_difference(a: f64, b: f64) -> f64 {
    if a >= 0.0 {
        libm::erfc(a) - libm::erfc(b)
    } else if b <= 0.0 {
        libm::erfc(-b) - libm::erfc(-a)
    } else {
        libm::erf(b) - libm::erf(a)
    }
}

/// Node values of one build: `data[t·nodes·C + c·C + ch]` is channel ch at w-node c of texel t, with C = 3 per
/// band (X, Y, Z under each band's light).
struct NodeValues {
    nodes: usize,
    data: Vec<f64>,
}

/// The wavelengths a build sums and, per wavelength, the weights of its channels: (x̄S, ȳS, z̄S)·Δλ/Σ ȳSΔλ of each
/// band's light S, band after band. Several bands (lights) share every wavelength's |P|², the costly part.
struct Weights {
    lambda_um: Vec<f64>,
    /// `per_lambda[l·channels + ch]`.
    per_lambda: Vec<f64>,
    channels: usize,
}

impl Weights {
    /// The weights of `spectrals` (one per band); None where their wavelengths differ.
    fn of(spectrals: &[Spectral]) -> Option<Self> {
        let lambda_um = spectrals.first()?.lambda_um.clone();
        if spectrals.iter().any(|s| s.lambda_um != lambda_um) {
            return None;
        }
        let channels = 3 * spectrals.len();
        let mut per_lambda = Vec::with_capacity(lambda_um.len() * channels);
        for l in 0..lambda_um.len() {
            for s in spectrals {
                per_lambda.extend_from_slice(&s.weight[l]);
            }
        }
        Some(Self { lambda_um, per_lambda, channels })
    }

    fn at(&self, l: usize) -> &[f64] {
        &self.per_lambda[l * self.channels..(l + 1) * self.channels]
    }
}

/// What one build pass covers.
struct Pass<'a> {
    grid: Grid,
    nodes: usize,
    spectral: Weights,
    cell: &'a Cell,
    ax: Axis,
    ay: Axis,
    /// Texel centres' values instead of texel averages.
    point: bool,
    subsamples: usize,
}

/// One lobe at one wavelength: its cell bin (FFT order), the texels it reaches, and |A|² at each node in w.
struct Lobe {
    kx: usize,
    ky: usize,
    columns: (usize, usize),
    rows: (usize, usize),
    intensity: Vec<f64>,
}

/// One wavelength of the lattice path: the lobe weights per cell column and row, and the lobes.
struct Wavelength {
    weight: Vec<f64>,
    columns: Vec<(usize, Vec<f64>)>,
    rows: Vec<(usize, Vec<f64>)>,
    /// Sorted by their first row.
    lobes: Vec<Lobe>,
}

impl Pass<'_> {
    fn ws(&self) -> Vec<f64> {
        chebyshev::nodes(self.nodes).into_iter().map(|t| self.grid.w_of(t)).collect()
    }

    fn tick(progress: Option<Progress<'_>>, done: &AtomicUsize, offset: usize, total: usize) {
        let d = done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(p) = progress {
            p(offset + d, total);
        }
    }

    /// Lattice path, step 1: every wavelength's lobe weights and its lobes' intensities at every node in w.
    fn wavelengths(&self, progress: Option<Progress<'_>>, offset: usize, total: usize) -> Vec<Wavelength> {
        let ws = self.ws();
        let done = AtomicUsize::new(0);
        let widest = (1.0 / INVISIBLE).ln().sqrt();
        let (px, py) = (self.cell.px, self.cell.py);
        (0..self.spectral.lambda_um.len())
            .into_par_iter()
            .map(|l| {
                let lambda = self.spectral.lambda_um[l];
                let axis = |axis: &Axis, n: usize| -> Vec<(usize, Vec<f64>)> {
                    (0..n).map(|k| axis.lobe(Cell::bin(k, n) * axis.stride, lambda, widest, self.point)).collect()
                };
                let (columns, rows) = (axis(&self.ax, px), axis(&self.ay, py));
                let mut scratch = Vec::new();
                let spectra: Vec<Vec<Complex64>> = ws
                    .iter()
                    .map(|&w| self.cell.amplitudes(2.0 * std::f64::consts::PI * w / lambda, &mut scratch))
                    .collect();
                let mut lobes = Vec::new();
                for (ky, (y0, wy)) in rows.iter().enumerate() {
                    if wy.is_empty() {
                        continue;
                    }
                    for (kx, (x0, wx)) in columns.iter().enumerate() {
                        if wx.is_empty() {
                            continue;
                        }
                        let intensity: Vec<f64> = spectra.iter().map(|a| a[ky * px + kx].norm_sqr()).collect();
                        let peak = intensity.iter().fold(0.0, |m: f64, &v| m.max(v));
                        if peak < INVISIBLE {
                            continue;
                        }
                        // This lobe's own reach: beyond it, it adds less than INVISIBLE.
                        let reach = (peak / INVISIBLE).ln().sqrt();
                        let span = |first: usize, w: &[f64], k: usize, n: usize, axis: &Axis| {
                            let centre = (Cell::bin(k, n) * axis.stride) as f64 * lambda / axis.length;
                            let r = reach * axis.sigma * lambda / axis.length;
                            let lo = ((centre - r - axis.origin) / axis.texel).floor().max(0.0) as usize;
                            let hi = ((centre + r - axis.origin) / axis.texel).ceil().max(0.0) as usize;
                            (lo.max(first), hi.min(first + w.len()))
                        };
                        let (columns, rows) = (span(*x0, wx, kx, px, &self.ax), span(*y0, wy, ky, py, &self.ay));
                        if columns.0 < columns.1 && rows.0 < rows.1 {
                            lobes.push(Lobe { kx, ky, columns, rows, intensity });
                        }
                    }
                }
                lobes.sort_by_key(|lobe| lobe.rows.0);
                Self::tick(progress, &done, offset, total);
                Wavelength { weight: self.spectral.at(l).to_vec(), columns, rows, lobes }
            })
            .collect()
    }

    /// Lattice path, step 2: bands of texel rows gather every lobe that reaches them.
    fn lattice(&self, progress: Option<Progress<'_>>, offset: usize, total: usize) -> NodeValues {
        let wavelengths = self.wavelengths(progress, offset, total);
        let channels = self.spectral.channels;
        let (nu, nv, stride) = (self.grid.nu, self.grid.nv, self.nodes * channels);
        let band = (BAND_BYTES / (nu * stride * 8)).clamp(1, nv);
        let tallest = wavelengths.iter().flat_map(|w| w.lobes.iter().map(|l| l.rows.1 - l.rows.0)).max().unwrap_or(0);
        let mut data = vec![0.0; nu * nv * stride];
        data.par_chunks_mut(band * nu * stride).enumerate().for_each(|(index, acc)| {
            let (r0, r1) = (index * band, ((index + 1) * band).min(nv));
            let mut f = vec![0.0; stride];
            for wl in &wavelengths {
                let start = wl.lobes.partition_point(|l| l.rows.0 + tallest < r0);
                for lobe in &wl.lobes[start..] {
                    if lobe.rows.0 >= r1 {
                        break;
                    }
                    let (ya, yb) = (lobe.rows.0.max(r0), lobe.rows.1.min(r1));
                    if ya >= yb {
                        continue;
                    }
                    for (c, &i) in lobe.intensity.iter().enumerate() {
                        for (ch, &weight) in wl.weight.iter().enumerate() {
                            f[c * channels + ch] = i * weight;
                        }
                    }
                    let (x0, wx) = &wl.columns[lobe.kx];
                    let (y0, wy) = &wl.rows[lobe.ky];
                    let (xa, xb) = lobe.columns;
                    for row in ya..yb {
                        let fy = wy[row - y0];
                        let line = &mut acc[((row - r0) * nu + xa) * stride..((row - r0) * nu + xb) * stride];
                        for (texel, &fx) in line.chunks_exact_mut(stride).zip(&wx[xa - x0..xb - x0]) {
                            let s = fy * fx;
                            for (dst, &v) in texel.iter_mut().zip(&f) {
                                *dst += s * v;
                            }
                        }
                    }
                }
            }
        });
        NodeValues { nodes: self.nodes, data }
    }

    /// Coherent path: P at every sub-sample by the separable windowed sum, |P|² averaged into its texel; in
    /// parallel over the nodes in w, a batch of wavelengths at a time. A node sums a batch's wavelengths row by
    /// row of texels before it adds them to its plane of node values, so that plane (megabytes) is read and
    /// written once a batch rather than once a wavelength.
    fn coherent(&self, progress: Option<Progress<'_>>, offset: usize, total: usize) -> NodeValues {
        let (nu, nv, s) = (self.grid.nu, self.grid.nv, self.subsamples);
        let (px, py) = (self.cell.px, self.cell.py);
        let ws = self.ws();
        let channels = self.spectral.channels;
        let mut planes: Vec<Vec<f64>> = (0..self.nodes).map(|_| vec![0.0; nu * nv * channels]).collect();
        let done = AtomicUsize::new(0);
        let lambdas: Vec<usize> = (0..self.spectral.lambda_um.len()).collect();
        // A wavelength's sums along u (one line per spectrum row) take this much memory while its batch runs.
        let sums = py * nu * s * std::mem::size_of::<Complex64>();
        let batch = (BATCH_BYTES / (sums * rayon::current_num_threads()).max(1)).clamp(1, MAX_BATCH);
        for chunk in lambdas.chunks(batch) {
            // Each wavelength's taps along u and v at the sub-samples (shared by every node).
            let taps: Vec<_> = chunk
                .iter()
                .map(|&l| {
                    let lambda = self.spectral.lambda_um[l];
                    let columns = self.ax.taps(lambda, s, px).iter().map(|taps| Run::of(taps, px)).collect();
                    (columns, self.ay.taps(lambda, s, py))
                })
                .collect();
            planes.par_iter_mut().zip(&ws).for_each(|(plane, &w)| self.coherent_node(plane, w, chunk, &taps));
            for _ in chunk {
                Self::tick(progress, &done, offset, total);
            }
        }
        let stride = self.nodes * channels;
        let mut data = vec![0.0; nu * nv * stride];
        for (c, plane) in planes.iter().enumerate() {
            for (t, v) in plane.chunks_exact(channels).enumerate() {
                data[t * stride + c * channels..][..channels].copy_from_slice(v);
            }
        }
        NodeValues { nodes: self.nodes, data }
    }

    /// [`Self::coherent`]'s work for one node in w and one batch of wavelengths (`chunk`, with each one's taps along
    /// u and v at the sub-samples): their colour added into the node's `plane` of texels, row by row.
    fn coherent_node(&self, plane: &mut [f64], w: f64, chunk: &[usize], taps: &[LambdaTaps]) {
        let (nu, nv, s) = (self.grid.nu, self.grid.nv, self.subsamples);
        let channels = self.spectral.channels;
        let share = 1.0 / (s * s) as f64;
        let q: Vec<Vec<Option<Vec<Complex64>>>> =
            chunk.iter().zip(taps).map(|(&l, taps)| self.sums_along_u(w, self.spectral.lambda_um[l], taps)).collect();
        // P along one sub-sample row; Σ|P|² over a texel row's s×s sub-samples at one wavelength; the
        // batch's colour in that texel row.
        let mut p = vec![Complex64::default(); nu * s];
        let mut texels = vec![0.0; nu];
        let mut colour = vec![0.0; nu * channels];
        for row in 0..nv {
            let mut touched = false;
            for ((&l, (_, rows)), q) in chunk.iter().zip(taps).zip(&q) {
                let mut any = false;
                for taps in &rows[row * s..(row + 1) * s] {
                    let mut live = taps.iter().filter_map(|&(k, g)| q[k].as_ref().map(|line| (line, g)));
                    let Some((line, g)) = live.next() else { continue };
                    for (p, &a) in p.iter_mut().zip(line) {
                        *p = a * g;
                    }
                    for (line, g) in live {
                        for (p, &a) in p.iter_mut().zip(line) {
                            *p += a * g;
                        }
                    }
                    for (sum, p) in texels.iter_mut().zip(p.chunks_exact(s)) {
                        *sum += p.iter().map(|p| p.norm_sqr()).sum::<f64>();
                    }
                    any = true;
                }
                if any {
                    let weight: Vec<f64> = self.spectral.at(l).iter().map(|c| c * share).collect();
                    for (texel, sum) in colour.chunks_exact_mut(channels).zip(&mut texels) {
                        for (t, w) in texel.iter_mut().zip(&weight) {
                            *t += w * *sum;
                        }
                        *sum = 0.0;
                    }
                    touched = true;
                }
            }
            if touched {
                for (dst, c) in plane[row * nu * channels..][..nu * channels].iter_mut().zip(&mut colour) {
                    *dst += *c;
                    *c = 0.0;
                }
            }
        }
    }

    /// Per row of the spectrum at node `w` and wavelength `lambda` (µm) that is read and carries anything
    /// ([`live`]), its sums along u at every sub-sample column of `columns` (zero where the lookup is out of band);
    /// None for the others.
    fn sums_along_u(&self, w: f64, lambda: f64, (columns, rows): &LambdaTaps) -> Vec<Option<Vec<Complex64>>> {
        let (px, py) = (self.cell.px, self.cell.py);
        let kappa = 2.0 * std::f64::consts::PI * w / lambda;
        // The cells some sub-sample column's run reads, and the rows some sub-sample row's taps read (those of the
        // table's u and v at this wavelength: a quarter to a little over half of a 1000² patch's for a sphere's): the
        // spectrum is transformed along v, and summed along u, at those alone.
        let mut read = vec![false; px];
        columns.iter().for_each(|run| (run.start..run.start + run.weights.len()).for_each(|k| read[k % px] = true));
        let read_columns: Vec<usize> = (0..px).filter(|&k| read[k]).collect();
        let a = self.cell.amplitudes_at(kappa, Some(&read_columns), &mut Vec::new());
        let mut read = vec![false; py];
        rows.iter().flatten().for_each(|&(k, _)| read[k] = true);
        // The line twice over: every column's taps a run of it, even where they wrap.
        let mut doubled = vec![Complex64::default(); 2 * px];
        (0..py)
            .map(|r| {
                let line = &a[r * px..][..px];
                (read[r] && live(read_columns.iter().map(|&k| line[k]))).then(|| {
                    doubled[..px].copy_from_slice(line);
                    doubled[px..].copy_from_slice(line);
                    columns.iter().map(|run| run.sum(&doubled)).collect()
                })
            })
            .collect()
    }
}

impl<'a> Pass<'a> {
    /// The pass that builds `plan`'s table: its grid, its nodes in w, its wavelength step.
    fn new(hf: &HeightField, plan: &TablePlan, cell: &'a Cell) -> Self {
        let spectral = Spectral::of_plan(plan);
        Self::of_weights(hf, plan, cell, Weights::of(std::slice::from_ref(&spectral)).expect("one band"))
    }

    /// The pass of `plan` with the channels of `weights` (one band or several).
    fn of_weights(hf: &HeightField, plan: &TablePlan, cell: &'a Cell, weights: Weights) -> Self {
        let (grid, point) = (plan.grid, plan.point);
        let (lx, ly) = hf.size_um();
        let axis = |origin, count, length, sigma, pixels, stride, radius| Axis {
            origin,
            texel: grid.texel,
            count,
            length,
            sigma,
            pixels,
            stride,
            radius,
        };
        let w = &plan.window;
        Self {
            grid,
            nodes: plan.nodes.count,
            spectral: weights,
            cell,
            ax: axis(grid.u0, grid.nu, lx, w.sigma_x, hf.nx, cell.tx, w.radius_x),
            ay: axis(grid.v0, grid.nv, ly, w.sigma_y, hf.ny, cell.ty, w.radius_y),
            point,
            subsamples: plan.subsamples(),
        }
    }

    fn run(&self, lattice: bool, progress: Option<Progress<'_>>) -> NodeValues {
        let total = self.spectral.lambda_um.len();
        if lattice {
            self.lattice(progress, 0, total)
        } else {
            self.coherent(progress, 0, total)
        }
    }
}

/// How `plan`'s table is built, for its report: the path and what a texel holds (its segments share the grid, so
/// their sub-samples too).
fn path_report(plan: &TablePlan) -> String {
    let subsamples = plan.subsamples();
    format!(
        "{} path, {}{}",
        if plan.lattice { "lattice" } else { "coherent" },
        if plan.point { "texel-centre values" } else { "texel averages" },
        if subsamples > 1 { format!(" of {subsamples}×{subsamples} sub-samples") } else { String::new() },
    )
}

/// Builds the table `plan` describes for `hf`: node values at `plan.nodes` nodes in w, turned into Chebyshev
/// coefficients and certified (`crate::physics::baked::degree::certify`), the degree kept the certificate's.
/// `progress(done, total)` counts wavelengths.
/// A table of several segments of w is built segment after segment, each as a table of its own over its interval
/// (the terms it may keep are what fits in memory beside the others), and then joined
/// ([`BakedTable::from_segments`]); `progress` then counts every segment's wavelengths.
pub fn build(hf: &HeightField, plan: &TablePlan, progress: Option<Progress<'_>>) -> Result<BakedTable> {
    let cell = Cell::new(hf, plan.cell);
    let segments = plan.grid.segments;
    let mut parts = Vec::with_capacity(segments);
    let report = format!(
        "{}{}",
        path_report(plan),
        if segments > 1 { format!(", {segments} segments of w") } else { String::new() },
    );
    for segment in &plan.segments {
        let one = plan.with_segment(segment);
        let pass = Pass::new(hf, &one, &cell);
        let total = pass.spectral.lambda_um.len();
        let offset = parts.len() * total;
        let shifted = |done: usize, _: usize| {
            if let Some(p) = progress {
                p(offset + done, total * segments)
            }
        };
        let mut values = pass.run(one.lattice, Some(&shifted));
        let fit = degree::terms_that_fit(&plan.grid, one.nodes.count);
        let certificate = degree::certify(&mut values.data, fit, &one.nodes, one.tolerance)?;
        parts.push(BakedTable::from_coefficients(one.grid, &values.data, 3 * values.nodes, certificate, String::new()));
    }
    if segments == 1 {
        let mut table = parts.pop().expect("one segment");
        table.report = report;
        return Ok(table);
    }
    Ok(BakedTable::from_segments(plan.grid, parts, report))
}

/// Builds the tables of `plans`, which differ only in their light (the spectral bands of the environment's moments:
/// `light::prefilter::basis`), in one pass: every wavelength's |P|² — the FFTs and the windowed sums, nearly all
/// of a build — is computed once and weighted for each band. Each table is then certified on its own values, as
/// [`build`] would; a table from here equals [`build`]'s for its plan to rounding (the sums' order is the same).
/// Plans that cannot share a pass (several segments of w, different grids, nodes or wavelengths) are built one by
/// one.
pub fn build_bands(hf: &HeightField, plans: &[TablePlan]) -> Result<Vec<BakedTable>> {
    let Some(first) = plans.first() else { return Ok(Vec::new()) };
    let alike = |p: &TablePlan| {
        p.segments.len() == 1
            && p.grid == first.grid
            && p.nodes.count == first.nodes.count
            && p.lattice == first.lattice
            && p.point == first.point
            && p.cell == first.cell
            && p.window == first.window
            && p.lambda_step_nm == first.lambda_step_nm
            && p.mass_only == first.mass_only
            && p.lobe_width == first.lobe_width
    };
    let spectrals: Vec<Spectral> = plans.iter().map(Spectral::of_plan).collect();
    let weights = Weights::of(&spectrals);
    let (Some(weights), true) = (weights, plans.iter().all(alike)) else {
        return plans.iter().map(|p| build(hf, p, None)).collect();
    };
    let cell = Cell::new(hf, first.cell);
    let one = first.with_segment(&first.segments[0]);
    let pass = Pass::of_weights(hf, &one, &cell, weights);
    let values = pass.run(one.lattice, None);
    let (nodes, channels) = (values.nodes, pass.spectral.channels);
    let texels = values.data.len() / (nodes * channels);
    let report = format!("{}, with {} other band(s) in one pass", path_report(first), plans.len() - 1);
    plans
        .iter()
        .enumerate()
        .map(|(b, plan)| {
            // Band b's X, Y, Z at every node of every texel, in a single band's layout.
            let mut data = Vec::with_capacity(texels * nodes * 3);
            for t in 0..texels {
                for c in 0..nodes {
                    let at = t * nodes * channels + c * channels + 3 * b;
                    data.extend_from_slice(&values.data[at..at + 3]);
                }
            }
            let one = plan.with_segment(&plan.segments[0]);
            let fit = degree::terms_that_fit(&plan.grid, one.nodes.count);
            let certificate = degree::certify(&mut data, fit, &one.nodes, one.tolerance)?;
            Ok(BakedTable::from_coefficients(one.grid, &data, 3 * nodes, certificate, report.clone()))
        })
        .collect()
}
