//! Light from a whole environment integrated against the diffraction BRDF (model.md §3.10, which derives it): a
//! pixel's radiance towards ω_r as ∫∫ ρ·K·L(ω_i)/cos θ_i du dv over the table's (u, v), estimated by multiple
//! importance sampling (the balance heuristic) over three strategies — the baked table's texels by their colour's
//! envelope with a tent within each ([`TableProposal`]), a cosine-weighted floor ([`BRDF_FLOOR`] of the BRDF's
//! samples), and the environment's texels by luminance × solid angle ([`EnvLight`]) — each drawing its cells by
//! inverting 2D CDFs ([`Distribution2D`]) at the points of a shifted R2 sequence ([`r2`]).
//!
//! [`Integrator::pass`] is one estimate. It runs on the GPU with the baked table as ρ (`glsl/map_env.comp.glsl`,
//! whose sampling functions are this module's twins: ARCHITECTURE.md, "Twins") and on the CPU with the exact BRDF
//! (`reference::exact_env::ExactEnv`), the light then upsampled to spectra in `light::prefilter::basis`.

use glam::{DMat3, DVec3};

use crate::error::{Error, Result};
use crate::light::environment::{texel_solid_angle, EnvironmentMap};
use crate::physics::baked::BakedTable;

/// The widest environment the lighting samples: a wider map is box-averaged (by solid angle) down to it (its
/// texels are then 0.18° wide, finer than the lobes of a 65 µm coherence length).
pub const MAX_LIGHTING_WIDTH: u32 = 2048;
/// The widest texels an environment-lit map's table gets, in (u, v): on a flat mirror in a white furnace, texels of
/// 0.036 spread the lobe over angles where the gain and cos θ_i differ and the map read 1.3 % bright at 58°; at
/// 0.0058 it is within 0.1 % (tests/gpu/env_map.rs).
pub const ENV_TABLE_FOOTPRINT: f64 = 0.01;
/// Samples per pixel the reference takes (`map --env-reference`).
pub const REFERENCE_SAMPLES: u32 = 8192;
/// Samples per pixel unless a command says otherwise (half from each strategy).
pub const DEFAULT_ENV_SAMPLES: u32 = 256;
/// The most samples per pixel a command accepts.
pub const MAX_ENV_SAMPLES: u32 = 1 << 16;
/// The share of the BRDF strategy's samples drawn cosine-weighted rather than from the table.
pub const BRDF_FLOOR: f64 = 0.1;

/// How many of `n_brdf` samples are drawn cosine-weighted (a fixed count, not a coin per sample: a random split
/// would add the binomial spread of the table's share, 3 % at 128 samples, to every pixel).
pub fn floor_samples(n_brdf: u32) -> u32 {
    (f64::from(n_brdf) * BRDF_FLOOR).round() as u32
}

/// A piecewise-constant density over a grid of `nu`×`nv` cells drawn by inversion (PBRT's `Distribution2D`): a
/// row from the marginal CDF, a cell from the row's conditional CDF, the leftover fractions placing the point
/// within the cell, so that stratified input stays stratified over the cells. As the GPU reads it: one f32 array
/// (the marginal's nv + 1 values, then each row's nu + 1) and each cell's density over its measure, computed in
/// f32 from those same values so that both sides draw and weigh alike.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution2D {
    pub nu: usize,
    pub nv: usize,
    pub cdf: Vec<f32>,
    pub density: Vec<f32>,
}

impl Distribution2D {
    /// The GPU's buffer: the CDF, then the densities.
    pub fn gpu_words(&self) -> Vec<f32> {
        self.cdf.iter().chain(&self.density).copied().collect()
    }

    /// The distribution of `weights` (row-major, non-negative), each cell's density its probability over
    /// `measure(i)`; None when every weight is 0.
    pub fn new(weights: &[f64], nu: usize, nv: usize, measure: impl Fn(usize) -> f64) -> Option<Self> {
        let rows: Vec<f64> = (0..nv).map(|r| weights[r * nu..][..nu].iter().sum()).collect();
        let total: f64 = rows.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let mut cdf = Vec::with_capacity(nv + 1 + nv * (nu + 1));
        let running = |values: &mut dyn Iterator<Item = f64>, sum: f64, n: usize, out: &mut Vec<f32>| {
            let mut acc = 0.0;
            out.push(0.0);
            for (i, v) in values.enumerate() {
                // An empty row is drawn never; give it an even CDF all the same.
                acc += if sum > 0.0 { v / sum } else { 1.0 / n as f64 };
                out.push(if i + 1 == n { 1.0 } else { acc.min(1.0) as f32 });
            }
        };
        running(&mut rows.iter().copied(), total, nv, &mut cdf);
        for (r, &row) in rows.iter().enumerate() {
            running(&mut weights[r * nu..][..nu].iter().copied(), row, nu, &mut cdf);
        }
        let mut d = Self { nu, nv, cdf, density: Vec::new() };
        d.density = (0..nu * nv).map(|i| d.probability(i % nu, i / nu) / measure(i) as f32).collect();
        Some(d)
    }

    fn marginal(&self) -> &[f32] {
        &self.cdf[..=self.nv]
    }

    fn conditional(&self, row: usize) -> &[f32] {
        &self.cdf[self.nv + 1 + row * (self.nu + 1)..][..=self.nu]
    }

    /// The probability of cell (col, row), in f32 as the GPU has it.
    fn probability(&self, col: usize, row: usize) -> f32 {
        let (m, c) = (self.marginal(), self.conditional(row));
        (m[row + 1] - m[row]) * (c[col + 1] - c[col])
    }

    /// The cell (col, row) `xi` falls in and where in it (fractions in [0, 1)).
    pub fn sample(&self, xi: [f64; 2]) -> (usize, usize, f64, f64) {
        let (row, fy) = invert(self.marginal(), xi[1]);
        let (col, fx) = invert(self.conditional(row), xi[0]);
        (col, row, fx, fy)
    }
}

/// The last index i with cdf[i] ≤ x (x in [0, 1): never a zero-width bin) and x's place within [cdf[i], cdf[i+1]).
fn invert(cdf: &[f32], x: f64) -> (usize, f64) {
    let x32 = x as f32;
    let i = cdf.partition_point(|&c| c <= x32).clamp(1, cdf.len() - 1) - 1;
    let (lo, hi) = (f64::from(cdf[i]), f64::from(cdf[i + 1]));
    (i, if hi > lo { ((x - lo) / (hi - lo)).clamp(0.0, 1.0 - f64::EPSILON) } else { 0.5 })
}

/// The inverse CDF of the tent on [−1, 1] (density 1 − |t|): a texel's uniform fraction to an offset in texels.
pub fn tent(f: f64) -> f64 {
    if f < 0.5 {
        (2.0 * f).sqrt() - 1.0
    } else {
        1.0 - (2.0 * (1.0 - f)).sqrt()
    }
}

/// The plastic number's R2 sequence (Roberts 2018) in 32-bit fixed point: point k of a 2D low-discrepancy
/// sequence is frac(shift + k·(1/g, 1/g²)), which stays evenly spread for any count. Integer arithmetic, so that
/// the GPU's points are the CPU's.
pub const R2_STEP: [u32; 2] = [crate::gpu::interface::R2_STEP_X, crate::gpu::interface::R2_STEP_Y];

/// Point `k` of the R2 sequence shifted by `shift` (Cranley–Patterson rotation), in [0, 1)².
pub fn r2(k: u32, shift: [u32; 2]) -> [f64; 2] {
    let at = |d: usize| f64::from(shift[d].wrapping_add(k.wrapping_mul(R2_STEP[d])) >> 8) / f64::from(1u32 << 24);
    [at(0), at(1)]
}

/// A direction of the patch frame (z the normal) in the environment's (+y up): the map's zenith is the normal,
/// its azimuth 0 (+z) the patch's −y and 90° (+x) the patch's +x.
pub fn env_of_patch(omega: DVec3) -> DVec3 {
    DVec3::new(omega.x, omega.z, -omega.y)
}

/// The inverse of [`env_of_patch`].
pub fn patch_of_env(d: DVec3) -> DVec3 {
    DVec3::new(d.x, -d.z, d.y)
}

/// An environment prepared for sampling: its radiance (intensity applied) and a distribution over its texels.
#[derive(Clone, Debug)]
pub struct EnvLight {
    pub width: u32,
    pub height: u32,
    /// Linear sRGB radiance per texel, rows top first (alpha 0), as the GPU reads it.
    pub radiance: Vec<[f32; 4]>,
    /// Texels drawn by luminance × solid angle; densities per steradian.
    pub distribution: Distribution2D,
    /// Radians the map is turned about its up axis (a texel at azimuth φ lights from φ + rotation).
    pub rotation: f64,
}

impl EnvLight {
    /// `map` times `intensity`, turned by `rotation_deg`, box-averaged down to [`MAX_LIGHTING_WIDTH`]; refused where
    /// it gives no light.
    pub fn new(map: &EnvironmentMap, intensity: f64, rotation_deg: f64) -> Result<Self> {
        map.check_scale(intensity, rotation_deg).map_err(|e| Error::setting("env_intensity", e))?;
        let mut map = std::borrow::Cow::Borrowed(map);
        while map.width > MAX_LIGHTING_WIDTH {
            map = std::borrow::Cow::Owned(halve(&map));
        }
        let (width, height) = (map.width, map.height);
        let radiance: Vec<[f32; 4]> = map
            .rgb
            .iter()
            .map(|&[r, g, b]| [r, g, b].map(|c| (f64::from(c) * intensity) as f32))
            .map(|[r, g, b]| [r, g, b, 0.0])
            .collect();
        let solid_angle = |i: usize| texel_solid_angle(i as u32 / width, width);
        let weights: Vec<f64> = radiance
            .iter()
            .enumerate()
            .map(|(i, t)| crate::physics::spectrum::luminance([t[0], t[1], t[2]]).max(0.0) * solid_angle(i))
            .collect();
        let distribution = Distribution2D::new(&weights, width as usize, height as usize, solid_angle)
            .ok_or_else(|| Error::Light("the environment gives no light (every texel is black)".into()))?;
        Ok(Self { width, height, radiance, distribution, rotation: rotation_deg.to_radians() })
    }

    /// The texel lighting from `d` (unit, the environment's frame).
    pub fn texel_of(&self, d: DVec3) -> usize {
        let tau = std::f64::consts::TAU;
        let azimuth = (d.x.atan2(d.z) - self.rotation).rem_euclid(tau);
        let x = (((azimuth / tau + 0.5) * f64::from(self.width)) as u32) % self.width;
        let elevation = d.y.clamp(-1.0, 1.0).asin();
        let y = (((0.5 - elevation / std::f64::consts::PI) * f64::from(self.height)) as u32).min(self.height - 1);
        (y * self.width + x) as usize
    }

    /// Radiance (linear sRGB) from `d` and the density (sr⁻¹) with which [`Self::sample`] draws it.
    pub fn radiance(&self, d: DVec3) -> (DVec3, f64) {
        let i = self.texel_of(d);
        let t = self.radiance[i];
        (DVec3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2])), f64::from(self.distribution.density[i]))
    }

    /// A direction (the environment's frame) drawn by luminance × solid angle from a point of [0, 1)², uniform
    /// over its texel in (azimuth, sin elevation).
    pub fn sample(&self, xi: [f64; 2]) -> DVec3 {
        let (x, y, fx, fy) = self.distribution.sample(xi);
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let azimuth = ((x as f64 + fx) / w - 0.5) * std::f64::consts::TAU + self.rotation;
        let sin_e = |row: f64| (std::f64::consts::FRAC_PI_2 - row / h * std::f64::consts::PI).sin();
        let (top, bottom) = (sin_e(y as f64), sin_e(y as f64 + 1.0));
        let s = top + fy * (bottom - top);
        let c = (1.0 - s * s).max(0.0).sqrt();
        DVec3::new(c * azimuth.sin(), s, c * azimuth.cos())
    }
}

/// `map` at half its width, each texel the solid-angle-weighted mean of the four it covers.
fn halve(map: &EnvironmentMap) -> EnvironmentMap {
    let (w, h) = (map.width / 2, map.height / 2);
    let mut rgb = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        let (a, b) = (texel_solid_angle(2 * y, map.width), texel_solid_angle(2 * y + 1, map.width));
        for x in 0..w {
            let mut sum = [0.0f64; 3];
            for (row, weight) in [(2 * y, a), (2 * y + 1, b)] {
                for col in [2 * x, 2 * x + 1] {
                    let t = map.rgb[(row * map.width + col) as usize];
                    for c in 0..3 {
                        sum[c] += f64::from(t[c]) * weight;
                    }
                }
            }
            rgb.push(sum.map(|s| (s / (2.0 * (a + b))) as f32));
        }
    }
    EnvironmentMap { width: w, height: h, rgb }
}

/// The BRDF strategy's table density: a texel of the baked table drawn by its colour's envelope over w, then a tent
/// about its centre (the bilinear reconstruction of the envelope).
#[derive(Clone, Debug)]
pub struct TableProposal {
    pub u0: f64,
    pub v0: f64,
    pub texel: f64,
    pub nu: usize,
    pub nv: usize,
    /// Texels drawn by envelope × area; densities per unit of (u, v) area.
    pub distribution: Distribution2D,
}

impl TableProposal {
    /// The proposal of `table`'s finest level; refused where the table is black everywhere.
    pub fn new(table: &BakedTable) -> Result<Self> {
        let g = &table.grid;
        let level = &table.levels[0];
        let weights: Vec<f64> =
            (0..level.width * level.height).map(|i| table.texel_coefficients(level, i).map(f64::abs).sum()).collect();
        let area = g.texel * g.texel;
        let (nu, nv) = (level.width, level.height);
        let distribution = Distribution2D::new(&weights, nu, nv, |_| area)
            .ok_or_else(|| Error::Light("the baked table is black everywhere: nothing diffracts".into()))?;
        Ok(Self { u0: g.u0, v0: g.v0, texel: g.texel, nu, nv, distribution })
    }

    /// (u, v) drawn from a point of [0, 1)²: a texel, then a tent of one texel either way about its centre.
    pub fn sample(&self, xi: [f64; 2]) -> (f64, f64) {
        let (a, b, fx, fy) = self.distribution.sample(xi);
        let u = self.u0 + (a as f64 + 0.5 + tent(fx)) * self.texel;
        let v = self.v0 + (b as f64 + 0.5 + tent(fy)) * self.texel;
        (u, v)
    }

    /// The density of [`Self::sample`] at (u, v): the texels' densities interpolated bilinearly, 0 beyond the edge.
    pub fn density(&self, u: f64, v: f64) -> f64 {
        let fx = (u - self.u0) / self.texel - 0.5;
        let fy = (v - self.v0) / self.texel - 0.5;
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let at = |x: f64, y: f64| {
            if x < 0.0 || y < 0.0 || x >= self.nu as f64 || y >= self.nv as f64 {
                0.0
            } else {
                f64::from(self.distribution.density[y as usize * self.nu + x as usize])
            }
        };
        let top = at(x0, y0) * (1.0 - tx) + at(x0 + 1.0, y0) * tx;
        let bottom = at(x0, y0 + 1.0) * (1.0 - tx) + at(x0 + 1.0, y0 + 1.0) * tx;
        top * (1.0 - ty) + bottom * ty
    }
}

/// K of the module's note, sr⁻¹ per unit ρ: the diffraction's gain in physical units over the sun's solid angle
/// (the gain carries Ω_sun for a directional sun; an environment brings its own solid angles).
pub fn env_gain(sampling: &crate::physics::spectrum::Sampling, coherence_um: f64) -> Result<f64> {
    if !sampling.illuminant.physical {
        return Err(Error::Light("light from an environment needs the illuminant in physical units".into()));
    }
    Ok(crate::physics::spectrum::diffraction_gain(sampling, coherence_um) / crate::physics::optics::SUN_SOLID_ANGLE)
}

/// A pixel's estimate: the mean radiance (linear sRGB, the environment's units) and its standard error per channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    pub rgb: DVec3,
    pub std_error: DVec3,
}

/// The MIS estimator of the module's note.
#[derive(Clone, Copy)]
pub struct Integrator<'a> {
    pub env: &'a EnvLight,
    pub proposal: &'a TableProposal,
    /// Samples per pixel from the BRDF's strategy and from the environment's.
    pub n_brdf: u32,
    pub n_env: u32,
    /// The patch frame in the environment's (columns: the patch's x, y and normal; [`MAP_FRAME`] for a BRDF map).
    pub frame: DMat3,
}

/// A BRDF map's patch frame in the environment's ([`env_of_patch`]): the zenith is the normal.
pub const MAP_FRAME: DMat3 = DMat3::from_cols(DVec3::X, DVec3::NEG_Z, DVec3::Y);

impl Integrator<'_> {
    /// The BRDF strategies' densities in (u, v) for the view `omega_r` (patch frame), each times its samples:
    /// the table's and the cosine-weighted floor's.
    pub fn brdf_density(&self, u: f64, v: f64, omega_r: DVec3) -> f64 {
        let (x, y) = (-u - omega_r.x, -v - omega_r.y);
        let disc = if x * x + y * y < 1.0 { std::f64::consts::FRAC_1_PI } else { 0.0 };
        let floor = floor_samples(self.n_brdf);
        f64::from(self.n_brdf - floor) * self.proposal.density(u, v) + f64::from(floor) * disc
    }

    /// One sample's contribution for light from `omega_i` (patch frame, above the surface), `rho` the BRDF there
    /// as a colour matrix (the environment's linear sRGB radiance → the reflected linear sRGB, the gain K in it).
    fn contribution(&self, omega_i: DVec3, omega_r: DVec3, rho: DMat3) -> DVec3 {
        let (radiance, p_env) = self.env.radiance(self.frame * omega_i);
        let p_brdf = self.brdf_density(-omega_i.x - omega_r.x, -omega_i.y - omega_r.y, omega_r);
        let denominator = p_brdf * omega_i.z + f64::from(self.n_env) * p_env;
        if denominator <= 0.0 {
            return DVec3::ZERO;
        }
        rho * radiance / denominator
    }

    /// The radiance towards `omega_r` (patch frame), `rho(ω_i, ω_r)` the BRDF's colour matrix: each strategy's
    /// samples are its R2 points shifted by `shifts` (the GPU's pass, which draws its shifts per pixel).
    pub fn pass(&self, omega_r: DVec3, rho: &impl Fn(DVec3, DVec3) -> DMat3, shifts: [[u32; 2]; 3]) -> DVec3 {
        let floor = floor_samples(self.n_brdf);
        let mut total = DVec3::ZERO;
        let strategies =
            [(Strategy::Floor, floor), (Strategy::Table, self.n_brdf - floor), (Strategy::Env, self.n_env)];
        for ((strategy, n), shift) in strategies.into_iter().zip(shifts) {
            for k in 0..n {
                let xi = r2(k, shift);
                let omega_i = match strategy {
                    Strategy::Env => Some(self.frame.transpose() * self.env.sample(xi)).filter(|w| w.z > 0.0),
                    Strategy::Floor => {
                        // Uniform over the unit disc of ω_i.xy.
                        let (r, phi) = (xi[0].sqrt(), std::f64::consts::TAU * xi[1]);
                        above(r * phi.cos(), r * phi.sin())
                    }
                    Strategy::Table => {
                        let (u, v) = self.proposal.sample(xi);
                        above(-u - omega_r.x, -v - omega_r.y)
                    }
                };
                if let Some(omega_i) = omega_i {
                    total += self.contribution(omega_i, omega_r, rho(omega_i, omega_r));
                }
            }
        }
        total
    }

    /// [`Self::pass`] repeated with `replicates` independent shifts drawn from `seed` (randomised quasi-Monte
    /// Carlo): their mean, and its standard error from their spread.
    pub fn pixel(&self, omega_r: DVec3, rho: impl Fn(DVec3, DVec3) -> DMat3, seed: u64, replicates: u32) -> Estimate {
        let mut rng = fastrand::Rng::with_seed(seed);
        let mut word = || rng.u32(..);
        let passes: Vec<DVec3> = (0..replicates.max(2))
            .map(|_| {
                let shifts = std::array::from_fn(|_| [word(), word()]);
                self.pass(omega_r, &rho, shifts)
            })
            .collect();
        let n = passes.len() as f64;
        let mean = passes.iter().sum::<DVec3>() / n;
        let variance = passes.iter().map(|p| (*p - mean) * (*p - mean)).sum::<DVec3>() / (n - 1.0);
        Estimate { rgb: mean, std_error: (variance / n).powf(0.5) }
    }
}

/// The direction above the surface whose (x, y) these are; None outside the unit disc.
fn above(x: f64, y: f64) -> Option<DVec3> {
    let r2 = x * x + y * y;
    (r2 < 1.0).then(|| DVec3::new(x, y, (1.0 - r2).sqrt()))
}

/// ω_r of BRDF-map pixel (x, y) of a `size`-pixel map (`map_view` in glsl/include/map_view.glsl); None outside the
/// disk.
pub fn map_view(size: u32, x: u32, y: u32) -> Option<DVec3> {
    let half = f64::from(size) / 2.0;
    let (px, py) = ((f64::from(x) + 0.5 - half) / half, -((f64::from(y) + 0.5 - half) / half));
    let r2 = px * px + py * py;
    (r2 < 1.0).then(|| DVec3::new(px, py, (1.0 - r2).sqrt()))
}

/// The three ways a sample is drawn.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Strategy {
    Floor,
    Table,
    Env,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distribution_draws_each_cell_by_its_weight() {
        // 2 × 2 cells, one empty.
        let weights = [1.0, 0.0, 3.0, 6.0];
        let d = Distribution2D::new(&weights, 2, 2, |_| 2.0).unwrap();
        let n = 4096;
        let mut counts = [0usize; 4];
        for k in 0..n {
            let (c, r, fx, fy) = d.sample(r2(k, [12345, 678]));
            assert!((0.0..1.0).contains(&fx) && (0.0..1.0).contains(&fy));
            counts[r * 2 + c] += 1;
        }
        // Stratified: each share within a few points of n.
        for (c, w) in counts.iter().zip(weights) {
            assert!((*c as f64 / f64::from(n) - w / 10.0).abs() < 2e-3, "{counts:?}");
        }
        assert!((f64::from(d.density[3]) - 0.3).abs() < 1e-7);
        assert!(Distribution2D::new(&[0.0, 0.0], 2, 1, |_| 1.0).is_none());
        assert_eq!(tent(0.5), 0.0);
        assert!((tent(0.0) + 1.0).abs() < 1e-12 && (tent(1.0 - 1e-12) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn directions_and_texels_agree_with_the_map_layout() {
        let map = EnvironmentMap { width: 16, height: 8, rgb: vec![[1.0; 3]; 128] };
        let env = EnvLight::new(&map, 1.0, 30.0).unwrap();
        // (Point 0 is the unshifted corner, the zenith itself, where the azimuth is undefined.)
        for k in 1..1000 {
            let xi = r2(k, [99, 7]);
            let d = env.sample(xi);
            assert!((d.length() - 1.0).abs() < 1e-12);
            // Drawn from the texel the lookup finds again; a uniform map has density 1/4π.
            let (x, y, _, _) = env.distribution.sample(xi);
            assert_eq!(env.texel_of(d), y * 16 + x);
            assert!((env.radiance(d).1 - 1.0 / (4.0 * std::f64::consts::PI)).abs() < 1e-6);
        }
        let z = DVec3::new(0.3, -0.4, 0.866_025_403_784_438_6);
        assert!((patch_of_env(env_of_patch(z)) - z).length() < 1e-15);
        assert!((env_of_patch(DVec3::Z) - DVec3::Y).length() < 1e-15);
    }

    #[test]
    fn halving_keeps_the_light() {
        let mut rng = fastrand::Rng::with_seed(11);
        let rgb = (0..64 * 32).map(|_| [rng.f32(), 1.0, 2.0]).collect();
        let map = EnvironmentMap { width: 64, height: 32, rgb };
        let power = |m: &EnvironmentMap| -> f64 {
            (0..m.rgb.len()).map(|i| f64::from(m.rgb[i][0]) * texel_solid_angle(i as u32 / m.width, m.width)).sum()
        };
        let half = halve(&map);
        assert_eq!((half.width, half.height), (32, 16));
        assert!((power(&half) / power(&map) - 1.0).abs() < 1e-6);
    }
}
