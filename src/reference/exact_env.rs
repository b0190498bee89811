//! The exact reference of a BRDF map under a whole environment (model.md §3.10): the light module's MIS
//! estimator ([`Integrator`]) with the exact BRDF in f64 as ρ, the environment's light upsampled in the spectral
//! basis frames use, and the comparison of a map against it at chosen pixels (`map --env-reference`).

use glam::{DMat3, DVec3};

use crate::error::Result;
use crate::light::sampling::{env_gain, map_view, EnvLight, Estimate, Integrator, TableProposal, MAP_FRAME};

/// The wavelength step of the reference's spectral sums, nm (the table is built at 1 nm). Measured on the blazed
/// grating under a clear sky (tests/gpu/env_map.rs' 24 pixels): 1 nm steps change no pixel's luminance by more than
/// 0.12 % and the baked map's mean ΔE00 against the reference from 0.430 to 0.424, at five times the cost.
pub const REFERENCE_STEP_NM: f64 = 5.0;
/// Independent passes the reference's samples are split into (its standard error is their spread's).
pub const REFERENCE_REPLICATES: u32 = 8;

/// The exact BRDF integrated over an environment: the estimator above with the exact BRDF (f64, the full coherence
/// window, [`REFERENCE_STEP_NM`] steps: `Reference::flss_xyz_bands`), in [`REFERENCE_REPLICATES`] independently shifted
/// passes, a table only proposing where to look. Each estimate carries its standard error (from the passes' spread).
pub struct ExactEnv {
    reference: crate::physics::exact::Reference,
    /// The spectral basis' samplings (`light::prefilter::basis`), each with its gain (`env_gain`).
    bands: [(crate::physics::spectrum::Sampling, f64); 3],
    /// A⁻¹: the environment's RGB → the basis' coefficients (`light::prefilter::basis_colours`).
    to_light: DMat3,
}

impl ExactEnv {
    /// The reference of `hf` under `settings`' coherence length; the environment's light is upsampled to spectra
    /// in the basis frames use (`light::prefilter::basis`, in physical units), whatever light `settings` names.
    pub fn new(hf: &crate::physics::heightfield::HeightField, settings: &crate::material::Settings) -> Result<Self> {
        use crate::physics::spectrum::Sampling;
        // Every view of the hemisphere: |w| up to 2.
        let (reference, _) = crate::reference::exact_image::exact_reference(hf, settings.coherence_um, 2.0)?;
        let mut bands = Vec::new();
        for illuminant in crate::light::prefilter::basis() {
            let sampling = Sampling::visible_under(REFERENCE_STEP_NM, illuminant);
            bands.push((sampling, env_gain(&sampling, settings.coherence_um)?));
        }
        let to_light = crate::light::prefilter::basis_colours().inverse();
        Ok(Self { reference, bands: [bands[0], bands[1], bands[2]], to_light })
    }

    /// The radiance towards `omega_r` (patch frame, whose axes in the environment's frame are `frame`'s columns)
    /// under `env`, from `samples` samples (half from the BRDF's strategies, half from the environment's).
    pub fn estimate(
        &self,
        env: &EnvLight,
        proposal: &TableProposal,
        frame: DMat3,
        omega_r: DVec3,
        samples: u32,
        seed: u64,
    ) -> Estimate {
        let per_pass = (samples / REFERENCE_REPLICATES).max(2);
        let n_brdf = per_pass / 2;
        let integrator = Integrator { env, proposal, n_brdf, n_env: per_pass - n_brdf, frame };
        let samplings = self.bands.map(|(sampling, _)| sampling);
        let rho = |omega_i: DVec3, omega_r: DVec3| {
            if !(omega_i.z > 0.0 && omega_r.z > 0.0) {
                return DMat3::ZERO;
            }
            let xyz = self.reference.flss_xyz_bands(omega_i, omega_r, &samplings);
            let rgb: [DVec3; 3] =
                std::array::from_fn(|k| crate::physics::colour::xyz_to_linear_srgb(xyz[k]) * self.bands[k].1);
            DMat3::from_cols(rgb[0], rgb[1], rgb[2]) * self.to_light
        };
        integrator.pixel(omega_r, rho, seed, REFERENCE_REPLICATES)
    }
}

/// The exact reference of a BRDF map `size` pixels across under `env` ([`ExactEnv`]) at each of `pixels`,
/// `samples` per pixel.
pub fn reference_map_pixels(
    hf: &crate::physics::heightfield::HeightField,
    settings: &crate::material::Settings,
    proposal: &TableProposal,
    env: &EnvLight,
    size: u32,
    pixels: &[(u32, u32)],
    samples: u32,
) -> Result<Vec<Option<Estimate>>> {
    use rayon::prelude::*;
    let exact = ExactEnv::new(hf, settings)?;
    Ok(pixels
        .par_iter()
        .map(|&(x, y)| {
            map_view(size, x, y).map(|omega_r| {
                let seed = 0x5eed_0000_0000 ^ (u64::from(y) << 20) ^ u64::from(x);
                exact.estimate(env, proposal, MAP_FRAME, omega_r, samples, seed)
            })
        })
        .collect())
}

/// `count` distinct random pixels of a `size`-pixel map's disk (fewer where the disk has fewer), from `seed`.
pub fn random_map_pixels(size: u32, count: usize, seed: u64) -> Vec<(u32, u32)> {
    let mut all: Vec<(u32, u32)> =
        (0..size * size).map(|i| (i % size, i / size)).filter(|&(x, y)| map_view(size, x, y).is_some()).collect();
    let mut rng = fastrand::Rng::with_seed(seed);
    // A partial Fisher–Yates shuffle.
    let count = count.min(all.len());
    for i in 0..count {
        let j = rng.usize(i..all.len());
        all.swap(i, j);
    }
    all.truncate(count);
    all
}

/// A map against the reference at some of its pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    pub mean: f64,
    pub worst: f64,
    /// The median of the reference's standard error over its luminance.
    pub median_relative_error: f64,
}

/// ΔE00 of `map` against `reference` (as [`reference_map_pixels`] returns it for `pixels`) at `exposure_ev`.
pub fn compare(
    map: &crate::render::map::MapImage,
    pixels: &[(u32, u32)],
    reference: &[Option<Estimate>],
    exposure_ev: f64,
) -> Comparison {
    use crate::physics::colour::linear_srgb_to_xyz;
    let mut errors = Vec::new();
    let mut relative = Vec::new();
    for (&(x, y), r) in pixels.iter().zip(reference) {
        let Some(r) = r else { continue };
        let e = crate::reference::exact_image::delta_e(
            linear_srgb_to_xyz(map.pixel(x, y)),
            linear_srgb_to_xyz(r.rgb),
            exposure_ev,
        );
        errors.push(e);
        let y_ref = linear_srgb_to_xyz(r.rgb).y;
        if y_ref > 0.0 {
            relative.push(linear_srgb_to_xyz(r.std_error).y.abs() / y_ref);
        }
    }
    relative.sort_by(f64::total_cmp);
    let n = errors.len().max(1) as f64;
    Comparison {
        mean: errors.iter().sum::<f64>() / n,
        worst: errors.iter().copied().fold(0.0, f64::max),
        median_relative_error: relative.get(relative.len() / 2).copied().unwrap_or(0.0),
    }
}
