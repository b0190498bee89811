//! The frame renderer: a scene's GPU state ([`crate::render::scene_gpu`]) and the path that shades it
//! ([`crate::render::forward`] or [`crate::render::visibility`]). A frame records, in order: the sun's shadow map
//! (where it changed), then the path's passes, the environment behind or under the objects among them.
//!
//! A [`SceneRenderer`] is made for a first view, so that the pipelines its frames need exist from the start;
//! [`SceneRenderer::update`] writes the uniforms for each later view and switches pipelines where the view's
//! shadows change.

use ash::vk;

use crate::error::Result;
use crate::gpu::vk::{Context, Guard};
use crate::render::forward::ForwardPath;
pub use crate::render::scene_gpu::{orientation, MaterialInput, SurfaceMaterial, SurfaceVariant};
use crate::render::scene_gpu::{Formats, SceneGpu};
use crate::render::visibility::{ShadingPath, VisibilityPath};
use crate::render::{Instruments, SceneView, TargetView};
use crate::scene::mesh::Mesh;

/// What a renderer's frames are drawn into and how: the targets' colour format and samples, the build of the
/// surface shader, and the path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RendererSetup {
    pub format: vk::Format,
    pub samples: vk::SampleCountFlags,
    pub variant: SurfaceVariant,
    /// Forward, or the visibility buffer (linear frames of the first view's extent, not the counting variant).
    pub path: ShadingPath,
}

impl RendererSetup {
    /// Forward frames of `samples` into targets of `format`, display-encoded by the shaders or linear.
    pub fn forward(format: vk::Format, display_output: bool, samples: vk::SampleCountFlags) -> Self {
        Self { format, samples, variant: SurfaceVariant::Shade { display_output }, path: ShadingPath::Forward }
    }
}

/// The shading path a renderer takes, with its pipelines.
enum Path {
    Forward(ForwardPath),
    /// Boxed: its state (targets, buffers per object) is several times the forward path's pipelines.
    Visibility(Box<VisibilityPath>),
}

/// A scene's GPU state and the path that draws its frames (see the module's header).
pub struct SceneRenderer {
    scene: SceneGpu,
    path: Path,
}

impl SceneRenderer {
    pub const NAME: &'static str = crate::render::forward::NAME;

    /// Uploads `materials` and `objects` ((mesh, index into `materials`)) and builds the pipelines `setup` asks
    /// for, to draw `first` into targets of `extent` (its uniforms written, as by [`Self::update`]).
    pub fn new(
        ctx: &Context,
        (materials, objects): (&[MaterialInput<'_>], &[(&Mesh, usize)]),
        setup: RendererSetup,
        (first, extent): (&SceneView, vk::Extent2D),
    ) -> Result<Self> {
        let meshes = || objects.iter().map(|(mesh, _)| *mesh);
        let formats = Formats {
            color: setup.format,
            samples: setup.samples,
            variant: setup.variant,
            cull_back_faces: crate::render::culls_back_faces(meshes()),
            front_first: meshes().all(|mesh| mesh.front_first),
        };
        let visibility = setup.path == ShadingPath::Visibility;
        let mut scene = Guard::new(ctx, SceneGpu::new(ctx, materials, objects, formats, visibility)?);
        let aspect = extent.width as f32 / extent.height as f32;
        let spec = scene.update(ctx, first, aspect)?;
        let path = match setup.path {
            ShadingPath::Forward => Path::Forward(ForwardPath::new(ctx, &scene, spec)?),
            ShadingPath::Visibility => Path::Visibility(Box::new(VisibilityPath::new(ctx, &scene, extent, spec)?)),
        };
        Ok(Self { scene: scene.keep(), path })
    }

    /// Which path the renderer's frames take.
    pub fn path(&self) -> ShadingPath {
        match self.path {
            Path::Forward(_) => ShadingPath::Forward,
            Path::Visibility(_) => ShadingPath::Visibility,
        }
    }

    /// Writes every object's uniforms for `view` (its camera, light, sky, placements and shadow casters) at
    /// `aspect`, places the shadow map and the environment, and makes the pipelines for the view's shadows and
    /// lamps current; no submitted work may still read any of it.
    pub fn update(&mut self, ctx: &Context, view: &SceneView, aspect: f32) -> Result<()> {
        let spec = self.scene.update(ctx, view, aspect)?;
        match &mut self.path {
            Path::Forward(path) => path.select(ctx, &self.scene, spec),
            Path::Visibility(path) => path.select(ctx, &self.scene, spec),
        }
    }

    /// Sets the exposure and the tone curve of the shaders' display output; no submitted work may still read the
    /// uniforms.
    pub fn set_display(&mut self, exposure_ev: f64, tone: crate::display::Tone) -> Result<()> {
        self.scene.set_display(exposure_ev, tone)
    }

    /// Records every object into `target` (in attachment layouts).
    pub fn record(&self, ctx: &Context, cmd: vk::CommandBuffer, target: &TargetView, background: [f32; 4]) {
        self.record_with(ctx, cmd, target, background, Instruments::default());
    }

    /// [`Self::record`] with `instruments`: a counting renderer's per-pixel fetch counters, the shading draws
    /// bracketed for a pipeline-statistics query (the depth pre-pass is not counted), and a lap at the end of
    /// each pass ([`crate::render::pass`]).
    pub fn record_with(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        target: &TargetView,
        background: [f32; 4],
        instruments: Instruments<'_>,
    ) {
        let formats = &self.scene.formats;
        debug_assert_eq!(formats.variant.counting(), instruments.counts.is_some(), "counters for counting renderers");
        debug_assert_eq!(
            formats.samples, target.samples,
            "the renderer's pipelines are built for the target's samples"
        );
        self.scene.record_shadow(ctx, cmd);
        match &self.path {
            Path::Forward(path) => path.record(ctx, cmd, &self.scene, (target, background), instruments),
            Path::Visibility(path) => path.record(ctx, cmd, &self.scene, (target, background), instruments),
        }
    }

    /// What the uploads of the materials' tables (or Taylor terms) cost, material by material.
    pub fn uploads(&self) -> Vec<crate::render::diffraction::Upload> {
        self.scene.uploads()
    }

    /// # Safety
    /// The GPU must be done with everything.
    pub unsafe fn destroy(self, ctx: &Context) {
        match self.path {
            Path::Forward(path) => path.destroy(ctx),
            Path::Visibility(path) => path.destroy(ctx),
        }
        self.scene.destroy(ctx);
    }
}

crate::impl_destroy!(SceneRenderer);
