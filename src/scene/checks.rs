//! The `[camera]`, `[light]` and `[render]` tables checked and made values: a camera with a usable view, the sun's
//! direction, the environment (the sky, a map with its sun found, or none) and the light's spectrum, the image
//! settings. Every mistake names its line and what was expected.

use std::path::Path;

use glam::{DVec3, Vec3};
use toml::Spanned;

use crate::error::Result;
use crate::physics::illuminant::Illuminant;
use crate::scene::camera::Camera;
use crate::scene::file::{CameraDef, LightDef, Locator, RenderDef};
use crate::scene::light::{Environment, MapLight, MapSun, SkyLight};

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

/// The largest coordinate, scale or angle a scene may give (world units are arbitrary, but f32 transforms of
/// larger values lose the mesh or overflow).
pub(crate) const MAX_COORDINATE: f64 = 1e6;

/// The largest value of a linear colour or a light's level a scene may give (a pigment's or the background's
/// channel, `ambient`): far beyond any use (a uniform sky is 10⁻⁵ of the sun), far enough below f32's 3.4·10³⁸
/// that a frame's products stay finite at any exposure the frame is metered to.
pub(crate) const MAX_LEVEL: f64 = 1e6;

/// Three finite numbers of at most [`MAX_COORDINATE`] in magnitude.
pub(super) fn check_coords(loc: &Locator<'_>, span: std::ops::Range<usize>, what: &str, v: &[f64; 3]) -> Result<Vec3> {
    if v.iter().all(|x| x.is_finite() && x.abs() <= MAX_COORDINATE) {
        return Ok(DVec3::from(*v).as_vec3());
    }
    Err(loc.at(span, format!("{what} = {}: expected three finite numbers within ±{MAX_COORDINATE:e}", triple(v))))
}

/// Three numbers as the user wrote them (not as f32 would hold them: 1e308 is not `inf`).
pub(super) fn triple(v: &[f64; 3]) -> String {
    format!("[{}]", v.map(crate::error::number).join(", "))
}

/// A non-negative, finite number of at most `max` (a linear colour's channel, a light's radiance), or the line that
/// says what is expected of `what`.
pub(super) fn amount(value: f64, max: f64, what: &str) -> std::result::Result<f32, String> {
    match value.is_finite() && (0.0..=max).contains(&value) {
        true => Ok(value as f32),
        false => {
            Err(format!("{what} = {}: expected a non-negative number of at most {max:e}", crate::error::number(value)))
        }
    }
}

/// The `[camera]` table, checked: finite coordinates, an up vector off the line of sight, a field of view inside
/// (0°, 180°) and a usable depth range.
pub(super) fn camera(loc: &Locator<'_>, c: &CameraDef) -> Result<Camera> {
    let cam_span = c.position.span();
    let position = check_coords(loc, cam_span.clone(), "[camera] position", c.position.get_ref())?;
    let target = check_coords(loc, cam_span.clone(), "[camera] target", &c.target)?;
    let up = check_coords(loc, cam_span.clone(), "[camera] up", &c.up)?;
    let forward = target - position;
    if forward.length() > 0.0 && forward.normalize().cross(up).length() < 1e-6 {
        return Err(loc.at(cam_span.clone(), "[camera] up is parallel to the line of sight (or zero)"));
    }
    if position == target {
        return Err(loc.at(c.position.span(), "the camera position equals its target"));
    }
    let fov = *c.fov_y_deg.get_ref();
    if !(fov > 0.0 && fov < 180.0) {
        let fov = crate::error::number(fov);
        return Err(loc
            .at(c.fov_y_deg.span(), format!("fov_y_deg = {fov}: expected a field of view between 0 and 180 degrees")));
    }
    if !(c.near > 0.0 && c.far > c.near && c.far <= MAX_COORDINATE && c.far / c.near <= 1e7) {
        return Err(loc.whole("the camera needs 0 < near < far ≤ 1e6, with far/near at most 1e7"));
    }
    Ok(Camera { position, target, up, fov_y_deg: fov as f32, near: c.near as f32, far: c.far as f32 })
}

/// The `[render]` table with its defaults, checked.
pub(super) fn render_settings(loc: &Locator<'_>, r: &RenderDef) -> Result<RenderSettings> {
    let render = RenderSettings {
        width: r.width.unwrap_or(512),
        height: r.height.unwrap_or(512),
        exposure_ev: r.exposure_ev,
        background: [0.0; 3],
        samples: r.samples.unwrap_or(DEFAULT_SAMPLES),
    };
    if !(render.samples.is_power_of_two() && render.samples <= 64) {
        return Err(loc.whole("[render] samples is a power of two: 1 (no anti-aliasing), 2, 4, 8, …"));
    }
    let max = crate::display::MAX_EXPOSURE_EV;
    if render.exposure_ev.is_some_and(|ev| !ev.is_finite() || ev.abs() > max) {
        return Err(loc.whole(format!("[render] exposure_ev must be a number of stops within ±{max}")));
    }
    let background = r.background.unwrap_or([0.0; 3]);
    if background.iter().any(|&c| amount(c, MAX_LEVEL, "").is_err()) {
        return Err(loc.whole(format!(
            "[render] background = {}: a linear RGB colour, three non-negative numbers of at most {MAX_LEVEL:e}",
            triple(&background)
        )));
    }
    let render = RenderSettings { background: background.map(|c| c as f32), ..render };
    if render.width == 0 || render.height == 0 || render.width > 16384 || render.height > 16384 {
        return Err(loc.whole("[render] width and height must lie in 1..=16384"));
    }
    Ok(render)
}

/// The `[light]` table made values: the environment, the direction towards the sun and the light's spectrum.
pub(super) struct Light {
    pub environment: Option<Environment>,
    /// World-space unit vector towards the light.
    pub light_dir: Vec3,
    pub illuminant: Illuminant,
    /// Whether a sun lights the scene (not where a map or the lamps light it alone).
    pub sun: bool,
}

/// The `[light]` table, checked: a finite, non-zero direction, the environment ([`environment`]) and the
/// spectrum ([`illuminant`]); `lamps`: whether the scene has lamps (which may light it alone, and put it in physical
/// units).
pub(super) fn light(loc: &Locator<'_>, base: &Path, def: &LightDef, lamps: bool) -> Result<Light> {
    let direction = match &def.direction {
        Some(d) => Some(
            DVec3::from(*d.get_ref())
                .try_normalize()
                .filter(|v| v.is_finite())
                .ok_or_else(|| loc.at(d.span(), "the light direction must be a finite, non-zero vector"))
                // Normalised in f32 where f32 holds it (the light's bits, hence the shadow map's texel grid and
                // the golden images, as they were), in f64 where it would overflow.
                .map(|unit| DVec3::from(*d.get_ref()).as_vec3().try_normalize().unwrap_or(unit.as_vec3()))?,
        ),
        None => None,
    };
    let lamps_alone = lamps && direction.is_none() && environment_kind(loc, def)?.is_none();
    let (environment, light_dir) = match lamps_alone {
        true => (None, Vec3::Y),
        false => environment(loc, base, def, direction)?,
    };
    let alone = matches!(&environment, Some(Environment::Map(m)) if m.sun == MapSun::Alone);
    let sun = !(lamps_alone || alone);
    let illuminant = illuminant(loc, base, def, (environment.as_ref(), lamps, sun), light_dir)?;
    Ok(Light { environment, light_dir, illuminant, sun })
}

/// `[light] illuminant`, or the light's own where it names none: a map's sun's colour (upsampled from its RGB), the
/// sky model's sun at the light's elevation under an environment or beside lamps, else D65. Under an environment
/// or lamps the frame is in physical units: the diffraction in its true ratio to the sky-lit pigment, the lamps in
/// theirs to the sun.
fn illuminant(
    loc: &Locator<'_>,
    base: &Path,
    def: &LightDef,
    (environment, lamps, sun_lit): (Option<&Environment>, bool, bool),
    light_dir: Vec3,
) -> Result<Illuminant> {
    let direction_span = def.direction.as_ref().map_or(0..0, |d| d.span());
    let map_sun = match environment {
        Some(Environment::Map(m)) => Some(m.sun),
        _ => None,
    };
    let sun = |span| {
        // The sun at the light's own elevation, to 0.01° (the direction is f32: the name reads cleanly and the
        // spectrum does not notice).
        let elevation = (f64::from(light_dir.y).asin().to_degrees() * 100.0).round() / 100.0;
        let turbidity = environment.map_or(crate::physics::illuminant::SUN_TURBIDITY, Environment::turbidity);
        Illuminant::sun(elevation, turbidity).map_err(|e| loc.at(span, e))
    };
    let named_sun = |i: &Spanned<String>| i.get_ref().trim().eq_ignore_ascii_case("sun");
    let illuminant = match (&def.illuminant, map_sun) {
        // A map's own sun has its own colour: upsampled from its RGB as the map's light is.
        (None | Some(_), Some(MapSun::Found(found))) if def.illuminant.as_ref().is_none_or(named_sun) => {
            Illuminant::of_linear_srgb(found.irradiance, "the map's sun").map_err(|e| loc.at(direction_span, e))?
        }
        (Some(ill), _) if named_sun(ill) => sun(ill.span())?,
        (Some(ill), _) => Illuminant::parse(ill.get_ref(), base).map_err(|e| loc.at(ill.span(), e))?,
        // Under an environment the sun is the sky model's (none lights a map alone: its colour is unused).
        (None, Some(MapSun::Alone)) => Illuminant::d65(),
        (None, _) if environment.is_some() || (lamps && sun_lit) => sun(direction_span)?,
        (None, _) => Illuminant::d65(),
    };
    Ok(if environment.is_some() || lamps { illuminant.physical() } else { illuminant })
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
                 environment = \"FILE.exr\", whose map then gives the sun, or lights the scene alone, and under \
                 environment = \"none\" with [[lamp]]s, which then light it alone)",
            )
        })
    };
    let kind = environment_kind(loc, light)?;
    let model = match &light.sky_model {
        Some(m) => crate::physics::sky::SkyModel::named(m.get_ref()).map_err(|e| loc.at(m.span(), e))?,
        None => crate::physics::sky::SkyModel::default(),
    };
    let Some((k, span)) = kind else { return Ok((None, required()?)) };
    if let Some(a) = light.ambient.as_ref().filter(|a| *a.get_ref() != 0.0) {
        return Err(loc.at(a.span(), format!("ambient and environment = {k:?} would both light the pigment: keep one")));
    }
    if is_map_file(&k) {
        return map_light(loc, base, light, (&k, span), direction)
            .map(|(m, light_dir)| (Some(Environment::Map(std::sync::Arc::new(m))), light_dir));
    }
    let light_dir = required()?;
    let turbidity = light.turbidity.as_ref().map_or(crate::physics::illuminant::SUN_TURBIDITY, |t| *t.get_ref());
    let sky = SkyLight { turbidity, model };
    sky.sky(light_dir).map_err(|e| {
        let at = light.turbidity.as_ref().map_or(span, |t| t.span());
        if light.environment.is_none() {
            let hint = "the scene names no [light] environment, so it is under the clear sky; environment = \"none\" \
                        lights it by the sun alone";
            loc.at(at, format!("{e} ({hint})"))
        } else {
            loc.at(at, format!("environment = \"sky\": {e}"))
        }
    })?;
    Ok((Some(Environment::Sky(sky)), light_dir))
}

/// Whether `[light] environment = k` names a map file (.exr or .hdr).
fn is_map_file(k: &str) -> bool {
    let lower = k.to_ascii_lowercase();
    lower.ends_with(".exr") || lower.ends_with(".hdr")
}

/// `[light] environment` as written, with its span: a map file's name byte for byte, or "sky"; None for "none",
/// or where the scene names none and lights its pigment by the thesis's uniform grey sky (`ambient`, relative
/// units). A scene that names none otherwise is outdoors, under the clear sky. Refused: a name that is neither,
/// a file name with spaces around it, and keys that belong to another kind.
fn environment_kind(loc: &Locator<'_>, light: &LightDef) -> Result<Option<(String, std::ops::Range<usize>)>> {
    let kind = match &light.environment {
        // As written: a file's name is used as given, byte for byte (the keywords are matched trimmed).
        Some(e) => Some((e.get_ref().to_string(), e.span())),
        None => {
            light.ambient.is_none().then(|| ("sky".to_string(), light.direction.as_ref().map_or(0..0, |d| d.span())))
        }
    };
    let named = |name: &str| kind.as_ref().is_some_and(|(k, _)| k.trim().eq_ignore_ascii_case(name));
    if let Some((k, span)) = kind.as_ref().filter(|(k, _)| k.trim() != k && is_map_file(k.trim())) {
        return Err(loc.at(
            span.clone(),
            format!("environment {k:?}: the file name begins or ends with spaces; a name is used as written"),
        ));
    }
    if let Some((k, span)) = kind.as_ref().filter(|(k, _)| !(is_map_file(k) || named("sky") || named("none"))) {
        return Err(loc.at(
            span.clone(),
            format!("environment {k:?}: expected \"sky\" (the clear-sky model), \"FILE.exr\" or \"FILE.hdr\" (an HDR map) or \"none\""),
        ));
    }
    if !kind.as_ref().is_some_and(|(k, _)| is_map_file(k)) {
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
    let none = named("none");
    Ok(kind.filter(|_| !none))
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
    let rotation_deg = light.rotation_deg.as_ref().map_or(0.0, |v| *v.get_ref());
    let intensity = light.intensity.as_ref().map_or(1.0, |v| *v.get_ref());
    let direction_span = light.direction.as_ref().map_or(span.clone(), |d| d.span());
    let path = base.join(file);
    let loaded = crate::light::environment::EnvironmentMap::load(&path).map_err(|e| loc.at(span.clone(), e))?;
    if let Err(e) = loaded.check_scale(intensity, rotation_deg) {
        let key = if e.contains("intensity") { &light.intensity } else { &light.rotation_deg };
        return Err(loc.at(key.as_ref().map_or(span, |k| k.span()), e));
    }
    let search = crate::light::sun::find(&loaded);
    let (map, sun, light_dir, sun_texels) = match (search.sun, search.rest) {
        (Some(found), Some(rest)) => {
            let world = found_sun(loc, (file, span), &found, rotation_deg)?;
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

/// The world direction of the sun `found` in the map `file` (at `span`) once the map is turned by `rotation_deg`;
/// refused where that lies below the horizon.
fn found_sun(
    loc: &Locator<'_>,
    (file, span): (&str, std::ops::Range<usize>),
    found: &crate::light::sun::FoundSun,
    rotation_deg: f64,
) -> Result<Vec3> {
    let turn = glam::DQuat::from_rotation_y(rotation_deg.to_radians());
    let world = (turn * found.direction).as_vec3();
    let (elevation, azimuth) = (f64::from(world.y).asin().to_degrees(), f64::from(world.x.atan2(world.z)).to_degrees());
    if world.y <= 0.0 {
        return Err(loc.at(
            span,
            format!(
                "environment {file:?}: its sun ({}) lies {:.2}° below the horizon after rotation_deg: turn or flip the \
                 map so that its sky is up",
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
    Ok(world)
}

/// Warns where `[render] background` under an environment lies orders of magnitude from the environment's own
/// light in the frame's units (the sun's radiance is 1 there): a background of 0.5 under the sky is a hundred
/// thousand skies, which the objects then vanish against.
pub(super) fn background_units_warning(env: &Environment, light_dir: Vec3, bg: [f32; 3]) {
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
