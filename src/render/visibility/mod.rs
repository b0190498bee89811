//! The visibility buffer: a scene's frame shaded once per pixel and visible triangle, in three passes — the
//! raster pass (each sample's triangle id at the frame's samples, `glsl/visibility.frag`), the shading pass (per
//! object a full-screen triangle that rebuilds each pixel's first triangle from its vertices and shades it with
//! the forward path's code, `glsl/surface_resolve.frag`) and, with several samples, the edge pass (a compute
//! dispatch over the pixels that see further triangles, `glsl/surface_edges.comp`). ARCHITECTURE.md ("The
//! visibility buffer") says why, and what each pass writes.
//!
//! `VisibilityPath` owns the path's pipelines and its per-size state (`state::VisibilityState`); it draws
//! linear frames only (not a window's display-encoded ones, nor the profiler's counting ones). It agrees with the
//! forward path up to float rounding and the footprint's finite difference (`tests/gpu/visibility.rs`).

pub(crate) mod state;

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::interface::{
    Vertex, VisibilityPush, BINDING_MESH_INDICES, BINDING_VERTEX_OUTPUTS, BINDING_VISIBILITY_EDGES,
    BINDING_VISIBILITY_IDS, BINDING_VISIBILITY_TARGET, VISIBILITY_MAX_SAMPLES,
};
use crate::gpu::shaders;
use crate::gpu::shaders::VERTEX_ATTRIBUTES;
use crate::gpu::vk::{
    Blend, ComputePipelineDesc, Context, DepthTest, DescriptorWrite, Destroy, GraphicsPipelineDesc, Guard, ImageState,
    MemoryState, Pipeline,
};
use crate::render::scene_gpu::{MaterialGpu, SceneGpu, ViewSpec, ViewVariants};
use crate::render::{end_rendering, pass, Instruments, MeshBuffers, TargetView, DEPTH_FORMAT};
pub use state::check;
use state::{VisibilityState, VERTEX_STORAGE_WRITE};

/// How a scene's frame is shaded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadingPath {
    /// Each object's fragments shaded as they are drawn, into a target of the frame's samples (then resolved).
    #[default]
    Forward,
    /// Triangles first, then one shading per pixel and visible triangle (this module).
    Visibility,
}

impl ShadingPath {
    pub const NAMES: [&'static str; 2] = ["forward", "visibility"];

    pub fn name(self) -> &'static str {
        match self {
            Self::Forward => "forward",
            Self::Visibility => "visibility",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "forward" => Some(Self::Forward),
            "visibility" => Some(Self::Visibility),
            _ => None,
        }
    }

    /// The path `diffract render` takes for `meshes` when the user does not choose: [`Self::for_frame`]'s, but
    /// forward where the scene is beyond the visibility buffer's limits (objects, triangles), with the reason.
    pub fn for_scene<'a>(
        ctx: &Context,
        samples: vk::SampleCountFlags,
        meshes: impl ExactSizeIterator<Item = &'a crate::scene::mesh::Mesh>,
    ) -> (Self, Option<Error>) {
        match Self::for_frame(ctx, samples) {
            Self::Forward => (Self::Forward, None),
            Self::Visibility => match check(ctx, samples, meshes.map(|m| (m.indices.len() / 3) as u32)) {
                Ok(()) => (Self::Visibility, None),
                Err(e) => (Self::Forward, Some(e)),
            },
        }
    }

    /// The path a frame of `samples` per pixel takes on `ctx`'s device when the user does not choose: the
    /// visibility buffer on a CPU device with several samples (any count it takes, up to `VISIBILITY_MAX_SAMPLES`;
    /// lavapipe offers 4), where it was measured about twice as fast at the same error against the exact reference
    /// (docs/performance.md); forward at one sample, where the two cost the same, and on GPUs, where the
    /// visibility buffer is not measured yet.
    pub fn for_frame(ctx: &Context, samples: vk::SampleCountFlags) -> Self {
        let cpu = ctx.info.kind == vk::PhysicalDeviceType::CPU;
        let multisampled = (2..=VISIBILITY_MAX_SAMPLES).contains(&samples.as_raw());
        match cpu && multisampled && ctx.has_visibility_buffer() {
            true => Self::Visibility,
            false => Self::Forward,
        }
    }
}

/// A material's pipelines for the path's passes: the raster pass, the shading pass and, where the frame has
/// several samples, the edge pass.
pub(crate) struct VisibilityPipelines {
    raster: Pipeline,
    shade: Pipeline,
    edges: Option<Pipeline>,
}

impl VisibilityPipelines {
    /// `material`'s, for a view of `spec`.
    fn new(ctx: &Context, scene: &SceneGpu, material: &MaterialGpu, spec: ViewSpec) -> Result<Self> {
        let formats = scene.formats;
        let multisampled = formats.samples != vk::SampleCountFlags::TYPE_1;
        let push_constant_size = std::mem::size_of::<VisibilityPush>() as u32;
        let specialization = material.specialization(spec);
        let raster = Guard::new(
            ctx,
            ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                name: pass::VISIBILITY,
                vertex: if material.sky_at_vertex {
                    &shaders::SURFACE_SKY_VISIBILITY_VERT
                } else {
                    &shaders::SURFACE_VISIBILITY_VERT
                },
                fragment: Some(&shaders::VISIBILITY_FRAG),
                specialization: specialization.clone(),
                push_constant_size,
                vertex_stride: std::mem::size_of::<Vertex>() as u32,
                vertex_attributes: &VERTEX_ATTRIBUTES,
                color_format: vk::Format::R32_UINT,
                depth: Some((DEPTH_FORMAT, DepthTest::Write)),
                cull_back_faces: formats.cull_back_faces,
                samples: formats.samples,
                blend: Blend::Replace,
            })?,
        );
        // The shading pass's fragment shader for frames of one sample per pixel and of several.
        let resolve = match (material.baked, multisampled) {
            (true, false) => &shaders::SURFACE_RESOLVE_BAKED_ONE_FRAG,
            (true, true) => &shaders::SURFACE_RESOLVE_BAKED_FRAG,
            (false, false) => &shaders::SURFACE_RESOLVE_ONE_FRAG,
            (false, true) => &shaders::SURFACE_RESOLVE_FRAG,
        };
        // One triangle over the viewport at the far plane (background.vert), tested behind the resolved depth.
        let shade = Guard::new(
            ctx,
            ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                name: crate::render::forward::NAME,
                vertex: &shaders::BACKGROUND_VERT,
                fragment: Some(resolve),
                specialization: specialization.clone(),
                push_constant_size,
                vertex_stride: 0,
                vertex_attributes: &[],
                color_format: formats.color,
                depth: Some((DEPTH_FORMAT, DepthTest::Behind)),
                cull_back_faces: false,
                samples: vk::SampleCountFlags::TYPE_1,
                blend: Blend::Add,
            })?,
        );
        let edges = multisampled
            .then(|| {
                ctx.create_compute_pipeline(&ComputePipelineDesc {
                    name: pass::EDGES,
                    shader: if material.baked {
                        &shaders::SURFACE_EDGES_BAKED_COMP
                    } else {
                        &shaders::SURFACE_EDGES_COMP
                    },
                    specialization,
                    push_constant_size,
                })
            })
            .transpose()?;
        Ok(Self { raster: raster.keep(), shade: shade.keep(), edges })
    }

    /// Every material's, for a view of `spec`.
    fn of_scene(ctx: &Context, scene: &SceneGpu, spec: ViewSpec) -> Result<Vec<Self>> {
        let mut all = Guard::new(ctx, Vec::with_capacity(scene.materials.len()));
        for material in &scene.materials {
            all.push(Self::new(ctx, scene, material, spec)?);
        }
        Ok(all.keep())
    }

    /// # Safety
    /// No pending work may use them.
    unsafe fn destroy(self, ctx: &Context) {
        self.raster.destroy(ctx);
        self.shade.destroy(ctx);
        self.edges.destroy(ctx);
    }
}

/// The path: its state for frames of one size and its pipelines for the current view's [`ViewSpec`].
pub(crate) struct VisibilityPath {
    state: VisibilityState,
    pipelines: ViewVariants<Vec<VisibilityPipelines>>,
}

impl VisibilityPath {
    /// The path for `scene`'s frames of `extent` (and the scene's samples), shading a view of `spec`: linear colour
    /// only, and not the counting variant.
    pub fn new(ctx: &Context, scene: &SceneGpu, extent: vk::Extent2D, spec: ViewSpec) -> Result<Self> {
        let variant = scene.formats.variant;
        if variant.display_output() || variant.counting() {
            return Err(Error::Invalid(
                "the visibility buffer draws linear frames (not a window's, nor the profiler's counting ones)".into(),
            ));
        }
        let meshes: Vec<&MeshBuffers> = scene.objects.iter().map(|o| &o.mesh).collect();
        let state = Guard::new(ctx, VisibilityState::new(ctx, extent, scene.formats.samples, &meshes)?);
        let pipelines = ViewVariants::new(spec, |s| VisibilityPipelines::of_scene(ctx, scene, s))?;
        Ok(Self { state: state.keep(), pipelines })
    }

    /// Makes the pipelines for a view of `spec` current (built the first time).
    pub fn select(&mut self, ctx: &Context, scene: &SceneGpu, spec: ViewSpec) -> Result<()> {
        self.pipelines.select(spec, |s| VisibilityPipelines::of_scene(ctx, scene, s))
    }

    /// Records a frame of `scene` into `target`: the raster pass into the ids and the target's depth at the
    /// target's samples, then the shading pass into its one-sample colour (the resolve image of a target that keeps
    /// colour samples, which are left untouched) with the environment under it, then the edge pass.
    pub fn record(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        scene: &SceneGpu,
        (target, background): (&TargetView, [f32; 4]),
        instruments: Instruments<'_>,
    ) {
        debug_assert_eq!(self.state.ids.extent(), target.extent, "the visibility buffer is made for the target's size");
        let depth = target.depth.expect("a scene's target has a depth buffer");
        // Under an environment the objects add their colours to zero and the background goes under them; over a
        // constant background each object takes its share of the background away (`surface_resolve.frag`).
        let constant = if scene.background().is_some() { [0.0; 4] } else { background };
        let frame = Frame { scene, pipelines: self.pipelines.current(), state: &self.state, target, depth, constant };
        frame.raster(ctx, cmd, instruments);
        frame.shade(ctx, cmd, instruments);
        if !self.state.edges.is_empty() {
            frame.edges(ctx, cmd, instruments);
        }
    }

    /// # Safety
    /// No pending work may use the path.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.state.destroy(ctx);
        self.pipelines.destroy(ctx);
    }
}

/// What one frame's passes read.
struct Frame<'a> {
    scene: &'a SceneGpu,
    pipelines: &'a [VisibilityPipelines],
    state: &'a VisibilityState,
    target: &'a TargetView,
    /// The target's depth.
    depth: vk::ImageView,
    /// The colour the shading pass clears to and each object's share of it (zero under an environment).
    constant: [f32; 4],
}

impl Frame<'_> {
    /// Object `i`'s push constants (`edge`: 0, the shading pass; k, the edge pass's k-th list).
    fn push(&self, i: usize, edge: u32) -> VisibilityPush {
        let [r, g, b, a] = self.constant;
        VisibilityPush {
            object: i as u32 + 1,
            background_r: r,
            background_g: g,
            background_b: b,
            background_a: a,
            edge,
        }
    }

    /// Object `i`'s pipelines.
    fn pipelines(&self, i: usize) -> &VisibilityPipelines {
        &self.pipelines[self.scene.objects[i].material]
    }

    /// The raster pass: every object's triangles into the ids and the depth (resolved into the coverage depth
    /// where the frame has several samples), each vertex's outputs into its object's buffer.
    fn raster(&self, ctx: &Context, cmd: vk::CommandBuffer, instruments: Instruments<'_>) {
        let state = self.state;
        ctx.barrier_image(cmd, &state.ids, state::IDS_READ, ImageState::COLOR_ATTACHMENT);
        if let Some(coverage) = &state.coverage {
            ctx.barrier_image(cmd, coverage, state::COVERAGE_TESTED, ImageState::DEPTH_ATTACHMENT);
        }
        ctx.barrier_memory(cmd, state::OUTPUTS_READ, VERTEX_STORAGE_WRITE);
        let ids = [vk::RenderingAttachmentInfo::default()
            .image_view(state.ids.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue { color: vk::ClearColorValue { uint32: [0; 4] } })];
        let far = vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue { depth: crate::scene::camera::FAR_DEPTH, stencil: 0 },
        };
        let kept =
            if state.coverage.is_some() { vk::AttachmentStoreOp::DONT_CARE } else { vk::AttachmentStoreOp::STORE };
        let mut depth = vk::RenderingAttachmentInfo::default()
            .image_view(self.depth)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(kept)
            .clear_value(far);
        if let (Some(coverage), Some(mode)) = (&state.coverage, state.resolve) {
            depth = depth
                .resolve_mode(mode)
                .resolve_image_view(coverage.view)
                .resolve_image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL);
        }
        state::begin(ctx, cmd, &ids, &depth, self.target.extent);
        ctx.begin_label(cmd, pass::VISIBILITY);
        for (i, object) in self.scene.objects.iter().enumerate() {
            let mut writes = self.scene.object_writes(i);
            writes.push(DescriptorWrite::StorageBuffer(BINDING_VERTEX_OUTPUTS, &state.outputs[i]));
            ctx.bind(cmd, &self.pipelines(i).raster, &writes, bytemuck::bytes_of(&self.push(i, 0)));
            object.mesh.draw(ctx, cmd);
        }
        ctx.end_label(cmd);
        end_rendering(ctx, cmd);
        instruments.laps.lap(cmd, pass::VISIBILITY);
    }

    /// The descriptors object `i`'s shading and edge passes read.
    fn shade_writes(&self, i: usize) -> Vec<DescriptorWrite<'_>> {
        let state = self.state;
        let mut writes = self.scene.object_writes(i);
        writes.extend([
            DescriptorWrite::SampledImage(BINDING_VISIBILITY_IDS, &state.ids, &state.sampler),
            DescriptorWrite::StorageBuffer(BINDING_VERTEX_OUTPUTS, &state.outputs[i]),
            DescriptorWrite::StorageBuffer(BINDING_MESH_INDICES, &self.scene.objects[i].mesh.indices),
        ]);
        if let Some(list) = state.edges.get(i) {
            writes.push(DescriptorWrite::StorageBuffer(BINDING_VISIBILITY_EDGES, list));
        }
        writes
    }

    /// The shading pass: per object a full-screen triangle behind the coverage depth, adding each pixel's first
    /// triangle into the one-sample colour and listing the pixels that see more; the environment under them.
    fn shade(&self, ctx: &Context, cmd: vk::CommandBuffer, instruments: Instruments<'_>) {
        let state = self.state;
        ctx.barrier_image(cmd, &state.ids, ImageState::COLOR_ATTACHMENT, ImageState::SHADER_READ);
        ctx.barrier_memory(cmd, VERTEX_STORAGE_WRITE, MemoryState::FRAGMENT_STORAGE);
        ctx.barrier_memory(cmd, state::DEPTH_WRITTEN, state::DEPTH_TESTED);
        state.reset_edges(ctx, cmd);
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(self.target.resolve.unwrap_or(self.target.color))
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: self.constant } })];
        // The coverage: the resolved depth, or the one-sample frame's own; where the device resolves neither way,
        // the near plane's depth everywhere lets every pixel through.
        let known = state.coverage.is_none() || state.resolve.is_some();
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(state.coverage.as_ref().map_or(self.depth, |c| c.view))
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(if known { vk::AttachmentLoadOp::LOAD } else { vk::AttachmentLoadOp::CLEAR })
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: crate::scene::camera::NEAR_DEPTH, stencil: 0 },
            });
        state::begin(ctx, cmd, &color, &depth, self.target.extent);
        if let Some(s) = instruments.statistics {
            s.begin(cmd);
        }
        ctx.begin_label(cmd, pass::SHADING);
        for i in 0..self.scene.objects.len() {
            ctx.bind(cmd, &self.pipelines(i).shade, &self.shade_writes(i), bytemuck::bytes_of(&self.push(i, 0)));
            // SAFETY: cmd is recording inside a rendering scope with a full-screen pipeline bound.
            unsafe { ctx.device().cmd_draw(cmd, 3, 1, 0, 0) };
        }
        ctx.end_label(cmd);
        if let Some(s) = instruments.statistics {
            s.end(cmd);
        }
        if let Some(environment) = self.scene.background() {
            environment.record(ctx, cmd);
        }
        end_rendering(ctx, cmd);
        instruments.laps.lap(cmd, pass::SHADING);
    }

    /// The edge pass: each object's listed pixels, their further triangles added to the colour in place (the
    /// frame's one-sample image, in the GENERAL layout meanwhile).
    fn edges(&self, ctx: &Context, cmd: vk::CommandBuffer, instruments: Instruments<'_>) {
        let image = self
            .target
            .storage
            .expect("a multisampled visibility frame's target is a storage image (for_visibility_buffer)");
        let state = self.state;
        let colour =
            vk::ImageSubresourceRange::default().aspect_mask(vk::ImageAspectFlags::COLOR).level_count(1).layer_count(1);
        ctx.barrier_raw_image(cmd, image, colour, ImageState::COLOR_ATTACHMENT, ImageState::STORAGE);
        ctx.barrier_memory(cmd, MemoryState::FRAGMENT_STORAGE, state::EDGES_NEXT);
        ctx.begin_label(cmd, pass::EDGES);
        let into = self.target.resolve.unwrap_or(self.target.color);
        for i in 0..self.scene.objects.len() {
            let Some(pipeline) = &self.pipelines(i).edges else { continue };
            let mut writes = self.shade_writes(i);
            writes.push(DescriptorWrite::StorageView(BINDING_VISIBILITY_TARGET, into));
            ctx.bind(cmd, pipeline, &writes, &[]);
            for k in 1..=state.edge_lists() {
                if i > 0 || k > 1 {
                    ctx.barrier_memory(cmd, state::EDGES_ADDED, state::EDGES_NEXT);
                }
                let push = self.push(i, k);
                let offset = u64::from(k - 1) * state::edge_list_bytes(self.target.extent);
                // SAFETY: cmd is recording outside a rendering scope with the edge pass bound; each list begins
                // with its dispatch's size, which the shading pass counted.
                unsafe {
                    ctx.device().cmd_push_constants(
                        cmd,
                        pipeline.layout,
                        pipeline.push_stages,
                        0,
                        bytemuck::bytes_of(&push),
                    );
                    ctx.device().cmd_dispatch_indirect(cmd, state.edges[i].raw, offset);
                }
            }
        }
        ctx.end_label(cmd);
        ctx.barrier_raw_image(cmd, image, colour, ImageState::STORAGE, ImageState::COLOR_ATTACHMENT);
        instruments.laps.lap(cmd, pass::EDGES);
    }
}

crate::impl_destroy!(VisibilityPipelines, VisibilityPath);
