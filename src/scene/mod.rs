//! Scene files (TOML): a camera, a directional light, objects (OBJ meshes or built-in shapes) and materials
//! (a height field, measured or generated, with the settings that trade speed for accuracy). Paths are relative
//! to the scene file. Every mistake is refused with the file, the line and what was expected.
//!
//! ```toml
//! [camera]
//! position = [0.0, 0.5, 3.0]
//! target = [0.0, 0.0, 0.0]
//! fov_y_deg = 30.0
//!
//! [light]                       # a directional light: the sun
//! direction = [0.3, 1.0, 0.5]   # towards the light (optional under a map that holds its sun)
//! # environment = "sky"         # the default: the clear sky around it; "none": the sun alone; or "sky.exr"
//!
//! [[object]]
//! mesh = "meshes/snake.obj"     # or: shape = "plane" | "disk" | "sphere" | "cylinder" | "cube" | "snake"
//! # pattern = "corn"           # with shape = "snake": "corn" (default) or "plain"
//! # scale_dome = 0.12          # with shape = "snake": the scales' dome over their half-width (0.35 by default)
//! material = "elaphe"
//!
//! [material.elaphe]
//! heightfield = "patches/elaphe.gsf"   # or a PNG with pixel_size_um and height_um, or generate = "elaphe"
//! approach = "flss"
//! ```

pub mod camera;
pub mod mesh;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{EulerRot, Mat4, Quat, Vec3};
use serde::Deserialize;
use toml::Spanned;

use crate::error::{Error, Result};
use crate::material::{Approach, Settings, SettingsPatch};
use crate::physics::formats::png::PngScale;
use crate::physics::generate::{generate, PatchKind, PatchSpec};
use crate::physics::heightfield::HeightField;
use crate::physics::illuminant::Illuminant;
use crate::scene::camera::Camera;
use crate::scene::mesh::shapes::Shape;
use crate::scene::mesh::{obj, Mesh};

/// The scene `diffract render` draws when given none: the snake with the measured Elaphe scan under the clear
/// sky (built in, with the files it names, so it works from any folder).
pub const DEFAULT_SCENE: &str = include_str!("../../assets/scenes/elaphe-snake.toml");
/// Where the built-in scene's relative paths start: `assets/scenes` inside the binary.
const BUILT_IN_BASE: &str = "<built-in>/scenes";
/// The files under `assets/` built into the binary, for the built-in scene.
const BUILT_IN: [(&str, &[u8]); 2] = [
    ("afm/elaphe-100px.png", include_bytes!("../../assets/afm/elaphe-100px.png")),
    ("afm/xenopeltis-100px.png", include_bytes!("../../assets/afm/xenopeltis-100px.png")),
];

/// The built-in bytes of `file` when it names one of [`BUILT_IN`] from [`BUILT_IN_BASE`].
fn built_in(file: &Path) -> Option<&'static [u8]> {
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
/// The approach of a material that names none: the baked table (FLSS stays the reference, a material or the
/// command line can ask for it).
pub const DEFAULT_APPROACH: Approach = Approach::Baked;
/// The name the default scene reports in messages.
pub const DEFAULT_SCENE_NAME: &str = "assets/scenes/elaphe-snake.toml (built in)";

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    camera: CameraDef,
    light: LightDef,
    #[serde(default, rename = "object")]
    objects: Vec<Spanned<ObjectDef>>,
    #[serde(default)]
    material: BTreeMap<String, Spanned<MaterialDef>>,
    #[serde(default)]
    render: RenderDef,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraDef {
    position: Spanned<[f32; 3]>,
    target: [f32; 3],
    fov_y_deg: Spanned<f32>,
    #[serde(default = "default_up")]
    up: [f32; 3],
    #[serde(default = "default_near")]
    near: f32,
    #[serde(default = "default_far")]
    far: f32,
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}
fn default_near() -> f32 {
    0.01
}
fn default_far() -> f32 {
    1000.0
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightDef {
    /// Towards the sun; optional under a map that holds its sun (the map's is taken) or to light by the map alone.
    direction: Option<Spanned<[f32; 3]>>,
    illuminant: Option<Spanned<String>>,
    /// Radiance of a uniform sky, relative to the sun seen in a mirror (a clear sky is ~1e-5 of that).
    #[serde(default)]
    ambient: Option<Spanned<f32>>,
    /// "sky" (the default, unless `ambient` is given): the clear-sky model around the light's sun; "FILE.exr" or
    /// "FILE.hdr": an HDR map of the sky around it; "none": no environment (the sun alone, relative units).
    environment: Option<Spanned<String>>,
    /// The sky's turbidity (environment = "sky").
    turbidity: Option<Spanned<f64>>,
    /// The sky's model (environment = "sky"): "hosek-wilkie" (the default) or "preetham".
    sky_model: Option<Spanned<String>>,
    /// An environment map's turn about the up axis, degrees, and the factor on its radiance.
    rotation_deg: Option<Spanned<f64>>,
    intensity: Option<Spanned<f64>>,
    /// The sun's shadows (a shadow map); on by default where the scene has a ground.
    shadows: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectDef {
    mesh: Option<Spanned<String>>,
    shape: Option<Shape>,
    /// The snake's skin pattern (shape = "snake" only).
    pattern: Option<crate::scene::mesh::snake::Pattern>,
    /// How high the snake's scales are domed, relative to their half-width (shape = "snake" only).
    scale_dome: Option<Spanned<f32>>,
    material: Spanned<String>,
    #[serde(default)]
    translate: [f32; 3],
    #[serde(default)]
    rotate_deg: [f32; 3],
    scale: Option<Spanned<f32>>,
}

/// `tile = 10` or `tile = [10, 4]`.
#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum TileDef {
    Both(u32),
    Each([u32; 2]),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialDef {
    heightfield: Option<Spanned<String>>,
    generate: Option<PatchKind>,
    pixel_size_um: Option<f64>,
    height_um: Option<f64>,
    /// Generated patches: edge length, period and seed.
    size_um: Option<f64>,
    period_um: Option<f64>,
    seed: Option<u64>,
    tile: Option<TileDef>,
    /// Extend the patch to this size (µm) without a period (`physics::extend`), instead of tiling it.
    extend_um: Option<f64>,
    /// The speed/accuracy settings (`src/material/settings.rs`), under their keys.
    #[serde(flatten)]
    settings: SettingsPatch,
    /// Rotation of the patch about the normal, from the mesh tangent towards the bitangent.
    #[serde(default)]
    orientation_deg: f32,
    /// Linear RGB albedo of the skin's pigment under the grating.
    #[serde(default)]
    pigment: [f32; 3],
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RenderDef {
    width: Option<u32>,
    height: Option<u32>,
    exposure_ev: Option<f64>,
    /// Linear RGB behind the objects.
    background: Option<[f32; 3]>,
    /// Samples per pixel (multisample anti-aliasing; 1: none).
    samples: Option<u32>,
}

/// A material of a loaded scene.
#[derive(Clone, Debug)]
pub struct SceneMaterial {
    pub name: String,
    pub heightfield: HeightField,
    pub settings: Settings,
    pub orientation_deg: f32,
    pub pigment: [f32; 3],
    /// Pigment only (a material with neither heightfield nor generate, such as a ground's): a Lambertian albedo
    /// with no grating and no skin over it. `heightfield` is then a small flat patch that nothing draws.
    pub matte: bool,
}

/// An object of a loaded scene.
#[derive(Clone, Debug)]
pub struct SceneObject {
    pub mesh: Mesh,
    pub model: Mat4,
    pub material: usize,
    /// Whether it casts the sun's shadow (everything but the ground does; every object receives it).
    pub casts_shadow: bool,
}

/// Image settings a scene may carry (the command line overrides them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Stops of exposure; None: measured from the frame ([`crate::display::AutoExposure`]).
    pub exposure_ev: Option<f64>,
    pub background: [f32; 3],
    /// Samples per pixel: multisample anti-aliasing of edges (1: none). The device must support the count.
    pub samples: u32,
}

/// Samples per pixel when a scene does not say: edges anti-aliased by 4× multisampling, which every Vulkan
/// device supports.
pub const DEFAULT_SAMPLES: u32 = 4;

/// A loaded, checked scene.
#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub camera: Camera,
    /// World-space unit vector towards the light.
    pub light_dir: Vec3,
    /// The sky's radiance relative to the sun seen in a mirror.
    pub ambient: f32,
    /// The light's spectrum (`[light] illuminant`, D65 unless named; the sky model's sun under `environment =
    /// "sky"`); every material is prepared under it.
    pub illuminant: Illuminant,
    /// The light around the sun (`[light] environment`: the clear sky or an HDR map), which lights the pigment
    /// instead of `ambient`; with one the frame is in physical units.
    pub environment: Option<Environment>,
    /// Whether the sun casts shadows (`[light] shadows`; by default where the scene has a ground).
    pub shadows: bool,
    /// Whether the environment is drawn behind the objects: where there is one and `[render] background` sets no
    /// colour.
    pub environment_behind: bool,
    pub objects: Vec<SceneObject>,
    pub materials: Vec<SceneMaterial>,
    pub render: RenderSettings,
}

/// The clear sky around a scene's sun ([`crate::physics::sky`]), over a ground of [`SKY_GROUND_ALBEDO`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyLight {
    pub turbidity: f64,
    pub model: crate::physics::sky::SkyModel,
}

/// What lights a scene besides its sun.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The clear-sky model around the sun.
    Sky(SkyLight),
    /// An HDR map of the sky around the sun, from a file.
    Map(std::sync::Arc<MapLight>),
}

/// An equirectangular HDR map (`[light] environment = "FILE.exr"`): linear RGB radiance in its own units (cd/m²
/// from `diffract gen sky`, relative from a camera), times `intensity`, turned by `rotation_deg` about the up axis.
/// Where it holds a sun ([`crate::light::sun`]), the sun is taken out of it and becomes the scene's light, in the
/// map's units; otherwise the scene's sun is `[light] direction` with the clear-sky model's radiance, or there is
/// none and the map lights the scene alone. The frame is in units of the sun's radiance (the map's own units
/// where it has no sun).
#[derive(Clone, Debug, PartialEq)]
pub struct MapLight {
    pub path: PathBuf,
    /// The map, its sun (if it held one) taken out.
    pub map: crate::light::environment::EnvironmentMap,
    pub rotation_deg: f64,
    pub intensity: f64,
    /// The map's irradiance (E/π in its units, scaled and turned; without its sun).
    pub irradiance: crate::physics::sh::Irradiance,
    pub sun: MapSun,
    /// The texels the sun was taken out of, as the file had them (index, radiance): drawn behind the scene.
    pub sun_texels: Vec<(usize, [f32; 3])>,
}

/// Where the sun of a scene under a map comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapSun {
    /// The map's own, found in it (in the map's frame: [`MapLight::rotation_deg`] turns it).
    Found(crate::light::sun::FoundSun),
    /// `[light] direction`, with the clear-sky model's sun (a map without one, in cd/m²).
    Model,
    /// None: the map lights the scene alone.
    Alone,
}

impl Environment {
    /// Its irradiance on the pigment for the sun towards `light_dir`: nine SH coefficients of E/π in units of the
    /// sun's radiance (zero while the sun is below the horizon, where that unit is not defined).
    pub fn irradiance(&self, light_dir: Vec3) -> [[f32; 4]; 9] {
        match self {
            Environment::Sky(sky) => sky.irradiance(light_dir),
            Environment::Map(m) => match self.sun_luminance(light_dir) {
                Some(sun) => {
                    crate::physics::sh::Irradiance { coefficients: m.irradiance.coefficients.map(|c| c / sun) }
                        .to_vec4s()
                }
                None => [[0.0; 4]; 9],
            },
        }
    }

    /// The map the environment is, with the sun towards `light_dir` in it (`with_sun`, what is drawn behind a
    /// scene) or without it (what its diffraction reads at the mirror direction: the sun diffracts as the scene's
    /// light), the factor from its texels to the frame's units and its turn about +y (radians); None while the sun
    /// is below the horizon. The clear sky is rendered at `sky_width` texels across.
    pub fn panorama(
        &self,
        light_dir: Vec3,
        with_sun: bool,
        sky_width: u32,
    ) -> Result<Option<(std::borrow::Cow<'_, crate::light::environment::EnvironmentMap>, f64, f64)>> {
        let Some((scale, rotation)) = self.panorama_units(light_dir) else { return Ok(None) };
        let map = match self {
            // Behind the scene the map's sun is drawn as the file has it; the light it gives is the directional one.
            Environment::Map(m) if with_sun && !m.sun_texels.is_empty() => {
                let mut map = m.map.clone();
                for &(i, rgb) in &m.sun_texels {
                    map.rgb[i] = rgb;
                }
                std::borrow::Cow::Owned(map)
            }
            Environment::Map(m) => std::borrow::Cow::Borrowed(&m.map),
            Environment::Sky(sky) => {
                let model = sky.sky(light_dir)?;
                std::borrow::Cow::Owned(if with_sun {
                    crate::light::environment::EnvironmentMap::of_sky_and_sun(&model, sky_width, SKY_GROUND_ALBEDO)?
                } else {
                    crate::light::environment::EnvironmentMap::of_sky(&model, sky_width, SKY_GROUND_ALBEDO)?
                })
            }
        };
        Ok(Some((map, scale, rotation)))
    }

    /// [`Self::panorama`]'s factor from the map's texels to the frame's units and its turn (radians), without the
    /// map; None while the sun is below the horizon.
    pub fn panorama_units(&self, light_dir: Vec3) -> Option<(f64, f64)> {
        let sun = self.sun_luminance(light_dir)?;
        Some(match self {
            Environment::Map(m) => (m.intensity / sun, m.rotation_deg.to_radians()),
            Environment::Sky(_) => (1.0 / sun, 0.0),
        })
    }

    /// The sun's luminance, the frame's unit, which an environment's radiance is divided by: the model's sun
    /// towards `light_dir` through [`Self::turbidity`] (cd/m²; None while it is below the horizon), a map's own sun
    /// as a disc of the sun's solid angle (in the map's units, times its intensity), or 1 (the map's own units) for
    /// a map that lights the scene alone.
    pub fn sun_luminance(&self, light_dir: Vec3) -> Option<f64> {
        if let Environment::Map(m) = self {
            match m.sun {
                MapSun::Found(sun) => {
                    return Some(sun.illuminance() * m.intensity / crate::physics::optics::SUN_SOLID_ANGLE)
                }
                MapSun::Alone => return Some(1.0),
                MapSun::Model => {}
            }
        }
        crate::physics::sky::Sky::new(self.turbidity(), light_dir.as_dvec3()).ok().map(|s| s.sun_xyz().y)
    }

    /// One line for the user: what the environment does in a frame and what it does not (yet).
    pub fn describe(&self) -> String {
        let what = match self {
            Environment::Sky(sky) => {
                format!("the clear sky ({}, turbidity {})", sky.model.citation(), crate::error::number(sky.turbidity))
            }
            Environment::Map(m) => format!(
                "{} ({}×{} texels, intensity {}, turned {}°; {})",
                m.path.display(),
                m.map.width,
                m.map.height,
                crate::error::number(m.intensity),
                crate::error::number(m.rotation_deg),
                match m.sun {
                    MapSun::Found(_) => "its own sun is the light",
                    MapSun::Model => "the sun is [light] direction's",
                    MapSun::Alone => "no sun",
                }
            ),
        };
        format!(
            "environment: {what} lights the pigment (nine SH coefficients) and diffracts, by the BRDF's moments \
             against its l ≤ 2 radiance (the sun diffracts as the directional light)"
        )
    }

    /// The turbidity the sun's spectrum is seen through: the sky's, or the model's default under a map.
    pub fn turbidity(&self) -> f64 {
        match self {
            Environment::Sky(sky) => sky.turbidity,
            Environment::Map(_) => crate::physics::illuminant::SUN_TURBIDITY,
        }
    }
}

/// The albedo of the ground below a scene's sky (grass and soil, about 0.2).
pub const SKY_GROUND_ALBEDO: f64 = crate::physics::sky::GROUND_ALBEDO;

impl SkyLight {
    /// The sky model around the sun towards `light_dir`, over a ground of [`SKY_GROUND_ALBEDO`].
    pub fn sky(&self, light_dir: Vec3) -> Result<crate::physics::sky::Sky> {
        crate::physics::sky::Sky::of_model(self.model, self.turbidity, light_dir.as_dvec3(), SKY_GROUND_ALBEDO)
    }

    /// The sky's irradiance on the pigment for the sun towards `light_dir` (nine SH coefficients of E/π in units
    /// of the sun's radiance: `environment::sky_irradiance`); zero while the sun is below the horizon (night: the
    /// model is for daylight). The last result is kept: a viewer asks every frame, for the same light.
    pub fn irradiance(&self, light_dir: Vec3) -> [[f32; 4]; 9] {
        type Memo = Option<((u64, crate::physics::sky::SkyModel, [u32; 3]), [[f32; 4]; 9])>;
        static LAST: std::sync::Mutex<Memo> = std::sync::Mutex::new(None);
        let key = (self.turbidity.to_bits(), self.model, light_dir.to_array().map(f32::to_bits));
        let mut last = LAST.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((k, sh)) = *last {
            if k == key {
                return sh;
            }
        }
        let sh = match self.sky(light_dir) {
            Ok(sky) => crate::light::environment::sky_irradiance(&sky, SKY_GROUND_ALBEDO).to_vec4s(),
            Err(_) => [[0.0; 4]; 9],
        };
        *last = Some((key, sh));
        sh
    }
}

/// `[light] environment`, `turbidity`, `rotation_deg` and `intensity`: the sky, a map, or none; refused where the
/// light is below the horizon, where a uniform `ambient` sky would light the pigment twice, for a turbidity outside
/// the model's range, a map that cannot be used, or keys that belong to another kind.
fn environment(
    loc: &Locator<'_>,
    base: &Path,
    light: &LightDef,
    direction: Option<Vec3>,
) -> Result<(Option<Environment>, Vec3)> {
    // Outside a map the sun is [light] direction, which must be given.
    let required = || {
        direction.ok_or_else(|| {
            loc.whole(
                "[light] direction is missing: the direction towards the sun (it may be left out only under \
                 environment = \"FILE.exr\", whose map then gives the sun, or lights the scene alone)",
            )
        })
    };
    // A scene that names no environment is outdoors, under the clear sky, unless it lights its pigment by the
    // thesis's uniform grey sky (`ambient`, relative units): then the sun alone, as `environment = "none"`.
    let implicit = light.environment.is_none();
    let kind = match &light.environment {
        // As written: a file's name is used as given, byte for byte (the keywords are matched trimmed).
        Some(e) => Some((e.get_ref().to_string(), e.span())),
        None => {
            light.ambient.is_none().then(|| ("sky".to_string(), light.direction.as_ref().map_or(0..0, |d| d.span())))
        }
    };
    let named = |name: &str| kind.as_ref().is_some_and(|(k, _)| k.trim().eq_ignore_ascii_case(name));
    let is_file = |k: &str| {
        let lower = k.to_ascii_lowercase();
        lower.ends_with(".exr") || lower.ends_with(".hdr")
    };
    if let Some((k, span)) = kind.as_ref().filter(|(k, _)| k.trim() != k && is_file(k.trim())) {
        return Err(loc.at(
            span.clone(),
            format!("environment {k:?}: the file name begins or ends with spaces; a name is used as written"),
        ));
    }
    if let Some((k, span)) = kind.as_ref().filter(|(k, _)| !(is_file(k) || named("sky") || named("none"))) {
        return Err(loc.at(
            span.clone(),
            format!("environment {k:?}: expected \"sky\" (the clear-sky model), \"FILE.exr\" or \"FILE.hdr\" (an HDR map) or \"none\""),
        ));
    }
    if !kind.as_ref().is_some_and(|(k, _)| is_file(k)) {
        if let Some(key) = [&light.rotation_deg, &light.intensity].iter().find_map(|k| k.as_ref()) {
            return Err(loc.at(key.span(), "rotation_deg and intensity belong to environment = \"FILE.exr\" (a map)"));
        }
    }
    if let Some(t) = light.turbidity.as_ref().filter(|_| !named("sky")) {
        return Err(loc.at(t.span(), "turbidity belongs to environment = \"sky\""));
    }
    if let Some(m) = light.sky_model.as_ref().filter(|_| !named("sky")) {
        return Err(loc.at(m.span(), "sky_model belongs to environment = \"sky\""));
    }
    let model = match &light.sky_model {
        Some(m) => crate::physics::sky::SkyModel::named(m.get_ref()).map_err(|e| loc.at(m.span(), e))?,
        None => crate::physics::sky::SkyModel::default(),
    };
    let none = named("none");
    let Some((k, span)) = kind.filter(|_| !none) else { return Ok((None, required()?)) };
    if let Some(a) = light.ambient.as_ref().filter(|a| *a.get_ref() != 0.0) {
        return Err(loc.at(a.span(), format!("ambient and environment = {k:?} would both light the pigment: keep one")));
    }
    if is_file(&k) {
        return map_light(loc, base, light, (&k, span), direction)
            .map(|(m, light_dir)| (Some(Environment::Map(std::sync::Arc::new(m))), light_dir));
    }
    let light_dir = required()?;
    let turbidity = light.turbidity.as_ref().map_or(crate::physics::illuminant::SUN_TURBIDITY, |t| *t.get_ref());
    let sky = SkyLight { turbidity, model };
    sky.sky(light_dir).map_err(|e| {
        let at = light.turbidity.as_ref().map_or(span, |t| t.span());
        if implicit {
            let hint = "the scene names no [light] environment, so it is under the clear sky; environment = \"none\" \
                        lights it by the sun alone";
            loc.at(at, format!("{e} ({hint})"))
        } else {
            loc.at(at, format!("environment = \"sky\": {e}"))
        }
    })?;
    Ok((Some(Environment::Sky(sky)), light_dir))
}

/// `environment = "FILE.exr"` (named `file`, at `span`) with its `rotation_deg` and `intensity`: the map loaded
/// and checked, its sun found and taken out, and the scene's light direction (the map's sun's, else
/// `direction`, else none: the map alone). Refused where the sun is below the horizon.
fn map_light(
    loc: &Locator<'_>,
    base: &Path,
    light: &LightDef,
    (file, span): (&str, std::ops::Range<usize>),
    direction: Option<Vec3>,
) -> Result<(MapLight, Vec3)> {
    let number = |v: &Option<Spanned<f64>>, default: f64, what: &str, ok: &dyn Fn(f64) -> bool| {
        let x = v.as_ref().map_or(default, |v| *v.get_ref());
        if ok(x) {
            Ok(x)
        } else {
            Err(loc.at(v.as_ref().map_or(span.clone(), |v| v.span()), what.to_string()))
        }
    };
    let rotation_deg = number(&light.rotation_deg, 0.0, "rotation_deg must be a finite angle", &|x| x.is_finite())?;
    let intensity =
        number(&light.intensity, 1.0, "intensity must be a positive, finite factor", &|x| x.is_finite() && x > 0.0)?;
    let direction_span = light.direction.as_ref().map_or(span.clone(), |d| d.span());
    let path = base.join(file);
    let loaded = crate::light::environment::EnvironmentMap::load(&path).map_err(|e| loc.at(span.clone(), e))?;
    let search = crate::light::sun::find(&loaded);
    let turn = glam::DQuat::from_rotation_y(rotation_deg.to_radians());
    let (map, sun, light_dir, sun_texels) = match (search.sun, search.rest) {
        (Some(found), Some(rest)) => {
            let world = (turn * found.direction).as_vec3();
            let (elevation, azimuth) =
                (f64::from(world.y).asin().to_degrees(), f64::from(world.x.atan2(world.z)).to_degrees());
            if world.y <= 0.0 {
                return Err(loc.at(
                    span,
                    format!(
                        "environment {file:?}: its sun ({}) lies {:.2}° below the horizon after rotation_deg: turn or \
                         flip the map so that its sky is up",
                        found.describe(),
                        -elevation
                    ),
                ));
            }
            log::info!(
                target: crate::io::LOG_PLAIN,
                "{file}: {} (world: {elevation:.2}° elevation, {azimuth:.2}° azimuth): taken out of the map and made the \
                 scene's light, in the map's units",
                found.describe()
            );
            if let Some(second) = search.second {
                log::warn!(
                    "{file}: a second sun, {}, is left in the map (the brighter one is the light)",
                    second.describe()
                );
            }
            if let Some(given) = direction {
                log::warn!(
                    "{file}: the map's sun is the light; [light] direction [{:.3}, {:.3}, {:.3}] is not used",
                    given.x,
                    given.y,
                    given.z
                );
            }
            (rest.map, MapSun::Found(found), world, rest.texels)
        }
        _ => match direction {
            Some(d) => {
                crate::physics::sky::Sky::new(crate::physics::illuminant::SUN_TURBIDITY, d.as_dvec3())
                    .map_err(|e| loc.at(direction_span, format!("environment = {file:?}: the sun: {e}")))?;
                log::info!(
                    target: crate::io::LOG_PLAIN,
                    "{file}: no sun in the map; the scene's sun is [light] direction, with the clear-sky model's radiance"
                );
                (loaded, MapSun::Model, d, Vec::new())
            }
            None => {
                log::info!(
                    target: crate::io::LOG_PLAIN,
                    "{file}: no sun in the map and no [light] direction: the map lights the scene alone"
                );
                (loaded, MapSun::Alone, Vec3::Y, Vec::new())
            }
        },
    };
    let irradiance = map.irradiance(intensity, rotation_deg);
    Ok((MapLight { path, map, rotation_deg, intensity, irradiance, sun, sun_texels }, light_dir))
}

/// Errors located in a scene file: `file:line: message`.
struct Locator<'a> {
    name: &'a str,
    text: &'a str,
}

impl Locator<'_> {
    fn line(&self, offset: usize) -> usize {
        self.text[..offset.min(self.text.len())].matches('\n').count() + 1
    }

    fn at(&self, span: std::ops::Range<usize>, message: impl std::fmt::Display) -> Error {
        Error::Scene { file: self.name.to_string(), line: Some(self.line(span.start)), message: message.to_string() }
    }

    fn whole(&self, message: impl std::fmt::Display) -> Error {
        Error::Scene { file: self.name.to_string(), line: None, message: message.to_string() }
    }
}

impl Scene {
    /// Loads a scene file.
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = crate::io::input::read(path, crate::io::input::MAX_SCENE_BYTES, "scene")?;
        let text = String::from_utf8(bytes).map_err(|_| Error::input(path, "is not UTF-8 text (a TOML scene)"))?;
        let base = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        Self::parse(&text, &path.display().to_string(), base)
    }

    /// Material `m`'s settings under `overrides` (the command line's, a profile configuration's): under the sky a
    /// light the overrides name is in physical units too.
    pub fn material_settings(&self, m: &SceneMaterial, overrides: &crate::material::SettingsPatch) -> Settings {
        let mut s = overrides.apply(m.settings);
        if self.environment.is_some() {
            s.illuminant = s.illuminant.physical();
        }
        s
    }

    /// How much of the directional sun lights the scene: 1, or 0 where a map without a sun lights it alone
    /// (`SurfaceUniforms::light_dir`'s w).
    pub fn sun_strength(&self) -> f32 {
        match &self.environment {
            Some(Environment::Map(m)) if m.sun == MapSun::Alone => 0.0,
            _ => 1.0,
        }
    }

    /// The built-in default scene.
    pub fn default_scene() -> Result<Self> {
        Self::parse(DEFAULT_SCENE, DEFAULT_SCENE_NAME, Path::new(BUILT_IN_BASE))
    }

    /// Parses scene text; `name` appears in messages and `base` resolves relative paths.
    pub fn parse(text: &str, name: &str, base: &Path) -> Result<Self> {
        let loc = Locator { name, text };
        let file: SceneFile = toml::from_str(text).map_err(|e| {
            let message = e.message().replace('\n', " ");
            match e.span() {
                Some(span) => loc.at(span, message.trim()),
                None => loc.whole(message.trim()),
            }
        })?;
        let camera = camera(&loc, &file.camera)?;
        let direction = match &file.light.direction {
            Some(d) => Some(
                Vec3::from(*d.get_ref())
                    .try_normalize()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| loc.at(d.span(), "the light direction must be a finite, non-zero vector"))?,
            ),
            None => None,
        };
        let direction_span = file.light.direction.as_ref().map_or(0..0, |d| d.span());
        let (environment, light_dir) = environment(&loc, base, &file.light, direction)?;
        let map_sun = match &environment {
            Some(Environment::Map(m)) => Some(m.sun),
            _ => None,
        };
        let sun = |span| {
            // The sun at the light's own elevation, to 0.01° (the direction is f32: the name reads cleanly and the
            // spectrum does not notice).
            let elevation = (f64::from(light_dir.y).asin().to_degrees() * 100.0).round() / 100.0;
            let turbidity =
                environment.as_ref().map_or(crate::physics::illuminant::SUN_TURBIDITY, Environment::turbidity);
            Illuminant::sun(elevation, turbidity).map_err(|e| loc.at(span, e))
        };
        let illuminant = match (&file.light.illuminant, map_sun) {
            // A map's own sun has its own colour: upsampled from its RGB as the map's light is.
            (None | Some(_), Some(MapSun::Found(found)))
                if file.light.illuminant.as_ref().is_none_or(|i| i.get_ref().trim().eq_ignore_ascii_case("sun")) =>
            {
                Illuminant::of_linear_srgb(found.irradiance, "the map's sun")
                    .map_err(|e| loc.at(direction_span.clone(), e))?
            }
            (Some(ill), _) if ill.get_ref().trim().eq_ignore_ascii_case("sun") => sun(ill.span())?,
            (Some(ill), _) => Illuminant::parse(ill.get_ref(), base).map_err(|e| loc.at(ill.span(), e))?,
            // Under an environment the sun is the sky model's (none lights a map alone: its colour is unused).
            (None, Some(MapSun::Alone)) => Illuminant::d65(),
            (None, _) if environment.is_some() => sun(direction_span.clone())?,
            (None, _) => Illuminant::d65(),
        };
        // Under the sky the frame is in physical units: the diffraction in its true ratio to the sky-lit pigment.
        let illuminant = if environment.is_some() { illuminant.physical() } else { illuminant };
        let mut materials = Vec::new();
        let mut index = BTreeMap::new();
        for (mat_name, def) in &file.material {
            index.insert(mat_name.clone(), materials.len());
            materials.push(material(&loc, base, mat_name, def, illuminant)?);
        }
        if file.objects.is_empty() {
            return Err(loc.whole("the scene has no [[object]]"));
        }
        let mut objects = Vec::new();
        for def in &file.objects {
            objects.push(object(&loc, base, def, &index)?);
        }
        let render = render_settings(&loc, &file.render)?;
        let ambient = file.light.ambient.as_ref().map_or(0.0, |a| *a.get_ref());
        if !(ambient.is_finite() && ambient >= 0.0) {
            return Err(loc.whole("[light] ambient must be a non-negative number"));
        }
        let grounded = objects.iter().any(|o| !o.casts_shadow);
        // Without a sun there is nothing to cast a shadow.
        let shadows = file.light.shadows.unwrap_or(grounded) && map_sun != Some(MapSun::Alone);
        let environment_behind = environment.is_some() && file.render.background.is_none();
        if let (Some(env), Some(bg)) = (&environment, file.render.background) {
            background_units_warning(env, light_dir, bg);
        }
        Ok(Self {
            name: name.to_string(),
            camera,
            light_dir,
            ambient,
            illuminant,
            environment,
            shadows,
            environment_behind,
            objects,
            materials,
            render,
        })
    }
}

/// Warns where `[render] background` under an environment lies orders of magnitude from the environment's own
/// light in the frame's units (the sun's radiance is 1 there): a background of 0.5 under the sky is a hundred
/// thousand skies, which the objects then vanish against.
fn background_units_warning(env: &Environment, light_dir: Vec3, bg: [f32; 3]) {
    // E/π's mean over the sphere: about the environment's mean radiance (half of it where the ground is dark).
    let sh = env.irradiance(light_dir);
    let level = crate::physics::spectrum::luminance([sh[0][0], sh[0][1], sh[0][2]]) * crate::gpu::interface::SH_Y00;
    let colour = crate::physics::spectrum::luminance(bg);
    if level > 0.0 && colour > 0.0 && !(0.01..=100.0).contains(&(colour / level)) {
        log::warn!(
            "[render] background {bg:?} is in the frame's units (the sun's radiance is 1), {:.1e} times the \
             environment's mean radiance ({level:.1e}): the objects will look {} against it, and a measured exposure \
             follows it; leave it out to draw the environment behind them",
            colour / level,
            if colour > level { "black" } else { "glaring" }
        );
    }
}

/// The flat patch behind a matte material: edge and pixel (µm).
const MATTE_PATCH_UM: f64 = 4.0;
const MATTE_PIXEL_UM: f64 = 0.25;

/// The largest coordinate, scale or angle a scene may give (world units are arbitrary, but f32 transforms of
/// larger values lose the mesh or overflow).
const MAX_COORDINATE: f32 = 1e6;

/// Three finite numbers of at most [`MAX_COORDINATE`] in magnitude.
fn check_coords(loc: &Locator<'_>, span: std::ops::Range<usize>, what: &str, v: &[f32; 3]) -> Result<()> {
    if v.iter().all(|x| x.is_finite() && x.abs() <= MAX_COORDINATE) {
        return Ok(());
    }
    Err(loc.at(span, format!("{what} = {v:?}: expected three finite numbers within ±{MAX_COORDINATE:e}")))
}

trait Get3 {
    fn get3(&self) -> [f32; 3];
}

/// The `[camera]` table, checked: finite coordinates, an up vector off the line of sight, a field of view inside
/// (0°, 180°) and a usable depth range.
fn camera(loc: &Locator<'_>, c: &CameraDef) -> Result<Camera> {
    let cam_span = c.position.span();
    check_coords(loc, cam_span.clone(), "[camera] position", c.position.get_ref())?;
    check_coords(loc, cam_span.clone(), "[camera] target", &c.target)?;
    check_coords(loc, cam_span.clone(), "[camera] up", &c.up)?;
    let forward = Vec3::from(c.target) - Vec3::from(*c.position.get_ref());
    if forward.length() > 0.0 && forward.normalize().cross(Vec3::from(c.up)).length() < 1e-6 {
        return Err(loc.at(cam_span.clone(), "[camera] up is parallel to the line of sight (or zero)"));
    }
    if c.position.get3() == c.target {
        return Err(loc.at(c.position.span(), "the camera position equals its target"));
    }
    let fov = *c.fov_y_deg.get_ref();
    if !(fov > 0.0 && fov < 180.0) {
        return Err(loc
            .at(c.fov_y_deg.span(), format!("fov_y_deg = {fov}: expected a field of view between 0 and 180 degrees")));
    }
    if !(c.near > 0.0 && c.far > c.near && c.far.is_finite() && c.far / c.near <= 1e7) {
        return Err(loc.whole("the camera needs 0 < near < far, finite, with far/near at most 1e7"));
    }
    Ok(Camera {
        position: Vec3::from(*c.position.get_ref()),
        target: Vec3::from(c.target),
        up: Vec3::from(c.up),
        fov_y_deg: fov,
        near: c.near,
        far: c.far,
    })
}

/// The `[render]` table with its defaults, checked.
fn render_settings(loc: &Locator<'_>, r: &RenderDef) -> Result<RenderSettings> {
    let render = RenderSettings {
        width: r.width.unwrap_or(512),
        height: r.height.unwrap_or(512),
        exposure_ev: r.exposure_ev,
        background: r.background.unwrap_or([0.0; 3]),
        samples: r.samples.unwrap_or(DEFAULT_SAMPLES),
    };
    if !(render.samples.is_power_of_two() && render.samples <= 64) {
        return Err(loc.whole("[render] samples is a power of two: 1 (no anti-aliasing), 2, 4, 8, …"));
    }
    let max = crate::display::MAX_EXPOSURE_EV;
    if render.exposure_ev.is_some_and(|ev| !ev.is_finite() || ev.abs() > max) {
        return Err(loc.whole(format!("[render] exposure_ev must be a number of stops within ±{max}")));
    }
    if render.background.iter().any(|c| !(c.is_finite() && *c >= 0.0)) {
        return Err(loc.whole("[render] background is a linear RGB colour: three non-negative numbers"));
    }
    if render.width == 0 || render.height == 0 || render.width > 16384 || render.height > 16384 {
        return Err(loc.whole("[render] width and height must lie in 1..=16384"));
    }
    Ok(render)
}

impl Scene {
    /// Every material's patch (one cell of it, where the scene tiles it) extended to `size_um` × `size_um`
    /// without a period (`--extend-um`: [`crate::physics::extend::extend`]); matte materials have none.
    pub fn extend_patches(&mut self, size_um: f64) -> Result<()> {
        for m in self.materials.iter_mut().filter(|m| !m.matte) {
            m.heightfield = crate::physics::extend::extend(&m.heightfield, size_um)
                .map_err(|e| Error::Invalid(format!("[material.{}] --extend-um: {e}", m.name)))?;
        }
        Ok(())
    }
}

impl Get3 for Spanned<[f32; 3]> {
    fn get3(&self) -> [f32; 3] {
        *self.get_ref()
    }
}

fn material(
    loc: &Locator<'_>,
    base: &Path,
    name: &str,
    def: &Spanned<MaterialDef>,
    illuminant: Illuminant,
) -> Result<SceneMaterial> {
    let span = def.span();
    let d = def.get_ref();
    let at = |msg: String| loc.at(span.clone(), format!("[material.{name}] {msg}"));
    let matte = d.heightfield.is_none() && d.generate.is_none();
    let patch_keys = [d.pixel_size_um, d.height_um, d.size_um, d.period_um].iter().any(Option::is_some);
    if matte && (patch_keys || d.seed.is_some() || d.tile.is_some() || d.extend_um.is_some()) {
        return Err(at(
            "has no heightfield or generate (a matte material: pigment only), so its patch keys mean nothing".into(),
        ));
    }
    let hf =
        match (&d.heightfield, d.generate) {
            (Some(path), None) => {
                let file = base.join(path.get_ref());
                let png = match (d.pixel_size_um, d.height_um) {
                    (Some(pixel_size_um), Some(height_um)) => Some(PngScale { pixel_size_um, height_um }),
                    (None, None) => None,
                    _ => return Err(at("pixel_size_um and height_um go together".into())),
                };
                match (built_in(&file), png) {
                    (Some(bytes), Some(scale)) => crate::physics::formats::png::from_bytes(&file, bytes, scale)
                        .map_err(|e| loc.at(path.span(), e))?,
                    (Some(_), None) => return Err(at("a PNG height field needs pixel_size_um and height_um".into())),
                    (None, _) if !file.exists() => {
                        return Err(loc.at(
                            path.span(),
                            format!("heightfield {:?}: no such file ({})", path.get_ref(), file.display()),
                        ))
                    }
                    (None, png) => crate::physics::formats::load(&file, png).map_err(|e| loc.at(path.span(), e))?,
                }
            }
            (None, Some(kind)) => {
                let mut spec = PatchSpec::new(kind, d.size_um.unwrap_or(13.0), d.pixel_size_um.unwrap_or(0.065));
                spec.period_um = d.period_um.unwrap_or(spec.period_um);
                spec.depth_um = d.height_um.unwrap_or(spec.depth_um);
                spec.seed = d.seed.unwrap_or(1);
                generate(&spec).map_err(|e| at(e.to_string()))?
            }
            (Some(_), Some(_)) => return Err(at("give either heightfield or generate, not both".into())),
            // Matte: a flat patch the renderer never draws (the smallest the preparation accepts).
            (None, None) => generate(&PatchSpec::new(PatchKind::Flat, MATTE_PATCH_UM, MATTE_PIXEL_UM))
                .map_err(|e| at(e.to_string()))?,
        };
    let hf = match (d.tile, d.extend_um) {
        (Some(_), Some(_)) => {
            return Err(at("give tile (repeat the patch) or extend_um (grow it without a period), not both".into()))
        }
        (None, Some(um)) => crate::physics::extend::extend(&hf, um).map_err(|e| at(e.to_string()))?,
        (None, None) => hf,
        (Some(TileDef::Both(n)), None) => hf.tiled(n as usize, n as usize).map_err(|e| at(e.to_string()))?,
        (Some(TileDef::Each([x, y])), None) => hf.tiled(x as usize, y as usize).map_err(|e| at(e.to_string()))?,
    };
    if !f64::from(d.orientation_deg).is_finite() {
        return Err(at(format!("orientation_deg = {}: expected a finite number", d.orientation_deg)));
    }
    d.settings.check().map_err(at)?;
    let mut patch = d.settings;
    // A scene that states its table tolerance means it: a table that cannot reach it is refused.
    patch.strict_table |= patch.table_tolerance.is_some();
    let settings = patch.apply(Settings { approach: DEFAULT_APPROACH, illuminant, ..Settings::default() });
    if d.pigment.iter().any(|c| !(c.is_finite() && *c >= 0.0)) {
        return Err(at("pigment is a linear RGB albedo: three non-negative numbers".into()));
    }
    Ok(SceneMaterial {
        name: name.to_string(),
        heightfield: hf,
        settings,
        orientation_deg: d.orientation_deg,
        pigment: d.pigment,
        matte,
    })
}

fn object(
    loc: &Locator<'_>,
    base: &Path,
    def: &Spanned<ObjectDef>,
    materials: &BTreeMap<String, usize>,
) -> Result<SceneObject> {
    let span = def.span();
    let d = def.get_ref();
    let mesh = match (&d.mesh, d.shape) {
        (Some(path), None) => {
            let file: PathBuf = base.join(path.get_ref());
            obj::load(&file).map_err(|e| loc.at(path.span(), e))?
        }
        (None, Some(Shape::Snake)) => {
            use crate::scene::mesh::snake::{snake, SnakeSpec, MAX_SCALE_DOME};
            let defaults = SnakeSpec::default();
            let scale_dome = match &d.scale_dome {
                Some(dome) if !(0.0..=MAX_SCALE_DOME).contains(dome.get_ref()) => {
                    return Err(loc.at(dome.span(), format!("scale_dome must be between 0 (flat) and {MAX_SCALE_DOME}")))
                }
                Some(dome) => *dome.get_ref(),
                None => defaults.scale_dome,
            };
            snake(&SnakeSpec { pattern: d.pattern.unwrap_or_default(), scale_dome, ..defaults })
        }
        (None, Some(_)) if d.pattern.is_some() || d.scale_dome.is_some() => {
            return Err(loc.at(span, "pattern and scale_dome are for shape = \"snake\""))
        }
        (None, Some(shape)) => shape.build(),
        (Some(_), Some(_)) => return Err(loc.at(span, "an [[object]] has either mesh or shape, not both")),
        (None, None) => return Err(loc.at(span, "an [[object]] needs mesh = \"FILE.obj\" or shape = \"...\"")),
    };
    let material = *materials.get(d.material.get_ref()).ok_or_else(|| {
        let known: Vec<&str> = materials.keys().map(String::as_str).collect();
        loc.at(
            d.material.span(),
            format!("no [material.{}] in the scene (it has: {})", d.material.get_ref(), known.join(", ")),
        )
    })?;
    let scale = d.scale.as_ref().map(|s| *s.get_ref()).unwrap_or(1.0);
    if !(scale.is_finite() && scale > 0.0 && scale <= MAX_COORDINATE) {
        return Err(loc.at(
            d.scale.as_ref().map(|s| s.span()).unwrap_or(span),
            format!("scale must be positive and at most {MAX_COORDINATE:e}"),
        ));
    }
    check_coords(loc, span.clone(), "translate", &d.translate)?;
    check_coords(loc, span.clone(), "rotate_deg", &d.rotate_deg)?;
    let [rx, ry, rz] = d.rotate_deg.map(f32::to_radians);
    let model = Mat4::from_scale_rotation_translation(
        Vec3::splat(scale),
        Quat::from_euler(EulerRot::XYZ, rx, ry, rz),
        Vec3::from(d.translate),
    );
    Ok(SceneObject { mesh, model, material, casts_shadow: d.shape != Some(Shape::Ground) })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
[camera]
position = [0.0, 0.5, 3.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 30.0

[light]
direction = [0.3, 1.0, 0.5]
illuminant = "D65"
environment = "none"
[[object]]
shape = "sphere"
material = "blaze"
scale = 0.5

[material.blaze]
generate = "blazed"
size_um = 6.5
approach = "nmm"
tile = [2, 3]
"#;

    fn error_of(text: &str) -> String {
        Scene::parse(text, "s.toml", Path::new(".")).expect_err("refused").to_string()
    }

    /// A ground (matte: a material without a patch) turns the sun's shadows on unless the scene says otherwise;
    /// it receives them and casts none; a matte material refuses patch keys.
    #[test]
    fn a_ground_is_matte_receives_shadows_and_casts_none() {
        assert!(!Scene::parse(GOOD, "s.toml", Path::new(".")).unwrap().shadows, "no ground, no shadows");
        let ground = format!("{GOOD}\n[[object]]\nshape = \"ground\"\nmaterial = \"soil\"\n\n[material.soil]\npigment = [0.2, 0.2, 0.2]\n");
        let s = Scene::parse(&ground, "s.toml", Path::new(".")).unwrap();
        assert!(s.shadows);
        assert_eq!(s.objects.iter().map(|o| o.casts_shadow).collect::<Vec<_>>(), [true, false]);
        let soil = s.materials.iter().find(|m| m.name == "soil").unwrap();
        assert!(soil.matte && !s.materials.iter().find(|m| m.name == "blaze").unwrap().matte);
        let ground_mesh = &s.objects[1].mesh;
        assert!(ground_mesh.vertices.iter().all(|v| v.position[1] == 0.0 && v.normal == [0.0, 1.0, 0.0]));
        let off = ground.replace("illuminant = \"D65\"", "illuminant = \"D65\"\nshadows = false");
        assert!(!Scene::parse(&off, "s.toml", Path::new(".")).unwrap().shadows);
        let on = GOOD.replace("illuminant = \"D65\"", "illuminant = \"D65\"\nshadows = true");
        assert!(Scene::parse(&on, "s.toml", Path::new(".")).unwrap().shadows);
        let e = error_of(&ground.replace("pigment = [0.2, 0.2, 0.2]", "pigment = [0.2, 0.2, 0.2]\nperiod_um = 2.0"));
        assert!(e.contains("[material.soil]") && e.contains("matte"), "{e}");
    }

    /// `environment = "FILE.exr"`: the map lights the pigment as the sky it holds would (a map of the clear sky
    /// without its sun gives the sky's nine coefficients within 2e-4 of the largest: measured 5.0e-5), in
    /// physical units under the model's sun;
    /// a map that holds a sun, map keys without a map and a turbidity with one are refused.
    #[test]
    fn an_environment_map_lights_the_scene_as_its_sky_would() {
        let dir = std::env::temp_dir().join(format!("diffract-scene-env-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let light_dir = Vec3::new(-0.3, 0.6, 0.5).normalize();
        let sky = crate::physics::sky::Sky::new(3.0, light_dir.as_dvec3()).unwrap();
        for (name, map) in [
            ("around.exr", crate::light::environment::EnvironmentMap::of_sky(&sky, 512, SKY_GROUND_ALBEDO).unwrap()),
            (
                "sunny.exr",
                crate::light::environment::EnvironmentMap::of_sky_and_sun(&sky, 64, SKY_GROUND_ALBEDO).unwrap(),
            ),
        ] {
            crate::io::output::write_exr_rgb(&dir.join(name), map.width, map.height, &map.to_rgba()).unwrap();
        }
        let [x, y, z] = light_dir.to_array();
        let text = GOOD.replace("direction = [0.3, 1.0, 0.5]", &format!("direction = [{x}, {y}, {z}]"));
        assert!(text.contains(&format!("direction = [{x}")), "GOOD's light moved");
        let with = |light: &str| text.replace("illuminant = \"D65\"\nenvironment = \"none\"", light);
        let map = Scene::parse(&with("environment = \"around.exr\""), "s.toml", &dir).unwrap();
        let sky = Scene::parse(&with("environment = \"sky\""), "s.toml", &dir).unwrap();
        assert!(matches!(map.environment, Some(Environment::Map(_))));
        assert_eq!((map.illuminant, map.illuminant.physical), (sky.illuminant, true));
        let (a, b) = (map.environment.as_ref().unwrap(), sky.environment.as_ref().unwrap());
        let (a, b) = (a.irradiance(light_dir), b.irradiance(light_dir));
        let size = b.iter().map(|c| c[0].abs() + c[1].abs() + c[2].abs()).fold(0.0, f32::max);
        for (p, q) in a.iter().zip(&b) {
            for k in 0..3 {
                assert!((p[k] - q[k]).abs() < 2e-4 * size, "map {a:?}\nsky {b:?}");
            }
        }
        // Half the intensity, half the light.
        let dim = Scene::parse(&with("environment = \"around.exr\"\nintensity = 0.5"), "s.toml", &dir).unwrap();
        let half = dim.environment.unwrap().irradiance(light_dir);
        assert!((half[0][2] / a[0][2] - 0.5).abs() < 1e-6);
        let refused = |light: &str, needle: &str| {
            let e = Scene::parse(&with(light), "s.toml", &dir).expect_err("refused").to_string();
            assert!(e.starts_with("s.toml:") && e.contains(needle), "{light}: {e}");
        };
        // A map with its sun (64 texels wide: the sun within one texel of 5.6°): the sun is found, taken out and
        // made the light — its direction within half a texel of the light's, its luminance that of the model's sun
        // (within 3 %: the cap keeps some of the bright sky about the sun), and the pigment lit by the sky once
        // (the map's irradiance in the sun's units within 3 % of the sky's; before, the sun was counted twice).
        let sunny = Scene::parse(&with("environment = \"sunny.exr\""), "s.toml", &dir).unwrap();
        let texel = std::f32::consts::TAU / 64.0;
        assert!(sunny.light_dir.angle_between(light_dir) < 0.5 * texel, "{}", sunny.light_dir);
        let e = sunny.environment.as_ref().unwrap();
        let unit = e.sun_luminance(sunny.light_dir).unwrap();
        let model = crate::physics::sky::Sky::new(3.0, light_dir.as_dvec3()).unwrap().sun_xyz().y;
        assert!((unit / model - 1.0).abs() < 0.03, "{unit:.4e} against {model:.4e}");
        let once = e.irradiance(sunny.light_dir);
        eprintln!(
            "a map's own sun: luminance {:.4}× the model's, the sky's irradiance {:.4}× the sky's",
            unit / model,
            once[0][1] / b[0][1]
        );
        assert!((once[0][1] / b[0][1] - 1.0).abs() < 0.03, "{:?} against {:?}", once[0], b[0]);
        assert!(sunny.illuminant.physical && sunny.illuminant.name.contains("map's sun"));
        // Behind the scene the map is drawn as the file has it, sun included; its light comes without it.
        let file = crate::light::environment::EnvironmentMap::load(&dir.join("sunny.exr")).unwrap();
        let (behind, _, _) = e.panorama(sunny.light_dir, true, 64).unwrap().unwrap();
        let (lighting, _, _) = e.panorama(sunny.light_dir, false, 64).unwrap().unwrap();
        assert!(behind.rgb == file.rgb && lighting.rgb != file.rgb);
        // Without [light] direction too; a map without a sun and without a direction lights the scene alone.
        let no_direction = |light: &str| {
            let text = with(light);
            let start = text.find("direction = [").unwrap();
            let end = start + text[start..].find('\n').unwrap();
            format!("{}{}", &text[..start], &text[end + 1..])
        };
        let found = Scene::parse(&no_direction("environment = \"sunny.exr\""), "s.toml", &dir).unwrap();
        assert_eq!(found.light_dir, sunny.light_dir);
        let alone = Scene::parse(&no_direction("environment = \"around.exr\""), "s.toml", &dir).unwrap();
        assert!(alone.sun_strength() == 0.0 && !alone.shadows && sunny.sun_strength() == 1.0);
        let e = Scene::parse(&no_direction("environment = \"sky\""), "s.toml", &dir).unwrap_err().to_string();
        assert!(e.contains("[light] direction is missing"), "{e}");
        refused("environment = \"missing.hdr\"", "missing.hdr");
        refused("environment = \"sky\"\nrotation_deg = 10.0", "belong to environment = \"FILE.exr\"");
        refused("environment = \"around.exr\"\nturbidity = 3.0", "turbidity belongs");
        refused("environment = \"around.exr\"\nintensity = -1.0", "intensity must be");
        refused("environment = \"around.exr\"\nambient = 0.1", "both light the pigment");
        refused("environment = \"around.png\"", "expected \"sky\"");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `environment = "sky"`: the sky model's sun (at the light's elevation) in physical units, and the sky's
    /// irradiance for the pigment; refused with a second sky (`ambient`), a turbidity out of range or without the
    /// sky, a sun below the horizon, an unknown environment.
    #[test]
    fn a_sky_lights_the_scene_in_physical_units() {
        let sky =
            GOOD.replace("illuminant = \"D65\"\nenvironment = \"none\"", "environment = \"sky\"\nturbidity = 2.5");
        let s = Scene::parse(&sky, "s.toml", Path::new(".")).unwrap();
        let model = crate::physics::sky::SkyModel::HosekWilkie;
        assert_eq!(s.environment, Some(Environment::Sky(SkyLight { turbidity: 2.5, model })));
        let elevation = (f64::from(s.light_dir.y).asin().to_degrees() * 100.0).round() / 100.0;
        assert_eq!(s.illuminant, Illuminant::sun(elevation, 2.5).unwrap().physical());
        assert!(s.illuminant.physical && s.materials[0].settings.illuminant.physical);
        let sh = s.environment.as_ref().unwrap().irradiance(s.light_dir);
        assert!(sh[0][2] > sh[0][0] && sh[0][0] > 0.0, "a blue sky: {:?}", sh[0]);
        // A named light under the sky, from the file or the command line, is in physical units too.
        let lamp = sky.replace("turbidity = 2.5", "illuminant = \"A\"");
        let s = Scene::parse(&lamp, "s.toml", Path::new(".")).unwrap();
        assert_eq!(s.illuminant, Illuminant::named("A").unwrap().physical());
        let mut patch = crate::material::SettingsPatch::default();
        patch.set("illuminant", "F11").unwrap();
        assert!(s.material_settings(&s.materials[0], &patch).illuminant.physical);
        assert!(error_of(&sky.replace("turbidity = 2.5", "ambient = 0.001")).contains("both light the pigment"));
        assert!(error_of(&sky.replace("turbidity = 2.5", "turbidity = 0.5")).contains("turbidity"));
        // Preetham's sky by name: fitted from turbidity 2, so 1.5 is refused there and not under Hosek–Wilkie.
        let preetham = sky.replace("turbidity = 2.5", "sky_model = \"preetham\"");
        let p = Scene::parse(&preetham, "s.toml", Path::new(".")).unwrap();
        let model = crate::physics::sky::SkyModel::Preetham;
        assert_eq!(p.environment, Some(Environment::Sky(SkyLight { turbidity: 3.0, model })));
        assert!(p.environment.as_ref().unwrap().describe().contains("Preetham"));
        assert!(error_of(&preetham.replace("sky_model", "turbidity = 1.5\nsky_model")).contains("Preetham et al."));
        assert!(Scene::parse(&sky.replace("turbidity = 2.5", "turbidity = 1.5"), "s.toml", Path::new(".")).is_ok());
        let prague = error_of(&sky.replace("turbidity = 2.5", "sky_model = \"prague\""));
        assert!(prague.starts_with("s.toml:") && prague.contains("hosek-wilkie"), "{prague}");
        assert!(
            error_of(&GOOD.replace("illuminant = \"D65\"", "sky_model = \"preetham\"")).contains("sky_model belongs")
        );
        assert!(error_of(&GOOD.replace("illuminant = \"D65\"", "turbidity = 3.0")).contains("environment = \"sky\""));
        assert!(error_of(&sky.replace("[0.3, 1.0, 0.5]", "[0.3, -1.0, 0.5]")).contains("below the horizon"));
        let moon = error_of(&sky.replace("\"sky\"", "\"moon\""));
        assert!(moon.starts_with("s.toml:9: ") && moon.contains("\"moon\""), "{moon}");
    }

    /// A scene that names no environment is outdoors: under the clear sky (turbidity 3 unless it names one), in
    /// physical units; one that lights its pigment by the thesis's grey `ambient` sky keeps the sun alone; a sun
    /// below the horizon is refused with the way out.
    #[test]
    fn a_scene_without_an_environment_is_under_the_clear_sky() {
        let outdoors = GOOD.replace("\nenvironment = \"none\"", "");
        let s = Scene::parse(&outdoors, "s.toml", Path::new(".")).unwrap();
        assert_eq!(
            s.environment,
            Some(Environment::Sky(SkyLight { turbidity: 3.0, model: crate::physics::sky::SkyModel::HosekWilkie }))
        );
        assert!(s.illuminant.physical && s.environment_behind);
        let hazy = Scene::parse(&outdoors.replace("illuminant = \"D65\"", "turbidity = 6.0"), "s.toml", Path::new("."));
        assert_eq!(
            hazy.unwrap().environment,
            Some(Environment::Sky(SkyLight { turbidity: 6.0, model: crate::physics::sky::SkyModel::HosekWilkie }))
        );
        let grey = Scene::parse(&outdoors.replace("illuminant = \"D65\"", "ambient = 0.01"), "s.toml", Path::new("."));
        let grey = grey.unwrap();
        assert!(grey.environment.is_none() && !grey.illuminant.physical && grey.ambient == 0.01);
        assert!(error_of(&outdoors.replace("illuminant = \"D65\"", "ambient = 0.01\nturbidity = 3.0"))
            .contains("turbidity belongs"));
        let night = error_of(&outdoors.replace("[0.3, 1.0, 0.5]", "[0.3, -1.0, 0.5]"));
        assert!(night.starts_with("s.toml:8: ") && night.contains("below the horizon"), "{night}");
        assert!(night.contains("environment = \"none\" lights it by the sun alone"), "{night}");
    }

    /// `extend_um` grows the patch without a period instead of tiling it (the pixel kept); with `tile` it is
    /// refused in one line, as on a matte material; `--extend-um` extends every patch of a loaded scene (one cell
    /// of a tiled one).
    #[test]
    fn a_patch_is_extended_or_tiled_not_both() {
        let extended = GOOD.replace("tile = [2, 3]", "extend_um = 13.0");
        let s = Scene::parse(&extended, "s.toml", Path::new(".")).unwrap();
        assert_eq!((s.materials[0].heightfield.nx, s.materials[0].heightfield.ny), (200, 200));
        assert_eq!(s.materials[0].heightfield.period_cell(), (200, 200), "no period");
        let both = error_of(&GOOD.replace("tile = [2, 3]", "tile = [2, 3]\nextend_um = 13.0"));
        assert!(both.contains("give tile") && both.contains("not both"), "{both}");
        assert!(error_of(&GOOD.replace("tile = [2, 3]", "extend_um = 2.0")).contains("smaller than the patch"));
        let mut tiled = Scene::parse(GOOD, "s.toml", Path::new(".")).unwrap();
        tiled.extend_patches(13.0).unwrap();
        assert_eq!((tiled.materials[0].heightfield.nx, tiled.materials[0].heightfield.ny), (200, 200));
    }

    #[test]
    fn a_good_scene_loads() {
        let s = Scene::parse(GOOD, "s.toml", Path::new(".")).unwrap();
        assert_eq!(s.objects.len(), 1);
        assert_eq!(s.materials[0].settings.approach, Approach::Nmm);
        assert_eq!(s.materials[0].heightfield.nx, 2 * 100);
        assert_eq!(s.materials[0].heightfield.ny, 3 * 100);
        assert!((s.light_dir.length() - 1.0).abs() < 1e-6);
        // The light's illuminant reaches every material's settings.
        let a = Scene::parse(&GOOD.replace("\"D65\"", "\"a\""), "s.toml", Path::new(".")).unwrap();
        assert_eq!((a.illuminant.name, a.materials[0].settings.illuminant), ("A", a.illuminant));
        // The Taylor order, by its name or by its first one.
        for key in ["order", "terms"] {
            let s = Scene::parse(
                &GOOD.replace("tile = [2, 3]", &format!("tile = [2, 3]\n{key} = 7")),
                "s.toml",
                Path::new("."),
            );
            assert_eq!(s.unwrap().materials[0].settings.order, Some(7), "{key}");
        }
        // `auto` where the help shows it (the shading chooses, as where the key is left out); another word is not.
        let auto = "tile = [2, 3]\norder = \"auto\"\ntable_segments = \"auto\"\nwindow_radius = \"auto\"";
        let s = Scene::parse(&GOOD.replace("tile = [2, 3]", auto), "s.toml", Path::new(".")).unwrap();
        let m = &s.materials[0].settings;
        assert_eq!((m.order, m.table_segments, m.window_radius), (None, None, None));
        let many =
            Scene::parse(&GOOD.replace("tile = [2, 3]", "tile = [2, 3]\norder = \"many\""), "s.toml", Path::new("."));
        assert!(many.unwrap_err().to_string().contains("expected a number or \"auto\""));
    }

    #[test]
    fn the_snakes_scales_are_as_domed_as_the_scene_says() {
        let snake = |extra: &str| {
            let text = GOOD.replace("shape = \"sphere\"", &format!("shape = \"snake\"\n{extra}"));
            Scene::parse(&text, "s.toml", Path::new("."))
        };
        // The normals' spread over the mesh: a flatter dome leans them less away from the body's.
        let spread = |scene: Scene| {
            let mesh = &scene.objects[0].mesh;
            let ys: Vec<f32> = mesh.vertices.iter().map(|v| v.normal[1]).collect();
            ys.iter().map(|y| y * y).sum::<f32>() / ys.len() as f32
        };
        let (default, flat) = (spread(snake("").unwrap()), spread(snake("scale_dome = 0.0").unwrap()));
        assert!((default - flat).abs() > 1e-3, "{default} {flat}");
        assert_eq!(spread(snake("scale_dome = 0.35").unwrap()), default);
        for bad in ["scale_dome = -0.1", "scale_dome = 1.5", "scale_dome = nan"] {
            assert!(snake(bad).unwrap_err().to_string().contains("scale_dome must be between 0"), "{bad}");
        }
        let sphere = GOOD.replace("shape = \"sphere\"", "shape = \"sphere\"\nscale_dome = 0.1");
        assert!(error_of(&sphere).contains("are for shape = \"snake\""));
    }

    #[test]
    fn mistakes_name_their_line() {
        assert!(error_of(&GOOD.replace("scale = 0.5", "scael = 0.5")).starts_with("s.toml:14: unknown field `scael`"));
        assert!(error_of(&GOOD.replace("fov_y_deg = 30.0", "fov_y_deg = \"wide\"")).starts_with("s.toml:5:"));
        assert!(error_of(&GOOD.replace("material = \"blaze\"", "material = \"gold\""))
            .starts_with("s.toml:13: no [material.gold]"));
        assert!(error_of(&GOOD.replace("shape = \"sphere\"", "mesh = \"nope.obj\"")).starts_with("s.toml:12:"));
        assert!(error_of(&GOOD.replace("generate = \"blazed\"", "heightfield = \"nope.gsf\""))
            .starts_with("s.toml:17: heightfield"));
        assert!(error_of(&GOOD.replace("shape = \"sphere\"", "shape = \"torus\""))
            .starts_with("s.toml:12: unknown variant `torus`"));
        assert!(error_of(&GOOD.replace("illuminant = \"D65\"", "illuminant = \"D300\"")).starts_with("s.toml:9: "));
        // "sun" alone: the sky model's sun at the light's elevation.
        let sun = Scene::parse(&GOOD.replace("illuminant = \"D65\"", "illuminant = \"sun\""), "s.toml", Path::new("."));
        let elevation = (f64::from(sun.as_ref().unwrap().light_dir.y).asin().to_degrees() * 100.0).round() / 100.0;
        assert_eq!(sun.unwrap().illuminant, Illuminant::sun(elevation, 3.0).unwrap());
        assert!(error_of(&GOOD.replace("illuminant = \"D65\"", "illuminant = \"G\"")).contains("D65, D50"));
        assert!(error_of(&GOOD.replace("illuminant = \"D65\"", "illuminant = \"nope.csv\"")).contains("nope.csv"));
        // The light's spectrum is the light's: a material does not take it.
        assert!(error_of(&GOOD.replace("size_um = 6.5", "size_um = 6.5\nilluminant = \"A\"")).contains("illuminant"));
        assert!(error_of(&GOOD.replace("[camera]", "[camera\n")).starts_with("s.toml:2:"));
        assert!(error_of(&GOOD.replace("scale = 0.5", "scale = 0.5\ntranslate = [nan, 0.0, 0.0]"))
            .starts_with("s.toml:11: translate"));
        assert!(error_of(&GOOD.replace("target = [0.0, 0.0, 0.0]", "target = [0.0, 0.0, 0.0]\nup = [0.0, 0.5, 3.0]"))
            .contains("parallel"));
        assert!(error_of(&GOOD.replace("size_um = 6.5", "size_um = 6.5\ncoherence_um = inf")).contains("coherence_um"));
        assert!(error_of(&format!("{GOOD}\n[render]\nexposure_ev = nan\n")).contains("exposure_ev"));
        // The material's settings (declared in settings.rs) are checked as the command line's are, at the line.
        let setting = |line: &str| error_of(&GOOD.replace("size_um = 6.5", &format!("size_um = 6.5\n{line}")));
        assert!(setting("window_radius = 99").starts_with("s.toml:16: [material.blaze] window_radius: "));
        assert!(setting("lambda_step_nm = 0").contains("(0, 400]"));
        assert!(setting("colour = 1").contains("unknown field `colour`"), "{}", setting("colour = 1"));
        let fast = error_of(&GOOD.replace("approach = \"nmm\"", "approach = \"fast\""));
        assert!(fast.contains("unknown variant `fast`"), "{fast}");
        assert!(setting("order = \"many\"").starts_with("s.toml:"), "{}", setting("order = \"many\""));
        for e in [error_of("x = 1"), error_of(&GOOD.replace("scale = 0.5", "scale = -1.0"))] {
            assert_eq!(e.lines().count(), 1, "{e}");
        }
    }

    #[test]
    fn the_default_scene_loads() {
        let s = Scene::default_scene().unwrap();
        assert!(!s.objects.is_empty() && !s.materials.is_empty());
        // Outdoors, in physical units, with the sky drawn behind; its sun-only twin in the thesis's units.
        assert!(matches!(s.environment, Some(Environment::Sky(_))) && s.illuminant.physical && s.environment_behind);
        let sun = Scene::load(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/elaphe-snake-sun.toml")));
        let sun = sun.unwrap();
        assert!(sun.environment.is_none() && !sun.illuminant.physical && sun.ambient > 0.0);
        assert_eq!((sun.camera, sun.light_dir), (s.camera, s.light_dir));
    }
}
