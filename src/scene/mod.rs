//! Scene files (TOML): a camera, the sun and what lights the scene around it, objects (OBJ meshes or built-in
//! shapes) and materials (a height field, measured or generated, with the settings that trade speed for accuracy,
//! and pigment and normal maps).
//! Paths are relative to the scene file; every mistake is refused with the file, the line and what was expected.
//! docs/usage.md ("The scene file") documents the format, which `file.rs` declares; `checks.rs` makes the camera,
//! light and image tables values, `objects.rs` the materials and objects, `light.rs` holds what lights a scene.

pub mod camera;
mod checks;
mod file;
mod lamps;
mod light;
pub mod mesh;
mod objects;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::error::{Error, Result};
use crate::material::Settings;
use crate::physics::illuminant::Illuminant;
use crate::scene::camera::Camera;
pub use crate::scene::checks::{RenderSettings, DEFAULT_SAMPLES};
pub use crate::scene::file::DEFAULT_SCENE;
use crate::scene::file::{Locator, SceneFile, BUILT_IN_BASE};
pub use crate::scene::light::{Environment, MapLight, MapSun, SkyLight, SKY_GROUND_ALBEDO};
pub use crate::scene::objects::{SceneMaterial, SceneObject, DEFAULT_APPROACH};

/// The name the default scene reports in messages.
pub const DEFAULT_SCENE_NAME: &str = "assets/scenes/elaphe-snake.toml (built in)";

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
    /// Whether the sun and the lamps cast shadows (`[light] shadows`; by default where the scene has a ground).
    pub shadows: bool,
    /// Whether the environment is drawn behind the objects: where there is one and `[render] background` sets no
    /// colour.
    pub environment_behind: bool,
    pub objects: Vec<SceneObject>,
    pub materials: Vec<SceneMaterial>,
    pub render: RenderSettings,
    /// The lamps (`[[lamp]]`), in world units of metres: with any, the frame is in physical units.
    pub lamps: Vec<crate::light::lamp::Lamp>,
    /// Whether a sun lights the scene: not where a map without one or the lamps light it alone.
    pub sun: bool,
    /// The files the scene was read from, each with what it is: the scene file itself (where it was loaded from a
    /// file), its height fields, meshes, environment map and measured illuminant — what no output of a run may be.
    pub files: Vec<(String, PathBuf)>,
}

impl Scene {
    /// Loads a scene file.
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = crate::io::input::read(path, crate::io::input::MAX_SCENE_BYTES, "scene")?;
        let text = String::from_utf8(bytes).map_err(|_| Error::input(path, "is not UTF-8 text (a TOML scene)"))?;
        let base = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        let mut scene = Self::parse(&text, &path.display().to_string(), base)?;
        scene.files.insert(0, ("the scene".to_string(), path.to_path_buf()));
        Ok(scene)
    }

    /// Material `m`'s settings under `overrides` (the command line's, a profile configuration's): under the sky a
    /// light the overrides name is in physical units too.
    pub fn material_settings(&self, m: &SceneMaterial, overrides: &crate::material::SettingsPatch) -> Settings {
        let mut s = overrides.apply(m.settings);
        if self.environment.is_some() || !self.lamps.is_empty() {
            s.illuminant = s.illuminant.physical();
        }
        s
    }

    /// How much of the directional sun lights the scene: 1, or 0 where a map without a sun or the lamps light it
    /// alone (`SurfaceUniforms::light_dir`'s w).
    pub fn sun_strength(&self) -> f32 {
        if self.sun {
            1.0
        } else {
            0.0
        }
    }

    /// The frame's unit of luminance for the sun towards `light_dir`, cd/m²: the sun's own where it is in physical
    /// units (under an environment, or beside lamps: the sky model's sun), 1 where the lamps light the scene alone
    /// or the sun is below the horizon (the frame in cd/m²), the map's own units under a map alone. What a lamp's
    /// candela are divided by (`light::lamp::LampUniforms`).
    pub fn unit_luminance(&self, light_dir: Vec3) -> f64 {
        if !self.sun {
            return 1.0;
        }
        let sun = match &self.environment {
            Some(env) => env.sun_luminance(light_dir),
            None => crate::physics::sky::Sky::new(crate::physics::illuminant::SUN_TURBIDITY, light_dir.as_dvec3())
                .ok()
                .map(|s| s.sun_xyz().y),
        };
        sun.filter(|l| *l > 0.0 && l.is_finite()).unwrap_or(1.0)
    }

    /// What a frame of the scene under the sun towards `light_dir` holds (its EXR says so): in physical units
    /// (under an environment or lamps) the luminance of RGB (1, 1, 1) in cd/m² — the sun's luminance, or 1 where
    /// lamps light the scene alone —; a map's own units under a map alone; else the thesis's relative units.
    pub fn frame_units(&self, light_dir: Vec3) -> crate::io::output::FrameUnits {
        let map_alone = !self.sun && self.lamps.is_empty();
        let (white_luminance, comment) = if map_alone {
            (None, "linear sRGB in the environment map's own units (no sun)".to_string())
        } else if self.environment.is_some() || !self.lamps.is_empty() {
            let unit = self.unit_luminance(light_dir);
            let what = match self.sun {
                true => "the sun's luminance",
                false => "1 cd/m² (lamps alone)",
            };
            (Some(unit), format!("linear sRGB, physical: (1, 1, 1) is {what}, {unit:.6e} cd/m²"))
        } else {
            (None, "linear sRGB, relative: the sun's glint in a flat mirror of reflectance 1 is 1".to_string())
        };
        crate::io::output::FrameUnits { white_luminance, comment }
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
        let camera = checks::camera(&loc, &file.camera)?;
        let lamps = lamps::lamps(&loc, &file.lamps)?;
        let checks::Light { environment, light_dir, illuminant, sun } =
            checks::light(&loc, base, &file.light, !lamps.is_empty())?;
        let mut materials = Vec::new();
        let mut index = BTreeMap::new();
        for (mat_name, def) in &file.material {
            index.insert(mat_name.clone(), materials.len());
            materials.push(objects::material(&loc, base, mat_name, def, illuminant)?);
        }
        if file.objects.is_empty() {
            return Err(loc.whole("the scene has no [[object]]"));
        }
        let mut objects = Vec::new();
        for def in &file.objects {
            objects.push(objects::object(&loc, base, def, &index, &materials)?);
        }
        let render = checks::render_settings(&loc, &file.render)?;
        let ambient = file.light.ambient.as_ref().map_or(Ok(0.0), |a| {
            checks::amount(*a.get_ref(), checks::MAX_LEVEL, "[light] ambient").map_err(|e| loc.at(a.span(), e))
        })?;
        let grounded = objects.iter().any(|o| !o.casts_shadow);
        // Without a sun or a lamp there is nothing to cast a shadow.
        let shadows = file.light.shadows.unwrap_or(grounded) && (sun || !lamps.is_empty());
        let environment_behind = environment.is_some() && file.render.background.is_none();
        if let (Some(env), Some(_)) = (&environment, file.render.background) {
            checks::background_units_warning(env, light_dir, render.background);
        }
        let mut files = read_files(&file, base, environment.as_ref(), illuminant);
        // The maps an object's OBJ brought from its MTL (the materials' are listed already).
        for path in objects.iter().flat_map(|o| o.mesh.maps.files()) {
            if !files.iter().any(|(_, f)| f == path) {
                files.push(("an object's map (from its MTL)".to_string(), path.to_path_buf()));
            }
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
            lamps,
            sun,
            files,
        })
    }
}

/// The files a scene names that it read: its height fields and meshes, its environment map, its illuminant's SPD
/// (a built-in file, in no folder, is none of them).
fn read_files(
    file: &SceneFile,
    base: &Path,
    environment: Option<&Environment>,
    illuminant: Illuminant,
) -> Vec<(String, PathBuf)> {
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    for (name, def) in &file.material {
        if let Some(path) = &def.get_ref().heightfield {
            files.push((format!("[material.{name}]'s height field"), base.join(path.get_ref())));
        }
        for (what, map) in [("pigment map", &def.get_ref().pigment_map), ("normal map", &def.get_ref().normal_map)] {
            if let Some(path) = map {
                files.push((format!("[material.{name}]'s {what}"), base.join(path.get_ref())));
            }
        }
    }
    for def in &file.objects {
        if let Some(path) = &def.get_ref().mesh {
            files.push(("an object's mesh".to_string(), base.join(path.get_ref())));
        }
    }
    if let Some(Environment::Map(map)) = environment {
        files.push(("the environment map".to_string(), map.path.clone()));
    }
    if illuminant.name.to_ascii_lowercase().ends_with(".csv") {
        files.push(("the illuminant's SPD".to_string(), PathBuf::from(illuminant.name)));
    }
    files.retain(|(_, path)| path.is_file());
    files
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Approach;

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
        refused("environment = \"around.exr\"\nintensity = -1.0", "must be a positive, finite factor");
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

    #[test]
    fn the_usage_pages_template_parses_and_frames_its_sphere() {
        // docs/usage.md's template, with a generated patch for the user's scan: it loads, and its camera shows the
        // unit sphere at the middle of the picture, neither a speck nor filling it (it once did).
        let page = include_str!("../../docs/usage.md");
        let section = page.split("### The scene file").nth(1).expect("usage.md has its template");
        let block = section.split("```toml\n").nth(1).and_then(|b| b.split("```").next()).unwrap();
        let text = block.replace("heightfield = \"my-scan.gsf\"", "generate = \"elaphe\"\nsize_um = 6.5");
        let scene = Scene::parse(&text, "usage.md", Path::new(".")).unwrap();
        let (camera, object) = (&scene.camera, &scene.objects[0]);
        assert_eq!(object.mesh.vertices.len(), crate::scene::mesh::shapes::Shape::Sphere.build().vertices.len());
        let distance = (camera.position - object.model.transform_point3(Vec3::ZERO)).length();
        let share = 2.0 * (1.0 / distance).asin().to_degrees() / camera.fov_y_deg;
        assert!((0.3..0.8).contains(&share), "the sphere spans {share:.2} of the picture's height");
    }
}
