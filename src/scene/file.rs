//! The scene file's format: its TOML tables as serde reads them (with the spans that locate a mistake), the
//! [`Locator`] that turns a span into `file:line: message`, and the files built into the binary for the default
//! scene. Nothing here checks a value: `checks.rs` and `objects.rs` do.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use crate::error::Error;
use crate::material::SettingsPatch;
use crate::physics::generate::PatchKind;
use crate::scene::mesh::shapes::Shape;

/// The scene `diffract render` draws when given none: the snake with the measured Elaphe scan under the clear
/// sky (built in, with the files it names, so it works from any folder).
pub const DEFAULT_SCENE: &str = include_str!("../../assets/scenes/elaphe-snake.toml");
/// Where the built-in scene's relative paths start: `assets/scenes` inside the binary.
pub(super) const BUILT_IN_BASE: &str = "<built-in>/scenes";
/// The files under `assets/` built into the binary, for the built-in scene.
const BUILT_IN: [(&str, &[u8]); 2] = [
    ("afm/elaphe-100px.png", include_bytes!("../../assets/afm/elaphe-100px.png")),
    ("afm/xenopeltis-100px.png", include_bytes!("../../assets/afm/xenopeltis-100px.png")),
];

/// The built-in bytes of `file` when it names one of [`BUILT_IN`] from [`BUILT_IN_BASE`].
pub(super) fn built_in(file: &Path) -> Option<&'static [u8]> {
    let rest = file.strip_prefix("<built-in>").ok()?;
    let mut parts: Vec<&str> = Vec::new();
    for c in rest.components() {
        match c {
            std::path::Component::ParentDir => {
                parts.pop()?;
            }
            std::path::Component::Normal(p) => parts.push(p.to_str()?),
            _ => {}
        }
    }
    let name = parts.join("/");
    BUILT_IN.iter().find(|(n, _)| *n == name).map(|(_, bytes)| *bytes)
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneFile {
    pub(super) camera: CameraDef,
    pub(super) light: LightDef,
    #[serde(default, rename = "object")]
    pub(super) objects: Vec<Spanned<ObjectDef>>,
    #[serde(default)]
    pub(super) material: BTreeMap<String, Spanned<MaterialDef>>,
    #[serde(default)]
    pub(super) render: RenderDef,
    #[serde(default, rename = "lamp")]
    pub(super) lamps: Vec<Spanned<LampDef>>,
}

/// A `[[lamp]]`: a point or spot light (`light::lamp`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LampDef {
    /// "point" or "spot".
    pub(super) kind: Spanned<String>,
    /// Where it is, world units (metres).
    pub(super) position: Spanned<[f64; 3]>,
    /// Its luminous intensity, cd (a spot's along its axis).
    pub(super) intensity_cd: Spanned<f64>,
    /// The emitting disc's radius, m (default 0.01).
    pub(super) radius_m: Option<Spanned<f64>>,
    /// A spot's axis, from the lamp.
    pub(super) direction: Option<Spanned<[f64; 3]>>,
    /// A spot's half-angle and its edge's width, degrees.
    pub(super) cone_deg: Option<Spanned<f64>>,
    pub(super) soft_deg: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraDef {
    pub(super) position: Spanned<[f64; 3]>,
    pub(super) target: [f64; 3],
    pub(super) fov_y_deg: Spanned<f64>,
    #[serde(default = "default_up")]
    pub(super) up: [f64; 3],
    #[serde(default = "default_near")]
    pub(super) near: f64,
    #[serde(default = "default_far")]
    pub(super) far: f64,
}

pub(super) fn default_up() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}
pub(super) fn default_near() -> f64 {
    0.01
}
pub(super) fn default_far() -> f64 {
    1000.0
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LightDef {
    /// Towards the sun; optional under a map that holds its sun (the map's is taken) or to light by the map alone.
    pub(super) direction: Option<Spanned<[f64; 3]>>,
    pub(super) illuminant: Option<Spanned<String>>,
    /// Radiance of a uniform sky, relative to the sun seen in a mirror (a clear sky is ~1e-5 of that).
    #[serde(default)]
    pub(super) ambient: Option<Spanned<f64>>,
    /// "sky" (the default, unless `ambient` is given): the clear-sky model around the light's sun; "FILE.exr" or
    /// "FILE.hdr": an HDR map of the sky around it; "none": no environment (the sun alone, relative units).
    pub(super) environment: Option<Spanned<String>>,
    /// The sky's turbidity (environment = "sky").
    pub(super) turbidity: Option<Spanned<f64>>,
    /// The sky's model (environment = "sky"): "hosek-wilkie" (the default) or "preetham".
    pub(super) sky_model: Option<Spanned<String>>,
    /// An environment map's turn about the up axis, degrees, and the factor on its radiance.
    pub(super) rotation_deg: Option<Spanned<f64>>,
    pub(super) intensity: Option<Spanned<f64>>,
    /// The sun's and the lamps' shadows (shadow maps); on by default where the scene has a ground.
    pub(super) shadows: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ObjectDef {
    pub(super) mesh: Option<Spanned<String>>,
    pub(super) shape: Option<Shape>,
    /// The snake's skin pattern (shape = "snake" only).
    pub(super) pattern: Option<crate::scene::mesh::snake::Pattern>,
    /// How high the snake's scales are domed, relative to their half-width (shape = "snake" only).
    pub(super) scale_dome: Option<Spanned<f64>>,
    pub(super) material: Spanned<String>,
    #[serde(default)]
    pub(super) translate: [f64; 3],
    #[serde(default)]
    pub(super) rotate_deg: [f64; 3],
    pub(super) scale: Option<Spanned<f64>>,
}

/// `tile = 10` or `tile = [10, 4]`.
#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
pub(super) enum TileDef {
    Both(u32),
    Each([u32; 2]),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialDef {
    pub(super) heightfield: Option<Spanned<String>>,
    pub(super) generate: Option<PatchKind>,
    pub(super) pixel_size_um: Option<f64>,
    pub(super) height_um: Option<f64>,
    /// Generated patches: edge length, period and seed.
    pub(super) size_um: Option<f64>,
    pub(super) period_um: Option<f64>,
    pub(super) seed: Option<u64>,
    pub(super) tile: Option<TileDef>,
    /// Extend the patch to this size (µm) without a period (`physics::extend`), instead of tiling it.
    pub(super) extend_um: Option<f64>,
    /// The speed/accuracy settings (`src/material/settings.rs`), under their keys.
    #[serde(flatten)]
    pub(super) settings: SettingsPatch,
    /// Rotation of the patch about the normal, from the mesh tangent towards the bitangent.
    #[serde(default)]
    pub(super) orientation_deg: f64,
    /// Linear RGB albedo of the skin's pigment under the grating.
    #[serde(default)]
    pub(super) pigment: [f64; 3],
    /// An sRGB PNG whose colour multiplies `pigment`, and a tangent-space normal map (`scene::mesh::maps`).
    pub(super) pigment_map: Option<Spanned<String>>,
    pub(super) normal_map: Option<Spanned<String>>,
    /// Metres one repeat of the maps covers on the ground and planes.
    pub(super) map_size_m: Option<Spanned<f64>>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RenderDef {
    pub(super) width: Option<u32>,
    pub(super) height: Option<u32>,
    pub(super) exposure_ev: Option<f64>,
    /// Linear RGB behind the objects.
    pub(super) background: Option<[f64; 3]>,
    /// Samples per pixel (multisample anti-aliasing; 1: none).
    pub(super) samples: Option<u32>,
}

/// Errors located in a scene file: `file:line: message`.
pub(super) struct Locator<'a> {
    pub(super) name: &'a str,
    pub(super) text: &'a str,
}

impl Locator<'_> {
    fn line(&self, offset: usize) -> usize {
        self.text[..offset.min(self.text.len())].matches('\n').count() + 1
    }

    pub(super) fn at(&self, span: std::ops::Range<usize>, message: impl std::fmt::Display) -> Error {
        Error::Scene { file: self.name.to_string(), line: Some(self.line(span.start)), message: message.to_string() }
    }

    pub(super) fn whole(&self, message: impl std::fmt::Display) -> Error {
        Error::Scene { file: self.name.to_string(), line: None, message: message.to_string() }
    }
}
