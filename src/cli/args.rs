//! Argument groups shared by several commands: a height field with its units, and the settings that trade
//! speed for accuracy.

use std::path::PathBuf;

use anyhow::bail;
use clap::Args;

use super::parse;
use crate::physics::baked::DEFAULT_TABLE_TOLERANCE;
use crate::physics::taylor::DEFAULT_TOLERANCE;
use crate::physics::window::DEFAULT_COHERENCE_UM;
use crate::physics::{HeightField, PngScale};
use crate::shading::{Approach, Overrides, Settings};

/// A height field and its physical units, shared by every command that reads one.
#[derive(Args, Debug, Clone)]
pub struct HeightFieldArgs {
    /// Height field: Gwyddion Simple Field (.gsf, units from the file) or greyscale PNG
    #[arg(long, value_name = "FILE")]
    pub heightfield: PathBuf,
    /// PNG only: pixel size in µm
    #[arg(value_parser = parse::finite, long, value_name = "P")]
    pub pixel_size_um: Option<f64>,
    /// PNG only: height in µm of the brightest grey value (255 or 65535); black is 0
    #[arg(value_parser = parse::finite, long, value_name = "H")]
    pub height_um: Option<f64>,
    /// Repeat the patch periodically NX times along x and NY along y
    #[arg(long, value_name = "NX[,NY]", value_parser = parse::tile)]
    pub tile: Option<(usize, usize)>,
}

impl HeightFieldArgs {
    pub fn load(&self) -> anyhow::Result<HeightField> {
        let png = match (self.pixel_size_um, self.height_um) {
            (Some(pixel_size_um), Some(height_um)) => Some(PngScale { pixel_size_um, height_um }),
            (None, None) => None,
            _ => bail!("--pixel-size-um and --height-um go together"),
        };
        let hf = crate::physics::formats::load(&self.heightfield, png)?;
        match self.tile {
            Some((tx, ty)) => Ok(hf.tiled(tx, ty)?),
            None => Ok(hf),
        }
    }
}

/// What a scene's material says about its patch besides the speed settings: the tolerance the Taylor order
/// is chosen for and the coherence length.
#[derive(Args, Debug, Clone)]
pub struct MaterialArgs {
    /// Tolerance on the amplitude |P − P_N| (a flat mirror at specular has |P| = 1)
    #[arg(value_parser = parse::finite, long, default_value_t = DEFAULT_TOLERANCE)]
    pub tolerance: f64,
    /// Coherence length in µm (the Gaussian window has σ_s = L/4)
    #[arg(value_parser = parse::finite, long, value_name = "L", default_value_t = DEFAULT_COHERENCE_UM)]
    pub coherence_um: f64,
}

impl MaterialArgs {
    /// [`Settings::default`] with this tolerance and coherence.
    pub fn settings(&self) -> Settings {
        Settings { tolerance: self.tolerance, coherence_um: self.coherence_um, ..Settings::default() }
    }
}

/// The accuracy of the Taylor sum and of the window, for every command that evaluates P.
#[derive(Args, Debug, Clone)]
pub struct AccuracyArgs {
    /// Taylor order N (terms 0..=N); default: the smallest N that meets --tolerance (--terms: its first name)
    #[arg(long, value_name = "N", alias = "terms")]
    pub order: Option<usize>,
    #[command(flatten)]
    pub material: MaterialArgs,
    /// Window taps either side of the nearest bin, at most 16 (default: brdf and terms the full window, weights
    /// ≥ 1e-17; map and render down to a weight of 1e-3)
    #[arg(long, value_name = "R", value_parser = parse::window_radius)]
    pub window_radius: Option<u32>,
}

/// Every setting of the shaders that trades speed for accuracy.
#[derive(Args, Debug, Clone)]
pub struct ShadingArgs {
    /// Shading approach
    #[arg(long, value_enum, default_value_t = Approach::Flss)]
    pub approach: Approach,
    #[command(flatten)]
    pub accuracy: AccuracyArgs,
    /// Wavelength step in nm over 380–780 nm (FLSS, PQ)
    #[arg(value_parser = parse::finite, long, value_name = "NM", default_value_t = 5.0)]
    pub lambda_step: f64,
    /// Exposure in stops applied before the sRGB transfer function (PNG only; the EXR stays linear)
    #[arg(value_parser = parse::finite, long, value_name = "EV", default_value_t = 0.0)]
    pub exposure: f64,
    /// Render even where f32 sums cannot reach --tolerance (the plan's estimate)
    #[arg(long)]
    pub accept_f32_error: bool,
    /// Baked: tolerance on the table's Chebyshev tail in w, relative to each texel's brightest value
    #[arg(value_parser = parse::finite, long, value_name = "T", default_value_t = DEFAULT_TABLE_TOLERANCE)]
    pub table_tolerance: f64,
    /// Baked: refuse a table that cannot reach --table-tolerance (memory or the term cap) instead of warning
    #[arg(long)]
    pub strict: bool,
}

impl ShadingArgs {
    pub fn settings(&self) -> Settings {
        Settings {
            approach: self.approach,
            order: self.accuracy.order,
            lambda_step_nm: self.lambda_step,
            window_radius: self.accuracy.window_radius,
            exposure_ev: self.exposure,
            accept_f32_error: self.accept_f32_error,
            table_tolerance: self.table_tolerance,
            strict_table: self.strict,
            ..self.accuracy.material.settings()
        }
    }
}

/// A directional light in the patch frame.
#[derive(Args, Debug, Clone)]
pub struct LightArgs {
    /// Light inclination θ_i in degrees (0 = normal incidence)
    #[arg(value_parser = parse::finite, long, value_name = "DEG")]
    pub light_theta: f64,
    /// Light azimuth φ_i in degrees
    #[arg(value_parser = parse::finite, long, value_name = "DEG", default_value_t = 0.0)]
    pub light_phi: f64,
}

/// Settings that replace every material's own in a scene (`render`, `view`, `profile`; a profiled BRDF map's
/// material starts from the defaults).
#[derive(Args, Debug, Clone)]
pub struct SceneOverrideArgs {
    /// Shading approach for every material (default: each material's own; `profile --heightfield`: flss)
    #[arg(long, value_enum)]
    pub approach: Option<Approach>,
    /// Exposure in stops (default: the scene's; `profile --heightfield`: 0)
    #[arg(value_parser = parse::finite, long, value_name = "EV")]
    pub exposure: Option<f64>,
    /// Taylor order N for every material (default: from each material's tolerance; --terms: its first name)
    #[arg(long, value_name = "N", alias = "terms")]
    pub order: Option<usize>,
    /// Wavelength step in nm for every material (default: each material's own; `profile --heightfield`: 5)
    #[arg(value_parser = parse::finite, long, value_name = "NM")]
    pub lambda_step: Option<f64>,
    /// Window radius for every material, at most 16 (default: each material's own)
    #[arg(long, value_name = "R", value_parser = parse::window_radius)]
    pub window_radius: Option<u32>,
    /// Shade even where f32 cannot reach the tolerance
    #[arg(long)]
    pub accept_f32_error: bool,
    /// Baked: refuse a table that cannot reach its tolerance (memory or the term cap) instead of warning (a scene
    /// that sets table_tolerance asks for this itself)
    #[arg(long)]
    pub strict: bool,
    /// Samples per pixel: multisample anti-aliasing of edges, 1 for none (default: the scene's, else 4; a BRDF
    /// map has one)
    #[arg(long, value_name = "N", value_parser = parse::samples)]
    pub samples: Option<u32>,
}

impl SceneOverrideArgs {
    /// The sample count for `scene` on `ctx`'s device: the flag, else the scene's; refused (one line) where the
    /// device cannot.
    pub fn sample_count(
        &self,
        ctx: &crate::vk::Context,
        scene: &crate::scene::Scene,
        format: ash::vk::Format,
    ) -> crate::error::Result<ash::vk::SampleCountFlags> {
        ctx.sample_count(self.samples.unwrap_or(scene.render.samples), format)
    }

    pub fn overrides(&self) -> Overrides {
        Overrides {
            approach: self.approach,
            order: self.order,
            lambda_step_nm: self.lambda_step,
            window_radius: self.window_radius,
            accept_f32_error: self.accept_f32_error,
            strict_table: self.strict,
        }
    }
}
