//! Argument groups shared by several commands: a height field with its units, and the settings that trade
//! speed for accuracy.

use std::path::PathBuf;

use anyhow::bail;
use clap::Args;

use crate::cli::parse;
use crate::material::{Settings, SettingsPatch};
use crate::physics::formats::png::PngScale;
use crate::physics::heightfield::HeightField;

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
    /// Extend the patch to UM × UM µm without a period: a random-phase field with its measured power spectrum and
    /// its height distribution (docs/approaches.md, "Extending a cut-out"), where --tile would repeat it
    #[arg(long, value_name = "UM", value_parser = parse::finite, conflicts_with = "tile")]
    pub extend_um: Option<f64>,
}

impl HeightFieldArgs {
    pub fn load(&self) -> anyhow::Result<HeightField> {
        let png = match (self.pixel_size_um, self.height_um) {
            (Some(pixel_size_um), Some(height_um)) => Some(PngScale { pixel_size_um, height_um }),
            (None, None) => None,
            _ => bail!("--pixel-size-um and --height-um go together"),
        };
        let hf = crate::physics::formats::load(&self.heightfield, png)?;
        match (self.tile, self.extend_um) {
            (Some(_), Some(_)) => {
                bail!("give --tile (repeat the patch) or --extend-um (grow it without a period), not both")
            }
            (Some((tx, ty)), None) => Ok(hf.tiled(tx, ty)?),
            (None, Some(um)) => Ok(crate::physics::extend::extend(&hf, um)?),
            (None, None) => Ok(hf),
        }
    }
}

/// The material settings of a command that prepares one material from [`Settings::default`] (`map`, `brdf`,
/// `terms`, a profiled BRDF map): every flag of [`SettingsPatch`] (declared in `src/material/settings.rs`).
#[derive(Args, Debug, Clone)]
pub struct MaterialArgs {
    #[command(flatten)]
    pub patch: SettingsPatch,
}

impl MaterialArgs {
    /// [`Settings::default`] with the flags' settings, refused (one line) where the command has no use for a
    /// setting that was given (`used`: the keys it reads).
    pub fn settings(&self, command: &str, used: &[&str]) -> anyhow::Result<Settings> {
        if let Some(key) = self.patch.keys_set().into_iter().find(|k| !used.contains(k)) {
            let flag = Settings::INFO.iter().find(|i| i.key == key).map_or(key, |i| i.flag);
            bail!("--{flag} has no effect on `diffract {command}` (it reads {})", flags(used));
        }
        Ok(self.patch.apply(Settings::default()))
    }
}

/// `--a, --b` for the keys `used`.
fn flags(used: &[&str]) -> String {
    let flag =
        |key: &&str| Settings::INFO.iter().find(|i| i.key == *key).map_or(key.to_string(), |i| format!("--{}", i.flag));
    used.iter().map(flag).collect::<Vec<_>>().join(", ")
}

/// The files a run reads besides a scene's (which names its own: `Scene::files`): a measured illuminant's SPD
/// given by `--illuminant`, and `extra` (a height field, an environment map, a font: what the command reads).
pub fn inputs(patch: &SettingsPatch, extra: &[(&str, Option<&std::path::Path>)]) -> Vec<(String, PathBuf)> {
    let mut files: Vec<(String, PathBuf)> =
        extra.iter().filter_map(|(what, path)| path.map(|p| (what.to_string(), p.to_path_buf()))).collect();
    if let Some(illuminant) = patch.illuminant.filter(|i| i.name.to_ascii_lowercase().ends_with(".csv")) {
        files.push(("the illuminant's SPD".to_string(), PathBuf::from(illuminant.name)));
    }
    files
}

/// Refuses, before any work, an output (what it is, its path) that is one of `inputs` ([`inputs`], a scene's
/// `files`): writing it would replace what the run reads.
pub fn check_outputs(outputs: &[(&str, PathBuf)], inputs: &[(String, PathBuf)]) -> crate::error::Result<()> {
    let outputs: Vec<(&str, &std::path::Path)> = outputs.iter().map(|(what, p)| (*what, p.as_path())).collect();
    let inputs: Vec<(&str, &std::path::Path)> = inputs.iter().map(|(what, p)| (what.as_str(), p.as_path())).collect();
    crate::io::output::check_not_inputs(&outputs, &inputs)
}

/// Hides from `cmd`'s help the setting flags that `command` does not read (they are refused when given).
pub fn hide_unused_settings(cmd: clap::Command, used: &[&str]) -> clap::Command {
    Settings::KEYS.iter().filter(|k| !used.contains(k)).fold(cmd, |cmd, key| cmd.mut_arg(*key, |a| a.hide(true)))
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
    /// The light's angular radius in degrees (the sun's is 0.267°): its coherence length follows, 65 µm × 0.267°/DEG
    /// (docs/model.md §1.13), where --coherence-um would set it directly
    #[arg(value_parser = parse::finite, long, value_name = "DEG")]
    pub light_radius_deg: Option<f64>,
}

/// The coherence length a light of angular radius `radius_deg` gives (model.md §1.13), refused beside an explicit
/// --coherence-um, with a note that says it: `brdf --light-radius-deg`, `map --light-radius-deg` and
/// `map --lamp-radius-m/--lamp-distance-m`.
pub fn coherence_of_light(radius_deg: f64, explicit: Option<f64>, flag: &str) -> anyhow::Result<f64> {
    if explicit.is_some() {
        anyhow::bail!("give {flag} (the coherence length follows from it) or --coherence-um, not both");
    }
    let coherence =
        crate::physics::coherence::of_light(radius_deg.to_radians()).map_err(|e| anyhow::anyhow!("{flag}: {e}"))?;
    errln!("note: a light {radius_deg:.4}° in radius: coherence length {coherence:.4} µm");
    Ok(coherence)
}

/// Settings that replace every material's own in a scene (`render`, `view`, `profile`; a profiled BRDF map's
/// material starts from the defaults), and the frame's exposure and samples.
#[derive(Args, Debug, Clone)]
pub struct SceneOverrideArgs {
    #[command(flatten)]
    pub patch: SettingsPatch,
    /// Exposure in stops (default: the scene's, else measured from the frame; `profile --heightfield`: 0)
    #[arg(value_parser = parse::exposure, long, value_name = "EV", alias = "exposure-ev")]
    pub exposure: Option<f64>,
    /// Samples per pixel: multisample anti-aliasing of edges, 1 for none (default: the scene's, else 4; a BRDF
    /// map has one)
    #[arg(long, value_name = "N", value_parser = parse::samples)]
    pub samples: Option<u32>,
    /// Extend every material's patch (one cell of a tiled one) to UM × UM µm without a period: a random-phase
    /// field with its measured power spectrum and its height distribution (docs/approaches.md, "Extending a
    /// cut-out"); default: each material's own `tile` or `extend_um`
    #[arg(long, value_name = "UM", value_parser = parse::finite)]
    pub extend_um: Option<f64>,
}

impl SceneOverrideArgs {
    /// The scene at `path` (None: the built-in one), its patches extended where `--extend-um` says.
    pub fn load_scene(&self, path: Option<&std::path::Path>) -> anyhow::Result<crate::scene::Scene> {
        let mut scene = match path {
            Some(path) => crate::scene::Scene::load(path)?,
            None => crate::scene::Scene::default_scene()?,
        };
        if let Some(um) = self.extend_um {
            scene.extend_patches(um)?;
        }
        Ok(scene)
    }

    /// The sample count for `scene` on `ctx`'s device: the flag, else the scene's; refused (one line) where the
    /// device cannot.
    pub fn sample_count(
        &self,
        ctx: &crate::gpu::vk::Context,
        scene: &crate::scene::Scene,
        format: ash::vk::Format,
    ) -> crate::error::Result<ash::vk::SampleCountFlags> {
        ctx.sample_count(self.samples.unwrap_or(scene.render.samples), format)
    }
}
