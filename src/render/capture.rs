//! Capturing a scene offscreen: its materials prepared (with the command line's overrides), one renderer and one
//! linear float target reused for every frame of a sequence.

use glam::Vec3;

use crate::error::{Error, Result};
use crate::gpu::vk::{Context, Guard};
use crate::material::SettingsPatch;
use crate::material::{Material, Reach};
use crate::render::gbuffer::{merge_reaches, GBuffer};
use crate::render::offscreen::OffscreenFrames;
use crate::render::surface::{MaterialInput, RendererSetup, SceneRenderer, SurfaceMaterial, SurfaceVariant};
use crate::render::visibility::ShadingPath;
use crate::render::{Frame, SceneView};
use crate::scene::camera::Camera;
use crate::scene::mesh::Mesh;
use crate::scene::Scene;

/// What a matte material's (undrawn) patch is prepared for: one point, coarsely.
const MATTE_REACH: Reach =
    Reach::Seen { domain: crate::physics::baked::Domain::POINT, footprint: crate::render::gbuffer::UNSEEN_FOOTPRINT };

/// Prepares every material of `scene` (Taylor terms or baked table, plan, window) for the views `reaches[i]` of
/// material i (one for all when a single one is given).
pub fn prepare_materials(scene: &Scene, overrides: &SettingsPatch, reaches: &[Reach]) -> Result<Vec<Material>> {
    prepare(scene, overrides, reaches, true)
}

/// Every material of `scene` for any view under `overrides`, without the environment's diffraction (its moments
/// take seconds to tabulate the first time): what the viewer draws while the real materials are prepared.
pub fn prepare_stand_ins(scene: &Scene, overrides: &SettingsPatch) -> Result<Vec<Material>> {
    prepare(scene, overrides, &[Reach::ANY], false)
}

fn prepare(scene: &Scene, overrides: &SettingsPatch, reaches: &[Reach], moments: bool) -> Result<Vec<Material>> {
    if reaches.is_empty() || (reaches.len() != 1 && reaches.len() != scene.materials.len()) {
        return Err(Error::Invalid(format!("{} reaches for {} materials", reaches.len(), scene.materials.len())));
    }
    scene
        .materials
        .iter()
        .enumerate()
        .map(|(i, m)| {
            // A matte material's patch is never drawn: the smallest table serves it.
            let reach = if m.matte { &MATTE_REACH } else { &reaches[i.min(reaches.len() - 1)] };
            let settings = scene.material_settings(m, overrides);
            // Under an environment the grating diffracts it too (light::prefilter), by its BRDF's moments: tabulated
            // beside the material's own table (each leaves a core idle part of the time).
            let want_moments = moments && scene.environment.is_some() && !m.matte;
            let (material, moments) = rayon::join(
                || Material::prepare(&m.heightfield, settings, reach),
                || want_moments.then(|| crate::material::moments_of(&m.heightfield, &settings)),
            );
            let mut material =
                material.map_err(|e| Error::Material { name: m.name.clone(), part: "", cause: Box::new(e) })?;
            material.moments = moments.transpose().map_err(|e| Error::Material {
                name: m.name.clone(),
                part: "the environment's diffraction: ",
                cause: Box::new(e),
            })?;
            Ok(material)
        })
        .collect()
}

/// What each material of `scene` must serve when drawn at `width`×`height` from each of `views` (camera, world
/// direction towards the light): the (u, v, w) and footprints its pixels see, from a G-buffer of every view, under
/// the sun and each lamp (from its own direction at each pixel's point).
pub fn scene_reaches(
    ctx: &Context,
    scene: &Scene,
    views: &[(Camera, Vec3)],
    width: u32,
    height: u32,
) -> Result<Vec<Reach>> {
    let lamps = !scene.lamps.is_empty();
    let frames = views
        .iter()
        .map(|(camera, light)| {
            let gbuffer = GBuffer::draw(ctx, scene, (camera, *light), (width, height), lamps)?;
            Ok(gbuffer.reaches_under(scene.materials.len(), scene.sun || !lamps, &scene.lamps))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(merge_reaches(&frames, scene.materials.len()))
}

/// The renderer's view of `scene`'s materials (from [`prepare_materials`], in the same order).
pub(crate) fn material_inputs<'a>(scene: &Scene, materials: &'a [Material]) -> Vec<MaterialInput<'a>> {
    materials
        .iter()
        .zip(&scene.materials)
        .map(|(material, m)| MaterialInput { material, surface: SurfaceMaterial::of(m) })
        .collect()
}

/// `scene`'s objects as (mesh, material index) for [`SceneRenderer::new`].
pub(crate) fn scene_objects(scene: &Scene) -> Vec<(&Mesh, usize)> {
    scene.objects.iter().map(|o| (&o.mesh, o.material)).collect()
}

/// A scene's GPU state and offscreen target.
pub struct SceneCapture {
    renderer: SceneRenderer,
    frames: OffscreenFrames,
    width: u32,
    height: u32,
}

impl SceneCapture {
    /// Uploads `materials` (from [`prepare_materials`]) and `scene`'s meshes, with a `width`×`height` target of
    /// `samples` per pixel (see [`Context::sample_count`]), drawn on the forward path.
    pub fn new(
        ctx: &Context,
        scene: &Scene,
        materials: &[Material],
        width: u32,
        height: u32,
        samples: ash::vk::SampleCountFlags,
    ) -> Result<Self> {
        Self::with_path(ctx, scene, materials, (width, height), samples, ShadingPath::Forward)
    }

    /// [`Self::new`] on `path`: the visibility buffer ([`crate::render::visibility`]) refuses a scene beyond its
    /// limits (check first with [`crate::render::visibility::check`], as `diffract render` does).
    pub fn with_path(
        ctx: &Context,
        scene: &Scene,
        materials: &[Material],
        (width, height): (u32, u32),
        samples: ash::vk::SampleCountFlags,
        path: ShadingPath,
    ) -> Result<Self> {
        let (inputs, objects) = (material_inputs(scene, materials), scene_objects(scene));
        let format = OffscreenFrames::format(false);
        let setup = RendererSetup { format, samples, variant: SurfaceVariant::Shade { display_output: false }, path };
        let first = (&SceneView::of(scene), ash::vk::Extent2D { width, height });
        let renderer = Guard::new(ctx, SceneRenderer::new(ctx, (&inputs, &objects), setup, first)?);
        let mut frames = Guard::new(ctx, OffscreenFrames::new(ctx, width, height, false, samples)?);
        if path == ShadingPath::Visibility {
            frames.for_visibility_buffer(ctx)?;
        }
        Ok(Self { renderer: renderer.keep(), frames: frames.keep(), width, height })
    }

    /// Which path its frames take.
    pub fn path(&self) -> ShadingPath {
        self.renderer.path()
    }

    /// Renders one frame under `view`: linear scene-referred RGBA float, checked to be finite.
    pub fn render(&mut self, ctx: &Context, view: &SceneView) -> Result<Frame> {
        self.renderer.update(ctx, view, self.width as f32 / self.height as f32)?;
        let frame = self.frames.render(ctx, &self.renderer, view.background)?;
        let bad = frame.linear().map_or(0, crate::io::stats::non_finite_pixels);
        if bad > 0 {
            return Err(Error::Precision(format!("{bad} pixels are not finite numbers (a bug in diffract)")));
        }
        Ok(frame)
    }

    /// The exposure for `tone` metered from `frame` (this capture's frame of `view`), with the line that says what
    /// was chosen. The filmic curve's meter reads the pixels that show objects: found by drawing `view` once more
    /// with nothing behind the objects, whose alpha is then each pixel's coverage
    /// ([`SceneView::without_background`]); where no object is in view, the sky or the background it shows.
    /// Clip's reads every lit pixel's brightest channel (with the subject alone, its 99.5th percentile of
    /// luminance at 0.9 clipped a channel of most of a grating's saturated colours).
    pub fn meter(
        &mut self,
        ctx: &Context,
        view: &SceneView,
        frame: &[f32],
        tone: crate::display::Tone,
    ) -> Result<(f64, String)> {
        if tone == crate::display::Tone::Clip {
            return Ok(crate::display::measure(frame, None, "the first frame", tone));
        }
        let coverage = self.render(ctx, &view.without_background())?;
        let alpha = coverage.linear().expect("scene frames are captured linear");
        Ok(crate::display::measure(frame, Some(alpha), "the first frame", tone))
    }

    /// What uploading each material's table (or Taylor terms) cost.
    pub fn uploads(&self) -> Vec<crate::render::diffraction::Upload> {
        self.renderer.uploads()
    }

    /// # Safety
    /// The GPU must be done with every frame.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.frames.destroy(ctx);
        self.renderer.destroy(ctx);
    }
}

crate::impl_destroy!(SceneCapture);
