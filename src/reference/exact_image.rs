//! The exact reference image that defines "error" for every other setting, and the error metrics. The same BRDF as
//! the shaders' FLSS (`Reference::flss_xyz`) in f64 with every accuracy setting pushed to a stated bound: the Taylor
//! order whose truncation bound is ≤ [`REFERENCE_TOLERANCE`] (or the exact DFT, for structures so deep that the f64
//! series would round by more than [`MAX_REFERENCE_ROUNDING`]), the full window, 1 nm wavelength steps (their
//! quadrature error estimated in the same run against 0.5 nm: [`ReferenceImage::quadrature`]). A large image's
//! reference may be evaluated at random pixels ([`ReferenceJob::keep_random_pixels`]), its errors then estimates
//! with a standard error.
//!
//! Errors are measured as displayed: XYZ (relative to a D65 mirror) scaled by 2^EV, CIELAB against the D65 white
//! with Y = 1 (no clipping), CIEDE2000; only pixels that show the surface count.

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::gpu::interface::MAX_LAMPS;
use crate::io::cache::KeyHash;
use crate::io::progress::Progress;
use crate::physics::coherence::CoherenceWindow;
use crate::physics::colour::linear_srgb_to_xyz;
use crate::physics::colour::{ciede2000, xyz_to_lab};
use crate::physics::exact::{window_gain, Method, Reference};
use crate::physics::heightfield::HeightField;
use crate::physics::illuminant::Illuminant;
use crate::physics::spectrum::{diffraction_gain, Sampling};
use crate::physics::taylor::{HeightStats, TaylorPlan};

/// The reference's bound on the Taylor amplitude error |P − P_N| (a flat mirror has |P| = 1 at specular).
pub const REFERENCE_TOLERANCE: f64 = 1e-10;
/// The largest f64 rounding estimate (amplitude) the reference accepts: below one part in 10⁶ of a mirror's
/// amplitude, far under what a colour difference can show.
pub const MAX_REFERENCE_ROUNDING: f64 = 1e-6;
/// The reference's wavelength step, nm.
pub const REFERENCE_STEP_NM: f64 = 1.0;
/// The finer step its quadrature error is estimated against, nm.
pub const CHECK_STEP_NM: f64 = 0.5;
/// How many pixels, spread over those the surface covers, the quadrature error is estimated on.
const CHECK_PIXELS: usize = 64;
/// Bumped whenever the reference's definition or its cache format changes: cached images of other versions are
/// recomputed. (2: XYZ stored only for the pixels that count; 3: a pixel's diffraction weighted by the sun's
/// visible share; 4: exact Fresnel, not Schlick's; 5: the lamps' diffraction; 6: widened by their coherence.)
const CACHE_VERSION: u32 = 6;
/// The seed of the random pixels a sampled reference keeps (fixed: a profile repeats, and its reference caches).
pub const SAMPLE_SEED: u64 = 0x5eed_d1ff_7ac7;

/// One pixel to evaluate: patch-frame unit directions to the light and to the viewer, the material seen, the
/// weight of its diffraction (the share of the sun no shadow hides; 0 for a matte material), the lamps' directions
/// and weights, and light that does not diffract (a scene's pigment term, XYZ) added as it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelQuery {
    pub omega_i: DVec3,
    pub omega_r: DVec3,
    pub material: usize,
    pub diffracted: f64,
    /// Each lamp's patch-frame unit direction, the weight of its diffraction (its irradiance at normal incidence
    /// over the sun's, Ω_sun times the frame's unit: `Scene::unit_luminance`; zero for no lamp) and the widening
    /// of its lobes by its shorter coherence (0: none).
    pub lamps: [PixelLamp; MAX_LAMPS as usize],
    pub extra_xyz: DVec3,
}

/// A lamp as a pixel sees it ([`PixelQuery::lamps`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelLamp {
    pub omega_i: DVec3,
    pub weight: f64,
    /// The variance in (u, v) its shorter coherence widens the lobes by (`light::lamp::widening_variance`; 0: the
    /// material's own).
    pub widening: f64,
}

/// No lamp lights the pixel.
pub const NO_LAMPS: [PixelLamp; MAX_LAMPS as usize] =
    [PixelLamp { omega_i: DVec3::ZERO, weight: 0.0, widening: 0.0 }; MAX_LAMPS as usize];

impl PixelQuery {
    /// Each light that diffracts here, the sun's first (its coherence the material's).
    pub fn lights(&self) -> impl Iterator<Item = PixelLamp> + '_ {
        let sun = PixelLamp { omega_i: self.omega_i, weight: self.diffracted, widening: 0.0 };
        std::iter::once(sun).chain(self.lamps.iter().copied()).filter(|l| l.weight > 0.0)
    }
}

/// A material as the reference sees it: its height field, coherence length and the light's spectrum.
#[derive(Clone, Copy, Debug)]
pub struct ReferenceMaterial<'a> {
    pub heightfield: &'a HeightField,
    pub coherence_um: f64,
    pub illuminant: Illuminant,
}

/// A reference image: XYZ per pixel (relative to a D65 mirror) and which pixels count.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceImage {
    pub width: u32,
    pub height: u32,
    pub xyz: Vec<DVec3>,
    pub mask: Vec<bool>,
    /// What the reference used, in one line.
    pub description: String,
    /// The 1 nm vs 0.5 nm check: (pixels compared, largest ΔE₀₀ at exposure 0, largest relative XYZ difference).
    pub quadrature: (usize, f64, f64),
    /// (pixels kept, pixels covered) where only random pixels were evaluated
    /// ([`ReferenceJob::keep_random_pixels`]); None where every covered pixel was.
    pub sampled: Option<(usize, usize)>,
    /// The same pixels from a quarter of the positions (every other one along each axis: (s/2)² of the s²), where
    /// [`Self::downsample`] averaged s² ≥ 4 of them (s even): how far the reference still moves with its positions.
    pub half_positions: Option<Vec<DVec3>>,
}

/// What a reference is computed for (also its cache key).
pub struct ReferenceJob<'a> {
    pub materials: Vec<ReferenceMaterial<'a>>,
    pub width: u32,
    pub height: u32,
    /// Per pixel (rows top first): the directions, or None where no surface is seen.
    pub pixels: Vec<Option<PixelQuery>>,
}

impl ReferenceJob<'_> {
    /// The BRDF map's pixels for a light from `light` (unit, patch frame): the disk of `glsl/map.frag.glsl`.
    pub fn map_pixels(size: u32, light: DVec3) -> Vec<Option<PixelQuery>> {
        (0..size * size)
            .map(|i| {
                crate::light::sampling::map_view(size, i % size, i / size).map(|omega_r| PixelQuery {
                    omega_i: light,
                    omega_r,
                    material: 0,
                    diffracted: 1.0,
                    lamps: NO_LAMPS,
                    extra_xyz: DVec3::ZERO,
                })
            })
            .collect()
    }

    /// Keeps the queries of `count` pixels of the output image (each `samples`×`samples` positions of this
    /// finer grid), chosen at random among those the surface covers at every position, and drops the rest: only
    /// the kept pixels are evaluated, and only they count in an error. The covered pixels are shuffled by a
    /// generator seeded with [`SAMPLE_SEED`]: the same pixels on every run, and nobody's choice. Returns (kept,
    /// covered).
    pub fn keep_random_pixels(&mut self, count: usize, samples: u32) -> (usize, usize) {
        let s = samples.max(1);
        let (fine_width, w, h) = (self.width, self.width / s, self.height / s);
        let positions = move |p: u32| {
            let (x, y) = (p % w, p / w);
            (0..s * s).map(move |k| ((y * s + k / s) * fine_width + x * s + k % s) as usize)
        };
        let mut covered: Vec<u32> = (0..w * h).filter(|&p| positions(p).all(|i| self.pixels[i].is_some())).collect();
        let total = covered.len();
        if count < total {
            fastrand::Rng::with_seed(SAMPLE_SEED).shuffle(&mut covered);
            covered.truncate(count);
        }
        let mut keep = vec![false; self.pixels.len()];
        for &p in &covered {
            for i in positions(p) {
                keep[i] = true;
            }
        }
        for (q, k) in self.pixels.iter_mut().zip(keep) {
            if !k {
                *q = None;
            }
        }
        (covered.len(), total)
    }

    /// A hash of everything the image depends on.
    fn key(&self) -> u64 {
        let mut h = KeyHash::default();
        h.u64(u64::from(CACHE_VERSION));
        for m in &self.materials {
            m.heightfield.hash_into(&mut h);
            h.f64(m.coherence_um);
            m.illuminant.hash_into(&mut h);
        }
        h.u64(u64::from(self.width));
        h.u64(u64::from(self.height));
        for p in &self.pixels {
            match p {
                Some(q) => {
                    h.u64(q.material as u64);
                    h.f64(q.diffracted);
                    for lamp in &q.lamps {
                        h.f64(lamp.weight);
                        h.f64(lamp.widening);
                        h.f64(lamp.omega_i.x);
                        h.f64(lamp.omega_i.y);
                        h.f64(lamp.omega_i.z);
                    }
                    for v in [q.omega_i, q.omega_r, q.extra_xyz] {
                        h.f64(v.x);
                        h.f64(v.y);
                        h.f64(v.z);
                    }
                }
                None => h.u64(u64::MAX),
            }
        }
        h.finish()
    }

    /// Computes the image (on every core, with progress on a terminal), or reads it from `cache` where an
    /// earlier run left it; a new image is written there.
    pub fn compute(&self, cache: Option<&Path>) -> Result<ReferenceImage> {
        if self.pixels.len() != (self.width * self.height) as usize {
            return Err(Error::Invalid("reference pixels do not match the image size".into()));
        }
        if let Some(image) = cache.and_then(|dir| read_cached(dir, self)) {
            return Ok(image);
        }
        if let Some(q) = self.pixels.iter().flatten().find(|q| q.material >= self.materials.len()) {
            return Err(Error::Invalid(format!(
                "a reference pixel names material {}, which does not exist",
                q.material
            )));
        }
        let made = (0..self.materials.len()).map(|i| self.material_reference(i)).collect::<Result<Vec<_>>>()?;
        let (references, descriptions): (Vec<Reference>, Vec<String>) = made.into_iter().unzip();
        // Each material's wavelengths under its light.
        let samplings = |step: f64| -> Vec<Sampling> {
            self.materials.iter().map(|m| Sampling::visible_under(step, m.illuminant)).collect()
        };
        let (fine, check) = (samplings(REFERENCE_STEP_NM), samplings(CHECK_STEP_NM));
        // In physical units the diffraction carries the BRDF's scale (`spectrum::diffraction_gain`), as the
        // shaders' does.
        let gains = |samplings: &[Sampling]| -> Vec<f64> {
            samplings.iter().zip(&self.materials).map(|(s, m)| diffraction_gain(s, m.coherence_um)).collect()
        };
        let (fine_gains, check_gains) = (gains(&fine), gains(&check));
        let pixel = |q: &PixelQuery, samplings: &[Sampling], gains: &[f64]| {
            let (reference, sampling) = (&references[q.material], &samplings[q.material]);
            let gain = gains[q.material];
            let diffraction: DVec3 = q
                .lights()
                .map(|light| match light.widening > 0.0 {
                    true => reference.flss_xyz_widened(light.omega_i, q.omega_r, sampling, light.widening),
                    false => reference.flss_xyz(light.omega_i, q.omega_r, sampling),
                } * gain * light.weight)
                .sum();
            diffraction + q.extra_xyz
        };
        let xyz = evaluate_rows(self, |q| pixel(q, &fine, &fine_gains));
        let quadrature = quadrature_check(self, |q| pixel(q, &check, &check_gains), &xyz);
        let description = format!(
            "{}; {} nm steps (vs {} nm on {} pixels: ΔE00 ≤ {:.2e} at EV 0, relative XYZ ≤ {:.1e})",
            descriptions.join("; "),
            REFERENCE_STEP_NM,
            CHECK_STEP_NM,
            quadrature.0,
            quadrature.1,
            quadrature.2
        );
        let mask = self.pixels.iter().map(Option::is_some).collect();
        let (width, height) = (self.width, self.height);
        let image =
            ReferenceImage { width, height, xyz, mask, description, quadrature, sampled: None, half_positions: None };
        if let Some(dir) = cache {
            // A cache that cannot be written costs time, not correctness: say so and go on.
            if let Err(e) = write_cached(dir, self, &image) {
                log::warn!("could not cache the reference in {}: {e}", dir.display());
            }
        }
        Ok(image)
    }

    /// The exact reference of material `i` for the views its pixels need, and how it is computed
    /// ([`exact_reference`]).
    fn material_reference(&self, i: usize) -> Result<(Reference, String)> {
        let m = &self.materials[i];
        let w_max = self
            .pixels
            .iter()
            .flatten()
            .filter(|q| q.material == i)
            .flat_map(|q| q.lights().map(move |l| (l.omega_i.z + q.omega_r.z).abs()))
            .fold(0.0, f64::max);
        exact_reference(m.heightfield, m.coherence_um, w_max)
    }
}

/// The exact reference of `hf` under `coherence_um` for views up to |w| = `w_max`, and how it is computed: an f64
/// Taylor sum where its rounding is small enough, the exact sum of exp(i·k·w·h) elsewhere (the full window).
pub fn exact_reference(hf: &HeightField, coherence_um: f64, w_max: f64) -> Result<(Reference, String)> {
    let (lx, ly) = hf.size_um();
    let window = CoherenceWindow::new(lx, ly, coherence_um, None)?;
    let plan = TaylorPlan::new(
        crate::physics::spectrum::VISIBLE_MIN_NM * 1e-3,
        w_max.max(1e-3),
        &HeightStats::of(hf),
        window_gain(&window, hf),
        REFERENCE_TOLERANCE,
        None,
    );
    let taps = format!("full window {}×{} taps (weights ≥ 1e-17)", 2 * window.radius_x + 1, 2 * window.radius_y + 1);
    // The f64 sum cancels like the GPU's f32 one, 2⁻²⁹ less: for deep structures (k·w·h of tens) it too would lose
    // the digits the comparison needs, or need more terms than a plan allows. There the reference sums
    // exp(i·k·w·h) itself (the exact method: no series, slower by about the patch's pixel count over the terms'
    // texel reads).
    let plan = match plan {
        Ok(plan) if plan.f64_error <= MAX_REFERENCE_ROUNDING => plan,
        deep => {
            let why = match deep {
                Ok(plan) => {
                    format!(
                        "an f64 Taylor sum would round by about {:.0e} at x_max = {:.1}",
                        plan.f64_error, plan.x_max
                    )
                }
                Err(e) => e.to_string(),
            };
            let description = format!("exact DFT of exp(i·k·w·h) (no series: {why}), {taps}");
            return Ok((Reference::new(hf, window, Method::Exact, None)?, description));
        }
    };
    let description = format!(
        "f64 Taylor N = {} (|P − P_N| ≤ {:.0e}, f64 rounding about {:.0e}), {taps}",
        plan.order, REFERENCE_TOLERANCE, plan.f64_error
    );
    Ok((Reference::new(hf, window, Method::Taylor, Some(plan))?, description))
}

impl ReferenceImage {
    /// The image of `s`×`s` blocks averaged (a reference evaluated at s² positions per pixel); a pixel counts
    /// where all of its positions show the surface (edge pixels, partly covered, are left out).
    pub fn downsample(self, s: u32) -> Self {
        if s <= 1 {
            return self;
        }
        let (w, h) = (self.width / s, self.height / s);
        let mut xyz = Vec::with_capacity((w * h) as usize);
        let mut half = Vec::with_capacity((w * h) as usize);
        let mut mask = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                let at = |i: u32, j: u32| ((y * s + j) * self.width + x * s + i) as usize;
                let (mut sum, mut sum_half) = (DVec3::ZERO, DVec3::ZERO);
                let mut all = true;
                for j in 0..s {
                    for i in 0..s {
                        sum += self.xyz[at(i, j)];
                        if i % 2 == 0 && j % 2 == 0 {
                            sum_half += self.xyz[at(i, j)];
                        }
                        all &= self.mask[at(i, j)];
                    }
                }
                xyz.push(sum / f64::from(s * s));
                half.push(sum_half / f64::from(s.div_ceil(2).pow(2)));
                mask.push(all);
            }
        }
        let description = format!("{}; {s}×{s} positions per pixel, averaged", self.description);
        let half_positions = (s % 2 == 0).then_some(half);
        let (quadrature, sampled) = (self.quadrature, self.sampled);
        Self { width: w, height: h, xyz, mask, description, quadrature, sampled, half_positions }
    }
}

/// Evaluates `f` for every pixel with a query, rows shared out to every core, progress on stderr.
fn evaluate_rows(job: &ReferenceJob<'_>, f: impl Fn(&PixelQuery) -> DVec3 + Sync) -> Vec<DVec3> {
    use rayon::prelude::*;
    let (w, h) = (job.width as usize, job.height as usize);
    let bar = Progress::new(format!("exact reference {w}×{h}"), h);
    bar.detail("rows");
    let start = Instant::now();
    let mut xyz = vec![DVec3::ZERO; w * h];
    xyz.par_chunks_mut(w).zip(job.pixels.par_chunks(w)).for_each(|(out, row)| {
        for (o, p) in out.iter_mut().zip(row) {
            *o = p.as_ref().map_or(DVec3::ZERO, &f);
        }
        bar.step();
    });
    if bar.is_drawn() {
        bar.line(&format!("exact reference {w}×{h}: done in {:.1} s", start.elapsed().as_secs_f64()));
    }
    bar.finish();
    xyz
}

/// The reference at 1 nm against 0.5 nm steps on [`CHECK_PIXELS`] pixels spread evenly over those with a query:
/// (pixels, largest ΔE₀₀, largest relative XYZ difference).
fn quadrature_check(
    job: &ReferenceJob<'_>,
    fine: impl Fn(&PixelQuery) -> DVec3 + Sync,
    xyz: &[DVec3],
) -> (usize, f64, f64) {
    let covered: Vec<usize> = job.pixels.iter().enumerate().filter(|(_, p)| p.is_some()).map(|(i, _)| i).collect();
    let picks: Vec<usize> =
        covered.iter().step_by((covered.len() / CHECK_PIXELS).max(1)).take(CHECK_PIXELS).copied().collect();
    use rayon::prelude::*;
    let results: Vec<(f64, f64)> = picks
        .par_iter()
        .map(|&i| {
            let q = job.pixels[i].expect("picked pixels have queries");
            let fine_xyz = fine(&q);
            let de = delta_e(fine_xyz, xyz[i], 0.0);
            let rel = (fine_xyz - xyz[i]).length() / fine_xyz.length().max(1e-300);
            (de, if fine_xyz.length() > 0.0 { rel } else { 0.0 })
        })
        .collect();
    let max_de = results.iter().map(|r| r.0).fold(0.0, f64::max);
    let max_rel = results.iter().map(|r| r.1).fold(0.0, f64::max);
    (picks.len(), max_de, max_rel)
}

/// CIEDE2000 between two XYZ colours (relative to a D65 mirror) as displayed at `exposure_ev`.
pub fn delta_e(a: DVec3, b: DVec3, exposure_ev: f64) -> f64 {
    let scale = exposure_ev.exp2();
    ciede2000(xyz_to_lab(a * scale), xyz_to_lab(b * scale))
}

/// An image's error against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageError {
    /// Mean and 99th-percentile CIEDE2000 over the pixels that count.
    pub mean_de: f64,
    pub p99_de: f64,
    /// √(Σ|XYZ − XYZ_ref|²) / √(Σ|XYZ_ref|²) over the same pixels.
    pub rel_rmse: f64,
    /// How many pixels were compared.
    pub pixels: usize,
    /// Where the reference holds random pixels only: the standard error of `mean_de` as an estimate of the mean
    /// over every covered pixel (s/√n).
    pub mean_de_se: Option<f64>,
    /// The mean CIEDE2000 against the reference from a quarter of its positions
    /// ([`ReferenceImage::half_positions`]): where it is within `mean_de_se` of `mean_de`, more positions would
    /// not move the figure either.
    pub mean_de_half_positions: Option<f64>,
}

/// Compares a linear sRGB RGBA image (rows top first, the GPU's output) with the reference at `exposure_ev`.
pub fn image_error(reference: &ReferenceImage, rgba: &[f32], exposure_ev: f64) -> Result<ImageError> {
    if rgba.len() != reference.xyz.len() * 4 {
        return Err(Error::Invalid("the image and its reference differ in size".into()));
    }
    let mut des = Vec::new();
    let mut half_sum = 0.0;
    let (mut err2, mut ref2) = (0.0, 0.0);
    for (i, (&r, _)) in reference.xyz.iter().zip(&reference.mask).enumerate().filter(|(_, (_, &m))| m) {
        let p = &rgba[4 * i..][..3];
        let xyz = linear_srgb_to_xyz(DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])));
        des.push(delta_e(xyz, r, exposure_ev));
        if let Some(half) = &reference.half_positions {
            half_sum += delta_e(xyz, half[i], exposure_ev);
        }
        err2 += (xyz - r).length_squared();
        ref2 += r.length_squared();
    }
    if des.is_empty() {
        return Err(Error::Invalid("no pixel of the image shows the surface".into()));
    }
    let n = des.len() as f64;
    let mean_de = des.iter().sum::<f64>() / n;
    let variance = des.iter().map(|d| (d - mean_de).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    Ok(ImageError {
        mean_de,
        pixels: des.len(),
        mean_de_se: reference.sampled.map(|_| (variance / n).sqrt()),
        mean_de_half_positions: reference.half_positions.as_ref().map(|_| half_sum / n),
        p99_de: crate::io::stats::percentile(&mut des, 0.99),
        rel_rmse: if ref2 > 0.0 { (err2 / ref2).sqrt() } else { err2.sqrt() },
    })
}

/// The default cache folder (`crate::io::cache::default_dir`).
pub fn default_cache_dir() -> Option<PathBuf> {
    crate::io::cache::default_dir()
}

/// A reference image's cache entry: its plan is the job's hash (every pixel's directions, the materials'
/// heights and coherence) and the image size.
fn stamp(job: &ReferenceJob<'_>) -> crate::io::cache::Stamp {
    let mut plan = crate::io::cache::PlanBytes::default();
    plan.u64(job.key()).u64(u64::from(job.width)).u64(u64::from(job.height));
    crate::io::cache::Stamp {
        kind: "reference",
        what: "reference image",
        version: u64::from(CACHE_VERSION),
        plan: plan.0,
    }
}

/// Bytes of a cached image: its quadrature check, its description, then per pixel the mask (1 byte) and, where it
/// is set, XYZ (3 f64): at most 25 bytes a pixel, 1 where the surface is not seen (or not sampled).
const PIXEL_BYTES: u64 = 25;
const MAX_DESCRIPTION: usize = 4096;

fn write_cached(dir: &Path, job: &ReferenceJob<'_>, image: &ReferenceImage) -> std::io::Result<()> {
    let mut bytes = Vec::with_capacity(64 + image.xyz.len() * PIXEL_BYTES as usize);
    bytes.extend_from_slice(&(image.quadrature.0 as u64).to_le_bytes());
    bytes.extend_from_slice(&image.quadrature.1.to_le_bytes());
    bytes.extend_from_slice(&image.quadrature.2.to_le_bytes());
    let text = &image.description.as_bytes()[..image.description.len().min(MAX_DESCRIPTION)];
    bytes.extend_from_slice(&(text.len() as u64).to_le_bytes());
    bytes.extend_from_slice(text);
    for (v, &m) in image.xyz.iter().zip(&image.mask) {
        bytes.push(u8::from(m));
        if m {
            for c in [v.x, v.y, v.z] {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    crate::io::cache::store(dir, &stamp(job), &bytes)
}

/// A cached image for `job`, or None (missing, or not checking out: it is then recomputed). Every XYZ must be
/// finite and non-negative.
fn read_cached(dir: &Path, job: &ReferenceJob<'_>) -> Option<ReferenceImage> {
    let n = (job.width * job.height) as usize;
    let most = 32 + MAX_DESCRIPTION as u64 + n as u64 * PIXEL_BYTES;
    let bytes = crate::io::cache::load(dir, &stamp(job), most)?;
    let image = parse_cached(&bytes, job);
    if image.is_none() {
        log::info!(
            "the cached reference image {} checks out but does not hold an image for its plan; computing it again",
            stamp(job).file(dir).display()
        );
    }
    image
}

fn parse_cached(bytes: &[u8], job: &ReferenceJob<'_>) -> Option<ReferenceImage> {
    let n = (job.width * job.height) as usize;
    let mut r = crate::io::cache::Reader::new(bytes);
    let quadrature = (usize::try_from(r.u64()?).ok()?, r.f64()?, r.f64()?);
    let description = r.string()?;
    let mut xyz = Vec::with_capacity(n);
    let mut mask = Vec::with_capacity(n);
    for _ in 0..n {
        let m = match r.take(1)?[0] {
            0 => false,
            1 => true,
            _ => return None,
        };
        let v = if m { DVec3::new(r.f64()?, r.f64()?, r.f64()?) } else { DVec3::ZERO };
        if !(v.is_finite() && v.min_element() >= 0.0) {
            return None;
        }
        xyz.push(v);
        mask.push(m);
    }
    let (width, height) = (job.width, job.height);
    r.finished().then_some(ReferenceImage {
        width,
        height,
        xyz,
        mask,
        description,
        quadrature,
        sampled: None,
        half_positions: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::physics::colour::xyz_to_linear_srgb;
    use crate::physics::colour::D65_WHITE;

    /// Random pixels: as many as asked, whole (all of a pixel's positions), among the covered ones only, the same
    /// on every run; a count beyond the covered pixels keeps them all.
    #[test]
    fn random_pixels_are_whole_covered_and_repeatable() {
        let job = |size: u32| ReferenceJob {
            materials: Vec::new(),
            width: size,
            height: size,
            pixels: ReferenceJob::map_pixels(size, DVec3::Z),
        };
        let (mut a, mut b) = (job(32), job(32));
        let covered_positions = a.pixels.iter().flatten().count();
        let (kept, covered) = a.keep_random_pixels(10, 2);
        assert_eq!(b.keep_random_pixels(10, 2), (kept, covered));
        assert_eq!(a.pixels, b.pixels, "the same pixels on every run");
        assert_eq!(kept, 10);
        assert!(covered * 4 <= covered_positions && covered > 150, "{covered} of {covered_positions}");
        assert_eq!(a.pixels.iter().flatten().count(), 40, "each kept pixel keeps its 2×2 positions");
        for y in (0..32).step_by(2) {
            for x in (0..32).step_by(2) {
                let here = [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(i, j)| a.pixels[(y + j) * 32 + x + i].is_some());
                assert!(here.iter().all(|&h| h == here[0]), "pixel ({x}, {y}) is kept whole or not at all");
            }
        }
        let mut all = job(32);
        assert_eq!(all.keep_random_pixels(usize::MAX, 2), (covered, covered));
    }

    /// The cache keeps XYZ for the pixels that count only, and gives back the same image.
    #[test]
    fn a_cached_image_reads_back_as_written() {
        let dir = std::env::temp_dir().join(format!("diffract-reference-cache-test-{}", std::process::id()));
        let mut job =
            ReferenceJob { materials: Vec::new(), width: 8, height: 8, pixels: ReferenceJob::map_pixels(8, DVec3::Z) };
        job.keep_random_pixels(5, 1);
        let mask: Vec<bool> = job.pixels.iter().map(Option::is_some).collect();
        let xyz = mask.iter().enumerate().map(|(i, &m)| if m { DVec3::splat(i as f64) } else { DVec3::ZERO }).collect();
        let image = ReferenceImage {
            width: 8,
            height: 8,
            xyz,
            mask,
            description: "test".into(),
            quadrature: (5, 1e-9, 1e-6),
            sampled: None,
            half_positions: None,
        };
        write_cached(&dir, &job, &image).unwrap();
        assert_eq!(read_cached(&dir, &job), Some(image));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_downsampled_reference_keeps_the_average_of_every_other_position_too() {
        // One pixel of 4×4 positions whose value is its index: the whole average and the 2×2 positions' one
        // (indices 0, 2, 8, 10).
        let xyz: Vec<DVec3> = (0..16).map(|i| DVec3::splat(f64::from(i))).collect();
        let fine = ReferenceImage {
            width: 4,
            height: 4,
            xyz,
            mask: vec![true; 16],
            description: String::new(),
            quadrature: (0, 0.0, 0.0),
            sampled: None,
            half_positions: None,
        };
        let pixel = fine.clone().downsample(4);
        assert_eq!((pixel.xyz[0].x, pixel.half_positions.as_ref().unwrap()[0].x), (7.5, 5.0));
        assert_eq!(fine.clone().downsample(3).half_positions, None, "odd position counts have no half");
        // Compared against both: the mean against the half is reported beside the mean.
        let rgb = xyz_to_linear_srgb(DVec3::splat(7.5)).to_array().map(|c| c as f32);
        let e = image_error(&pixel, &[rgb[0], rgb[1], rgb[2], 1.0], -3.0).unwrap();
        assert!(e.mean_de < 1e-3 && e.mean_de_half_positions.unwrap() > 1.0, "{e:?}");
    }

    #[test]
    fn srgb_round_trip() {
        let xyz = DVec3::new(0.3, 0.5, 0.2);
        assert!((linear_srgb_to_xyz(xyz_to_linear_srgb(xyz)) - xyz).length() < 1e-12);
    }

    #[test]
    fn identical_images_have_no_error_and_a_darker_one_has_some() {
        let white = D65_WHITE;
        let reference = ReferenceImage {
            width: 2,
            height: 1,
            xyz: vec![white, white * 0.5],
            mask: vec![true, true],
            description: String::new(),
            quadrature: (0, 0.0, 0.0),
            sampled: None,
            half_positions: None,
        };
        let to_rgb = |v: DVec3| xyz_to_linear_srgb(v).to_array().map(|c| c as f32);
        let [a, b, c] = to_rgb(white);
        let [d, e, f] = to_rgb(white * 0.5);
        let same = image_error(&reference, &[a, b, c, 1.0, d, e, f, 1.0], 0.0).unwrap();
        assert!(same.mean_de < 1e-3 && same.rel_rmse < 1e-6, "{same:?}");
        let dark = image_error(&reference, &[a * 0.9, b * 0.9, c * 0.9, 1.0, d, e, f, 1.0], 0.0).unwrap();
        assert!(dark.mean_de > 1.0 && (dark.rel_rmse - 0.1 / 1.25f64.sqrt()).abs() < 1e-6, "{dark:?}");
    }
}
