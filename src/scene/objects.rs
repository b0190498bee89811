//! A scene's materials and objects: each `[material.NAME]` table made a patch (loaded, generated or matte; tiled
//! or extended) with its settings and maps, and each `[[object]]` a mesh (a file or a built-in shape) placed in
//! the world, carrying its material's maps (or its MTL's).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{EulerRot, Mat4, Quat, Vec3};
use toml::Spanned;

use crate::error::Result;
use crate::material::{Approach, Settings};
use crate::physics::formats::png::PngScale;
use crate::physics::generate::{generate, PatchKind, PatchSpec};
use crate::physics::heightfield::HeightField;
use crate::physics::illuminant::Illuminant;
use crate::scene::checks::{amount, check_coords, triple, MAX_COORDINATE, MAX_LEVEL};
use crate::scene::file::{built_in, Locator, MaterialDef, ObjectDef, TileDef};
use crate::scene::mesh::maps::{MapKind, SurfaceMaps, Texture};
use crate::scene::mesh::shapes::Shape;
use crate::scene::mesh::{obj, Mesh};

/// The approach of a material that names none: the baked table (FLSS stays the reference, a material or the
/// command line can ask for it).
pub const DEFAULT_APPROACH: Approach = Approach::Baked;

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
    /// Its pigment and normal maps (an object's mesh may bring its own from an MTL: the material's come first).
    pub maps: SurfaceMaps,
    /// Metres one repeat of the maps covers on the ground and planes (None: one repeat over the whole shape).
    pub map_size_m: Option<f64>,
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

/// The flat patch behind a matte material: edge and pixel (µm).
const MATTE_PATCH_UM: f64 = 4.0;
const MATTE_PIXEL_UM: f64 = 0.25;

pub(super) fn material(
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
    let hf = patch(loc, base, d, &at)?;
    let hf = match (d.tile, d.extend_um) {
        (Some(_), Some(_)) => {
            return Err(at("give tile (repeat the patch) or extend_um (grow it without a period), not both".into()))
        }
        (None, Some(um)) => crate::physics::extend::extend(&hf, um).map_err(|e| at(e.to_string()))?,
        (None, None) => hf,
        (Some(TileDef::Both(n)), None) => hf.tiled(n as usize, n as usize).map_err(|e| at(e.to_string()))?,
        (Some(TileDef::Each([x, y])), None) => hf.tiled(x as usize, y as usize).map_err(|e| at(e.to_string()))?,
    };
    if !(d.orientation_deg.is_finite() && d.orientation_deg.abs() <= MAX_COORDINATE) {
        let deg = crate::error::number(d.orientation_deg);
        return Err(at(format!("orientation_deg = {deg}: expected a finite angle within ±{MAX_COORDINATE:e}")));
    }
    d.settings.check().map_err(at)?;
    let mut patch = d.settings;
    // A scene that states its table tolerance means it: a table that cannot reach it is refused.
    patch.strict_table |= patch.table_tolerance.is_some();
    let settings = patch.apply(Settings { approach: DEFAULT_APPROACH, illuminant, ..Settings::default() });
    if d.pigment.iter().any(|&c| amount(c, MAX_LEVEL, "").is_err()) {
        return Err(at(format!(
            "pigment = {}: a linear RGB albedo, three non-negative numbers of at most {MAX_LEVEL:e}",
            triple(&d.pigment)
        )));
    }
    let map = |key: &Option<Spanned<String>>, kind| {
        key.as_ref()
            .map(|path| {
                let file = base.join(path.get_ref());
                Texture::load(&file, kind).map(Arc::new).map_err(|e| loc.at(path.span(), e))
            })
            .transpose()
    };
    let maps =
        SurfaceMaps { pigment: map(&d.pigment_map, MapKind::Pigment)?, normal: map(&d.normal_map, MapKind::Normal)? };
    let map_size_m = match &d.map_size_m {
        Some(m) if !(m.get_ref().is_finite() && *m.get_ref() > 0.0 && *m.get_ref() <= MAX_COORDINATE) => {
            let size = crate::error::number(*m.get_ref());
            return Err(loc.at(
                m.span(),
                format!("map_size_m = {size}: expected metres, positive and at most {MAX_COORDINATE:e}"),
            ));
        }
        Some(_) if maps.is_empty() => return Err(at("has map_size_m but no pigment_map or normal_map".into())),
        m => m.as_ref().map(|m| *m.get_ref()),
    };
    Ok(SceneMaterial {
        name: name.to_string(),
        heightfield: hf,
        settings,
        orientation_deg: d.orientation_deg as f32,
        pigment: d.pigment.map(|c| c as f32),
        matte,
        maps,
        map_size_m,
    })
}

/// A material's patch as its table gives it: a height field file (a PNG with its scale, a GSF; the built-in scene's
/// from the binary), a generated one, or, for a matte material, the small flat patch nothing draws.
fn patch(
    loc: &Locator<'_>,
    base: &Path,
    d: &MaterialDef,
    at: &dyn Fn(String) -> crate::error::Error,
) -> Result<HeightField> {
    Ok(match (&d.heightfield, d.generate) {
        (Some(path), None) => {
            let file = base.join(path.get_ref());
            let png = match (d.pixel_size_um, d.height_um) {
                (Some(pixel_size_um), Some(height_um)) => Some(PngScale { pixel_size_um, height_um }),
                (None, None) => None,
                _ => return Err(at("pixel_size_um and height_um go together".into())),
            };
            match (built_in(&file), png) {
                (Some(bytes), Some(scale)) => {
                    crate::physics::formats::png::from_bytes(&file, bytes, scale).map_err(|e| loc.at(path.span(), e))?
                }
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
        (None, None) => {
            generate(&PatchSpec::new(PatchKind::Flat, MATTE_PATCH_UM, MATTE_PIXEL_UM)).map_err(|e| at(e.to_string()))?
        }
    })
}

pub(super) fn object(
    loc: &Locator<'_>,
    base: &Path,
    def: &Spanned<ObjectDef>,
    materials: &BTreeMap<String, usize>,
    loaded: &[SceneMaterial],
) -> Result<SceneObject> {
    let span = def.span();
    let d = def.get_ref();
    let mut mesh = match (&d.mesh, d.shape) {
        (Some(path), None) => {
            let file: PathBuf = base.join(path.get_ref());
            obj::load(&file).map_err(|e| loc.at(path.span(), e))?
        }
        (None, Some(Shape::Snake)) => {
            use crate::scene::mesh::snake::{snake, SnakeSpec, MAX_SCALE_DOME};
            let defaults = SnakeSpec::default();
            let scale_dome = match &d.scale_dome {
                Some(dome) if !(0.0..=f64::from(MAX_SCALE_DOME)).contains(dome.get_ref()) => {
                    return Err(loc.at(dome.span(), format!("scale_dome must be between 0 (flat) and {MAX_SCALE_DOME}")))
                }
                Some(dome) => *dome.get_ref() as f32,
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
    let scale = d.scale.as_ref().map_or(1.0, |s| *s.get_ref());
    place_maps(&mut mesh, &loaded[material], d.shape, scale).map_err(|e| loc.at(span.clone(), e))?;
    if !(scale.is_finite() && scale > 0.0 && scale <= MAX_COORDINATE) {
        return Err(loc.at(
            d.scale.as_ref().map(|s| s.span()).unwrap_or(span),
            format!("scale must be positive and at most {MAX_COORDINATE:e}"),
        ));
    }
    let translate = check_coords(loc, span.clone(), "translate", &d.translate)?;
    let rotate = check_coords(loc, span.clone(), "rotate_deg", &d.rotate_deg)?;
    let [rx, ry, rz] = rotate.to_array().map(f32::to_radians);
    let model = Mat4::from_scale_rotation_translation(
        Vec3::splat(scale as f32),
        Quat::from_euler(EulerRot::XYZ, rx, ry, rz),
        translate,
    );
    Ok(SceneObject { mesh, model, material, casts_shadow: d.shape != Some(Shape::Ground) })
}

/// Gives `mesh` its material's maps (each where the material has one; else what the mesh's MTL brought), turned
/// row for row where the mesh is an OBJ's (its v runs up the image), and scales a ground's or plane's UVs so that
/// one repeat covers the material's `map_size_m` at the object's `scale`.
fn place_maps(
    mesh: &mut Mesh,
    material: &SceneMaterial,
    shape: Option<Shape>,
    scale: f64,
) -> std::result::Result<(), String> {
    if !material.maps.is_empty() {
        let own = if shape.is_none() { material.maps.flipped() } else { material.maps.clone() };
        mesh.maps.pigment = own.pigment.or(mesh.maps.pigment.take());
        mesh.maps.normal = own.normal.or(mesh.maps.normal.take());
    }
    let Some(size) = material.map_size_m else { return Ok(()) };
    let half = match shape {
        Some(Shape::Ground) => f64::from(crate::scene::mesh::shapes::GROUND_HALF),
        Some(Shape::Plane) => 1.0,
        _ => {
            return Err(format!(
                "[material.{}] has map_size_m, which is for the ground and planes (a mesh's or shape's own UVs place \
                 its maps)",
                material.name
            ))
        }
    };
    let repeats = (2.0 * half * scale / size) as f32;
    for v in &mut mesh.vertices {
        // About the centre (smaller numbers: f32 keeps a map's texels apart over thousands of repeats).
        v.uv = v.uv.map(|c| (c - 0.5) * repeats);
    }
    Ok(())
}
