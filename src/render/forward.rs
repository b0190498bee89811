//! The forward path: each object's fragments shaded as they are drawn, into a target of the frame's samples
//! (then resolved).
//!
//! A frame draws every object twice: a depth pre-pass (vertex shader only), then the shading pass with an EQUAL
//! depth test, so that overlapping surfaces (a snake's scales lie four deep) are shaded once per pixel, not once
//! per layer. Where every mesh draws its triangles front first ([`crate::scene::mesh::Mesh::front_first`]: the
//! snake's scales top row first, flat and convex shapes) the pre-pass is left out: the shading pass tests
//! GREATER (depth is reversed, near 1) and writes depth, and the hidden fragments fail that test before they are
//! shaded. Objects are drawn in the scene's order: one hidden by an object before it fails the depth test
//! unshaded, one hidden by an object after it is shaded and then covered (the same image either way).

use ash::vk;

use crate::error::Result;
use crate::gpu::interface::{Vertex, BINDING_FETCH_COUNTS, BINDING_FRAME};
use crate::gpu::shaders;
use crate::gpu::shaders::VERTEX_ATTRIBUTES;
use crate::gpu::vk::{
    Blend, Context, DepthTest, DescriptorWrite, Destroy, GraphicsPipelineDesc, Guard, Pipeline, Shader, SpecConstants,
};
use crate::render::scene_gpu::{Formats, MaterialGpu, SceneGpu, SurfaceVariant, ViewSpec, ViewVariants};
use crate::render::{begin_rendering, end_rendering, pass, Instruments, TargetView, DEPTH_FORMAT};

/// The name the shading pipelines carry (labels).
pub const NAME: &str = "surface";

/// The forward path's pipelines: the depth pre-pass's (None where every mesh is drawn front first) and each
/// material's shading pipeline for the current view's [`ViewSpec`].
pub(crate) struct ForwardPath {
    depth: Option<Pipeline>,
    shading: ViewVariants<Vec<Pipeline>>,
}

impl ForwardPath {
    /// The path's pipelines for `scene`, shading a view of `spec`.
    pub fn new(ctx: &Context, scene: &SceneGpu, spec: ViewSpec) -> Result<Self> {
        let formats = scene.formats;
        let depth = (!formats.front_first).then(|| depth_pipeline(ctx, &formats)).transpose()?;
        let depth = Guard::new(ctx, depth);
        let pre_pass = depth.is_some();
        let shading = ViewVariants::new(spec, |s| shading_pipelines(ctx, scene, s, pre_pass))?;
        Ok(Self { depth: depth.keep(), shading })
    }

    /// Makes the pipelines for a view of `spec` current (built the first time).
    pub fn select(&mut self, ctx: &Context, scene: &SceneGpu, spec: ViewSpec) -> Result<()> {
        let pre_pass = self.depth.is_some();
        self.shading.select(spec, |s| shading_pipelines(ctx, scene, s, pre_pass))
    }

    /// Records `scene`'s objects into `target` (in attachment layouts): the depth pre-pass, the shading, the
    /// environment behind them, and the resolve of a multisampled target, each timed by `instruments.laps`.
    pub fn record(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        scene: &SceneGpu,
        (target, background): (&TargetView, [f32; 4]),
        instruments: Instruments<'_>,
    ) {
        let Instruments { counts, statistics, laps } = instruments;
        // Where the environment is drawn behind the objects, every sample is drawn: the colour needs no clear
        // (on a GPU, clearing a multisampled float target is much of what its samples cost).
        let environment = scene.background();
        begin_rendering(ctx, cmd, target, environment.is_none().then_some(background), None);
        if let Some(depth) = &self.depth {
            ctx.begin_label(cmd, pass::DEPTH);
            for object in &scene.objects {
                ctx.bind(cmd, depth, &[DescriptorWrite::UniformBuffer(BINDING_FRAME, &object.uniforms)], &[]);
                object.mesh.draw(ctx, cmd);
            }
            ctx.end_label(cmd);
            laps.lap(cmd, pass::DEPTH);
        }
        if let Some(s) = statistics {
            s.begin(cmd);
        }
        ctx.begin_label(cmd, pass::SHADING);
        for (i, object) in scene.objects.iter().enumerate() {
            let mut writes = scene.object_writes(i);
            if let Some(counts) = counts.filter(|_| scene.formats.variant.counting()) {
                writes.push(DescriptorWrite::StorageBuffer(BINDING_FETCH_COUNTS, counts));
            }
            ctx.bind(cmd, &self.shading.current()[object.material], &writes, &[]);
            object.mesh.draw(ctx, cmd);
        }
        ctx.end_label(cmd);
        if let Some(s) = statistics {
            s.end(cmd);
        }
        if let Some(environment) = environment {
            environment.record(ctx, cmd);
        }
        if target.resolve.is_some() {
            laps.lap(cmd, pass::SHADING);
            end_rendering(ctx, cmd);
            laps.lap(cmd, pass::RESOLVE);
        } else {
            end_rendering(ctx, cmd);
            laps.lap(cmd, pass::SHADING);
        }
    }

    /// # Safety
    /// No pending work may use the pipelines.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.depth.destroy(ctx);
        self.shading.destroy(ctx);
    }
}

/// The depth pre-pass: the surface's vertex shader alone, writing the nearest depth.
fn depth_pipeline(ctx: &Context, formats: &Formats) -> Result<Pipeline> {
    ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
        name: pass::DEPTH,
        vertex: &shaders::SURFACE_VERT,
        fragment: None,
        specialization: SpecConstants::default(),
        push_constant_size: 0,
        vertex_stride: std::mem::size_of::<Vertex>() as u32,
        vertex_attributes: &VERTEX_ATTRIBUTES,
        color_format: formats.color,
        depth: Some((DEPTH_FORMAT, DepthTest::Write)),
        cull_back_faces: formats.cull_back_faces,
        samples: formats.samples,
        blend: Blend::Replace,
    })
}

/// Each material's shading pipeline for a view of `spec`: after a depth pre-pass it tests EQUAL, else it tests
/// and writes depth itself.
fn shading_pipelines(ctx: &Context, scene: &SceneGpu, spec: ViewSpec, pre_pass: bool) -> Result<Vec<Pipeline>> {
    let formats = scene.formats;
    let mut pipelines = Guard::new(ctx, Vec::with_capacity(scene.materials.len()));
    for material in &scene.materials {
        let (vertex, fragment) = shaders_of(material, formats.variant);
        pipelines.push(ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
            name: NAME,
            vertex,
            fragment: Some(fragment),
            specialization: material.specialization(spec),
            push_constant_size: 0,
            vertex_stride: std::mem::size_of::<Vertex>() as u32,
            vertex_attributes: &VERTEX_ATTRIBUTES,
            color_format: formats.color,
            depth: Some((DEPTH_FORMAT, if pre_pass { DepthTest::Equal } else { DepthTest::Write })),
            cull_back_faces: formats.cull_back_faces,
            samples: formats.samples,
            blend: Blend::Replace,
        })?);
    }
    Ok(pipelines.keep())
}

/// The vertex and fragment shaders that draw `material` forward in the renderer's `variant`.
fn shaders_of(material: &MaterialGpu, variant: SurfaceVariant) -> (&'static Shader, &'static Shader) {
    let vertex = if material.sky_at_vertex { &shaders::SURFACE_SKY_VERT } else { &shaders::SURFACE_VERT };
    let fragment = match (variant, material.baked) {
        (SurfaceVariant::Shade { .. }, true) => &shaders::SURFACE_BAKED_FRAG,
        (SurfaceVariant::Shade { .. }, false) => &shaders::SURFACE_FRAG,
        (SurfaceVariant::CountFetches { .. }, true) => &shaders::SURFACE_BAKED_COUNT_FRAG,
        (SurfaceVariant::CountFetches { .. }, false) => &shaders::SURFACE_COUNT_FRAG,
    };
    (vertex, fragment)
}

crate::impl_destroy!(ForwardPath);
