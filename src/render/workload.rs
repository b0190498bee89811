//! The GPU side of `diffract profile`: a workload (a BRDF map, or a scene) drawn as one timed submission per
//! frame, its Taylor-term texel fetches counted per pixel by the shaders' counting variants, and the roofline
//! probe that measures the device's RG32F texel-fetch throughput.

use std::time::Instant;

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::interface::{BINDING_TABLE, SPEC_PROBE_LAYERS, SPEC_PROBE_TAPS};
use crate::gpu::shaders;
use crate::gpu::vk::{
    Blend, Buffer, BufferDesc, Context, DescriptorWrite, FrameTimes, GraphicsPipelineDesc, Guard, Image, ImageDesc,
    ImageState, Laps, MemoryState, PassProfile, Pipeline, Statistics,
};
use crate::render::diffraction::{PatchResources, Upload};
use crate::render::map::{map_target, MapPass, MapPipeline, MapShader, MapSpec};
use crate::render::offscreen::FrameTarget;
use crate::render::surface::{MaterialInput, RendererSetup, SceneRenderer, SurfaceVariant};
use crate::render::visibility::ShadingPath;
use crate::render::{pass, Instruments, OffscreenTarget, SceneView, LINEAR_FORMAT};
use crate::scene::mesh::Mesh;

/// One frame's cost: GPU time pass by pass (timestamps), wall time of record + submit + wait on the CPU, and
/// fragment invocations (pipeline statistics) where the device has them.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSample {
    pub times: Option<FrameTimes>,
    pub cpu_ms: f64,
    pub fragment_invocations: Option<u64>,
}

impl FrameSample {
    /// The frame's GPU time, its passes together.
    pub fn gpu_ms(&self) -> Option<f64> {
        self.times.as_ref().map(FrameTimes::total_ms)
    }

    /// Times one frame, recorded by `record` and copied into `readback` after it (as `render` copies its frames
    /// back) from `image`, left by `record` in `state`.
    fn measure(
        ctx: &Context,
        name: &str,
        (image, state, readback): (&Image, ImageState, &Buffer),
        record: impl FnOnce(vk::CommandBuffer, &Statistics<'_>, Laps<'_>),
    ) -> Result<Self> {
        let start = Instant::now();
        let PassProfile { times, fragment_invocations } = ctx.one_shot_profiled(name, |cmd, statistics, laps| {
            record(cmd, statistics, laps);
            ctx.record_readback(cmd, image, state, readback);
            laps.lap(cmd, pass::COPY);
        })?;
        Ok(Self { times, cpu_ms: start.elapsed().as_secs_f64() * 1e3, fragment_invocations })
    }
}

/// What the profiler times: frames drawn into an offscreen linear target.
pub trait Workload {
    /// Draws one frame as one submission and waits for it.
    fn frame(&mut self, ctx: &Context) -> Result<FrameSample>;
    /// The last frame's linear scene-referred RGBA, rows top first (a scene's display target: its 8-bit codes / 255).
    fn image(&self, ctx: &Context) -> Result<Vec<f32>>;
    /// What uploading each material's table or Taylor terms cost.
    fn uploads(&self) -> Vec<Upload>;
    /// Draws one frame with the counting shaders: each pixel's texel fetches and shadings, rows top first.
    fn count_fetches(&mut self, ctx: &Context) -> Result<Vec<Counts>>;
    /// The pipeline that draws a BRDF map's frames (None: a scene, always rasterised).
    fn map_shader(&self) -> Option<MapShader> {
        None
    }
    /// # Safety
    /// The GPU must be done with the workload.
    unsafe fn destroy(self: Box<Self>, ctx: &Context);
}

/// What the counting shaders record per pixel (`fetch_counts` in glsl/include/params.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Counts {
    /// Texels fetched (Taylor terms, or the baked table's trilinear samples at 8 texels each).
    pub fetches: u32,
    /// Fragment-shader invocations that shaded the pixel (after the early depth test, unlike llvmpipe's pipeline
    /// statistics, which count every rasterised 4×4 block).
    pub shaded: u32,
}
const _: () = assert!(std::mem::size_of::<Counts>() == 8);

/// Zeroed per-pixel counters, drawn into by `record`, read back.
pub(crate) fn counted_frame(
    ctx: &Context,
    width: u32,
    height: u32,
    name: &str,
    record: impl FnOnce(vk::CommandBuffer, &Buffer),
) -> Result<Vec<Counts>> {
    let bytes = (std::mem::size_of::<Counts>() as u64) * u64::from(width) * u64::from(height);
    let counts = ctx.create_buffer(BufferDesc::readback(bytes), "fetch counts")?;
    let result = ctx
        .one_shot(name, |cmd| {
            // SAFETY: cmd is recording; the buffer was made with TRANSFER_DST usage.
            unsafe { ctx.device().cmd_fill_buffer(cmd, counts.raw, 0, vk::WHOLE_SIZE, 0) };
            ctx.barrier_memory(cmd, MemoryState::TRANSFER_WRITE, MemoryState::FRAGMENT_STORAGE);
            record(cmd, &counts);
            ctx.barrier_memory(cmd, MemoryState::FRAGMENT_STORAGE, MemoryState::HOST_READ);
        })
        .and_then(|()| ctx.read_buffer(&counts))
        .map(|bytes| bytemuck::pod_collect_to_vec(&bytes));
    // SAFETY: one_shot waited.
    unsafe { counts.destroy(ctx) };
    result
}

/// A BRDF map of one material for one light, `size`×`size`, drawn in one submission per frame by either
/// pipeline; its fetches are counted by the fragment pass's counting variant (the same code per pixel).
pub struct MapWorkload {
    patch: PatchResources,
    pass: MapPipeline,
    counting: MapPass,
    target: OffscreenTarget,
    readback: Buffer,
    size: u32,
}

impl MapWorkload {
    /// The map `spec` asks for.
    pub fn new(ctx: &Context, spec: &MapSpec<'_>) -> Result<Self> {
        let MapSpec { material, size, footprint, .. } = *spec;
        let (patch, pass) = spec.parts(ctx)?;
        let counting = Guard::new(ctx, MapPass::counting(ctx, material, size, footprint)?);
        let target = Guard::new(ctx, map_target(ctx, size, size)?);
        let readback = ctx.create_readback(&target.color)?;
        Ok(Self {
            patch: patch.keep(),
            pass: pass.keep(),
            counting: counting.keep(),
            target: target.keep(),
            readback,
            size,
        })
    }
}

impl Workload for MapWorkload {
    fn frame(&mut self, ctx: &Context) -> Result<FrameSample> {
        let (pipeline, target, patch) = (&self.pass, &self.target, &self.patch);
        let copy = (&target.color, pipeline.target_state(), &self.readback);
        FrameSample::measure(ctx, pipeline.name(), copy, |cmd, statistics, laps| {
            // The whole map in one submission (a compute dispatch invokes no fragment shader: statistics of 0).
            statistics.begin(cmd);
            pipeline.record(ctx, cmd, patch, target, 0..self.size, true);
            statistics.end(cmd);
            laps.lap(cmd, pass::SHADING);
        })
    }

    fn image(&self, _ctx: &Context) -> Result<Vec<f32>> {
        Ok(bytemuck::pod_collect_to_vec(self.readback.mapped().unwrap_or_default()))
    }

    fn uploads(&self) -> Vec<Upload> {
        vec![self.patch.upload]
    }

    fn count_fetches(&mut self, ctx: &Context) -> Result<Vec<Counts>> {
        let (target, pass, patch) = (&self.target, &self.counting, &self.patch);
        counted_frame(ctx, self.size, self.size, "brdf map (counting fetches)", |cmd, counts| {
            target.begin(ctx, cmd);
            pass.record(ctx, cmd, patch, &target.view(), None, Some(counts));
        })
    }

    fn map_shader(&self) -> Option<MapShader> {
        Some(self.pass.shader())
    }

    unsafe fn destroy(self: Box<Self>, ctx: &Context) {
        self.pass.destroy(ctx);
        self.counting.destroy(ctx);
        self.target.destroy(ctx);
        self.readback.destroy(ctx);
        self.patch.destroy(ctx);
    }
}

/// Texels across the probe's texture (and its layers): 16 layers of 512² RG32F, 32 MiB, larger than the caches
/// of most GPUs' texture units, as the Taylor terms of a 1000² patch are.
const PROBE_SIDE: u32 = 512;
const PROBE_LAYERS: u32 = 16;
/// Taps per axis per fragment: 8 × 8 neighbouring texels × 16 layers = 1024 fetches per pixel.
const PROBE_TAPS: u32 = 8;
/// The probe grows its target until one frame takes at least this long (timestamps resolve far better, but
/// short frames measure launch overhead, not fetches).
const PROBE_MIN_MS: f64 = 20.0;
const PROBE_MAX_SIDE: u32 = 4096;

/// The roofline probe's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeResult {
    /// Median RG32F texel fetches per second over the frames.
    pub fetches_per_s: f64,
    /// Target side of the timed frames, pixels.
    pub side: u32,
    pub fetches_per_frame: u64,
    pub median_gpu_ms: f64,
}

/// Measures the device's RG32F texel-fetch throughput with `glsl/fetch_probe.frag.glsl`: the median over
/// `frames` frames (after one warm-up) of fetches / GPU time. `None` where the device has no timestamps.
pub fn fetch_probe(ctx: &Context, frames: usize) -> Result<Option<ProbeResult>> {
    if frames == 0 {
        return Err(Error::setting("frames", "the probe needs at least one frame".into()));
    }
    let desc = ImageDesc::texture_array(PROBE_SIDE, PROBE_SIDE, PROBE_LAYERS, vk::Format::R32G32_SFLOAT);
    let texture = Guard::new(ctx, ctx.create_image(desc, "fetch probe texture")?);
    // Deterministic non-trivial texels (a cheap hash), so the sums are not constant.
    let texels: Vec<f32> = (0..PROBE_SIDE * PROBE_SIDE * PROBE_LAYERS * 2)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 8) as f32 / (1u32 << 24) as f32)
        .collect();
    ctx.upload_image(&texture, bytemuck::cast_slice(&texels), ImageState::SHADER_READ)?;
    let sampler = Guard::new(ctx, ctx.create_sampler("fetch probe (nearest)")?);
    let pipeline = Guard::new(
        ctx,
        ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
            name: PROBE_NAME,
            vertex: &shaders::FULLSCREEN_VERT,
            fragment: Some(&shaders::FETCH_PROBE_FRAG),
            specialization: crate::gpu::vk::SpecConstants::default()
                .u32(SPEC_PROBE_LAYERS, PROBE_LAYERS)
                .i32(SPEC_PROBE_TAPS, PROBE_TAPS as i32),
            push_constant_size: 0,
            vertex_stride: 0,
            vertex_attributes: &[],
            color_format: LINEAR_FORMAT,
            depth: None,
            cull_back_faces: false,
            samples: vk::SampleCountFlags::TYPE_1,
            blend: Blend::Replace,
        })?,
    );
    let writes = [DescriptorWrite::SampledImage(BINDING_TABLE, &texture, &sampler)];
    let mut side = 256;
    loop {
        let target = Guard::new(ctx, OffscreenTarget::with_format(ctx, side, side, LINEAR_FORMAT, false)?);
        let Some(median_ms) = probe_frames(ctx, &target, &pipeline, &writes, frames)? else { return Ok(None) };
        if median_ms >= PROBE_MIN_MS || side >= PROBE_MAX_SIDE {
            let fetches_per_frame = u64::from(side) * u64::from(side) * u64::from(PROBE_TAPS.pow(2) * PROBE_LAYERS);
            return Ok(Some(ProbeResult {
                fetches_per_s: fetches_per_frame as f64 / (median_ms * 1e-3),
                side,
                fetches_per_frame,
                median_gpu_ms: median_ms,
            }));
        }
        side *= 2;
    }
}

const PROBE_NAME: &str = "fetch probe";

/// One warm-up frame, then the median GPU time of `frames` frames (None without timestamps).
fn probe_frames(
    ctx: &Context,
    target: &OffscreenTarget,
    pipeline: &Pipeline,
    writes: &[DescriptorWrite<'_>],
    frames: usize,
) -> Result<Option<f64>> {
    let mut times = Vec::with_capacity(frames);
    for i in 0..=frames {
        let ms = ctx.one_shot_timed(PROBE_NAME, |cmd| {
            target.begin(ctx, cmd);
            crate::render::begin_rendering(ctx, cmd, &target.view(), Some([0.0; 4]), None);
            ctx.bind(cmd, pipeline, writes, &[]);
            // SAFETY: recording inside the rendering scope with the pipeline bound.
            unsafe { ctx.device().cmd_draw(cmd, 3, 1, 0, 0) };
            crate::render::end_rendering(ctx, cmd);
        })?;
        let Some(ms) = ms else { return Ok(None) };
        if i > 0 {
            times.push(ms);
        }
    }
    Ok(crate::io::stats::median(&times))
}

/// A scene drawn by the surface pass into a linear float target with depth, one submission per frame.
pub struct SceneWorkload<'a> {
    inputs: Vec<MaterialInput<'a>>,
    objects: Vec<(&'a Mesh, usize)>,
    view: SceneView,
    renderer: SceneRenderer,
    target: OffscreenTarget,
    readback: Buffer,
    frame_target: FrameTarget,
    width: u32,
    height: u32,
}

impl<'a> SceneWorkload<'a> {
    /// Frames of `width`×`height` with `samples` per pixel into `frame_target` (as `render` or `view` draws them),
    /// shaded on `path`.
    pub fn new(
        ctx: &Context,
        inputs: Vec<MaterialInput<'a>>,
        objects: Vec<(&'a Mesh, usize)>,
        view: SceneView,
        (width, height): (u32, u32),
        (samples, frame_target, path): (vk::SampleCountFlags, FrameTarget, ShadingPath),
    ) -> Result<Self> {
        let format = frame_target.format();
        let target = Guard::new(ctx, OffscreenTarget::multisampled(ctx, width, height, format, true, samples)?);
        let shade = SurfaceVariant::Shade { display_output: frame_target.display_output() };
        let mut target = target;
        let renderer = Guard::new(ctx, Self::renderer(ctx, &inputs, &objects, &view, (shade, path), &target)?);
        if path == ShadingPath::Visibility {
            // SAFETY: nothing has drawn into the target yet.
            unsafe { target.for_visibility_buffer(ctx)? };
        }
        let readback = ctx.create_readback(&target.color)?;
        let (renderer, target) = (renderer.keep(), target.keep());
        Ok(Self { inputs, objects, view, renderer, target, readback, frame_target, width, height })
    }

    fn renderer(
        ctx: &Context,
        inputs: &[MaterialInput<'_>],
        objects: &[(&Mesh, usize)],
        view: &SceneView,
        (variant, path): (SurfaceVariant, ShadingPath),
        target: &OffscreenTarget,
    ) -> Result<SceneRenderer> {
        let (extent, samples, format) = (target.color.extent(), target.view().samples, target.color.desc.format);
        let setup = RendererSetup { format, samples, variant, path };
        let mut renderer = Guard::new(ctx, SceneRenderer::new(ctx, (inputs, objects), setup, (view, extent))?);
        if variant.display_output() {
            // As the viewer draws them by default (the exposure stays 0 EV: the frames are timed, not compared).
            renderer.set_display(0.0, crate::display::Tone::Filmic)?;
        }
        Ok(renderer.keep())
    }
}

impl Workload for SceneWorkload<'_> {
    fn frame(&mut self, ctx: &Context) -> Result<FrameSample> {
        let copy = (&self.target.color, ImageState::COLOR_ATTACHMENT, &self.readback);
        FrameSample::measure(ctx, SceneRenderer::NAME, copy, |cmd, statistics, laps| {
            self.target.begin(ctx, cmd);
            let instruments = Instruments { statistics: Some(statistics), laps, ..Instruments::default() };
            self.renderer.record_with(ctx, cmd, &self.target.view(), self.view.background, instruments);
        })
    }

    /// Linear RGBA; a display target's encoded values over 255 (timed, not compared with the exact reference).
    fn image(&self, _ctx: &Context) -> Result<Vec<f32>> {
        let bytes = self.readback.mapped().unwrap_or_default();
        Ok(match self.frame_target {
            FrameTarget::Linear => bytemuck::pod_collect_to_vec(bytes),
            FrameTarget::Display => bytes.iter().map(|&b| f32::from(b) / 255.0).collect(),
        })
    }

    fn uploads(&self) -> Vec<Upload> {
        self.renderer.uploads()
    }

    fn count_fetches(&mut self, ctx: &Context) -> Result<Vec<Counts>> {
        let variant = SurfaceVariant::CountFetches { stride: self.width };
        // Counted forward: both paths shade each visible triangle of a pixel once, with the same fetches. A
        // visibility buffer's target has no colour samples, so the forward count draws into a target of its own.
        let forward = (variant, ShadingPath::Forward);
        let own = match self.renderer.path() {
            ShadingPath::Forward => None,
            ShadingPath::Visibility => {
                let (format, samples) = (self.target.color.desc.format, self.target.view().samples);
                Some(OffscreenTarget::multisampled(ctx, self.width, self.height, format, true, samples)?)
            }
        };
        let own = Guard::new(ctx, own);
        let target = own.as_ref().unwrap_or(&self.target);
        let renderer = Self::renderer(ctx, &self.inputs, &self.objects, &self.view, forward, target)?;
        let background = self.view.background;
        let counts = counted_frame(ctx, self.width, self.height, "surface (counting fetches)", |cmd, counts| {
            target.begin(ctx, cmd);
            let instruments = Instruments { counts: Some(counts), ..Instruments::default() };
            renderer.record_with(ctx, cmd, &target.view(), background, instruments);
        });
        // SAFETY: counted_frame waited (and the guard destroys the target of its own).
        unsafe { renderer.destroy(ctx) };
        counts
    }

    unsafe fn destroy(self: Box<Self>, ctx: &Context) {
        self.renderer.destroy(ctx);
        self.target.destroy(ctx);
        self.readback.destroy(ctx);
    }
}
