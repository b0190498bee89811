//! BRDF maps on the GPU: a hemisphere of views for one light, drawn by a full-screen fragment shader or a compute
//! shader (the same pixels: `glsl/include/map_pixel.glsl`), band by band, and read back.

use ash::vk;
use glam::DVec3;

use crate::error::Result;
use crate::gpu::interface::{MapPush, BINDING_FETCH_COUNTS, BINDING_MAP_IMAGE, SPEC_FOOTPRINT, SPEC_MAP_LOCAL_SIZE};
use crate::gpu::shaders;
use crate::gpu::vk::{
    Blend, Buffer, ComputePipelineDesc, Context, DescriptorWrite, GraphicsPipelineDesc, Guard, Image, ImageDesc,
    ImageState, Pipeline,
};
use crate::io::progress::Progress;
use crate::material::Material;
use crate::render::diffraction::{counting_constants, light_params, PatchResources};
use crate::render::{begin_rendering, end_rendering, OffscreenTarget, TargetView, LINEAR_FORMAT};

/// Rows per submission of a BRDF map: keeps each submission short (no driver watchdog) and lets long maps
/// report progress.
const MAP_BAND_ROWS: u32 = 32;

/// A BRDF map read back: linear scene-referred sRGB-primaries RGBA, rows top first.
#[derive(Clone, Debug)]
pub struct MapImage {
    pub size: u32,
    pub rgba: Vec<f32>,
    /// GPU time of the map pass (all bands), where the device has timestamps.
    pub gpu_ms: Option<f64>,
}

impl MapImage {
    pub fn pixel(&self, x: u32, y: u32) -> DVec3 {
        let i = ((y * self.size + x) * 4) as usize;
        DVec3::new(f64::from(self.rgba[i]), f64::from(self.rgba[i + 1]), f64::from(self.rgba[i + 2]))
    }

    /// Pixels whose colour is not a finite number (a bug, reported loudly rather than written).
    pub fn non_finite(&self) -> usize {
        crate::io::stats::non_finite_pixels(&self.rgba)
    }

    /// Display-referred 8-bit sRGB RGBA after `exposure_ev` stops and the tone curve.
    pub fn to_rgba8(&self, exposure_ev: f64, tone: crate::display::Tone) -> Vec<u8> {
        crate::display::tone::to_rgba8(&self.rgba, exposure_ev, tone)
    }
}

/// The BRDF-map pipeline for one material.
pub(crate) struct MapPass {
    pipeline: Pipeline,
    counting: bool,
}

impl MapPass {
    pub const NAME: &'static str = "brdf map";

    /// `display_output`: exposure and sRGB in the shader (for a window's UNORM images); else linear RGB.
    /// `footprint`: a baked material averages over each pixel's footprint instead of reading its point value.
    pub fn new(
        ctx: &Context,
        material: &Material,
        color_format: vk::Format,
        display_output: bool,
        footprint: bool,
    ) -> Result<Self> {
        Self::build(ctx, material, color_format, display_output, None, footprint)
    }

    /// The profiler's variant: linear output, and each fragment adds its texel fetches (Taylor terms or baked
    /// table) to a per-pixel counter (`u32` at y·`stride` + x of the buffer passed to [`Self::record`]).
    pub fn counting(ctx: &Context, material: &Material, stride: u32, footprint: bool) -> Result<Self> {
        Self::build(ctx, material, LINEAR_FORMAT, false, Some(stride), footprint)
    }

    fn build(
        ctx: &Context,
        material: &Material,
        color_format: vk::Format,
        display_output: bool,
        count_stride: Option<u32>,
        footprint: bool,
    ) -> Result<Self> {
        let baked = material.table.is_some();
        let mut specialization = material.spec_constants(display_output).u32(SPEC_FOOTPRINT, u32::from(footprint));
        let mut fragment = if baked { &shaders::MAP_BAKED_FRAG } else { &shaders::MAP_FRAG };
        if let Some(stride) = count_stride {
            specialization = counting_constants(ctx, material, specialization, stride);
            fragment = if baked { &shaders::MAP_BAKED_COUNT_FRAG } else { &shaders::MAP_COUNT_FRAG };
        }
        let pipeline = ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
            name: Self::NAME,
            vertex: &shaders::FULLSCREEN_VERT,
            fragment: Some(fragment),
            specialization,
            push_constant_size: std::mem::size_of::<MapPush>() as u32,
            vertex_stride: 0,
            vertex_attributes: &[],
            color_format,
            depth: None,
            cull_back_faces: false,
            samples: vk::SampleCountFlags::TYPE_1,
            blend: Blend::Replace,
        })?;
        Ok(Self { pipeline, counting: count_stride.is_some() })
    }

    /// Records the map as the largest centred square of `target` (clearing `area`, or all of it, to black). A
    /// counting pass needs its counter buffer in `counts`.
    pub fn record(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        patch: &PatchResources,
        target: &TargetView,
        area: Option<vk::Rect2D>,
        counts: Option<&Buffer>,
    ) {
        let (w, h) = (target.extent.width as f32, target.extent.height as f32);
        let side = w.min(h);
        let push = MapPush { size: [side, side], offset: [0.5 * (w - side), 0.5 * (h - side)], origin: [0.0; 2] };
        debug_assert_eq!(self.counting, counts.is_some(), "a counting pass takes counters, and only it");
        let mut writes: Vec<DescriptorWrite<'_>> = patch.writes().into();
        if let Some(counts) = counts.filter(|_| self.counting) {
            writes.push(DescriptorWrite::StorageBuffer(BINDING_FETCH_COUNTS, counts));
        }
        begin_rendering(ctx, cmd, target, Some([0.0, 0.0, 0.0, 1.0]), area);
        ctx.bind(cmd, &self.pipeline, &writes, bytemuck::bytes_of(&push));
        // SAFETY: recording inside the rendering scope with the pipeline bound.
        unsafe { ctx.device().cmd_draw(cmd, 3, 1, 0, 0) };
        end_rendering(ctx, cmd);
    }

    /// # Safety
    /// No pending work may use the pass.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.pipeline.destroy(ctx);
    }
}

/// Which pipeline draws a BRDF map. Both give the same pixels (glsl/include/map_pixel.glsl).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapShader {
    /// A compute shader writing a storage image. It needs no raster unit, which on a compute part like an NVIDIA
    /// H200 is the scarce one: there the Elaphe map's shading ran 9–41× faster than as fragments.
    Compute,
    /// A full-screen triangle's fragment shader: what the viewer draws into its window, and offscreen maps on a
    /// CPU device, where lavapipe's tiled rasteriser read the baked table 1.07–1.31× faster than compute groups.
    Fragment,
}

impl MapShader {
    pub const NAMES: [&'static str; 2] = ["compute", "fragment"];

    /// The pipeline offscreen maps use on `ctx`'s device (`diffract map`, the profiler unless a sweep asks):
    /// compute on a GPU, fragment on a CPU device (measured as above).
    pub fn for_device(ctx: &Context) -> Self {
        if ctx.info.kind == vk::PhysicalDeviceType::CPU {
            Self::Fragment
        } else {
            Self::Compute
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Compute => "compute",
            Self::Fragment => "fragment",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "compute" => Some(Self::Compute),
            "fragment" => Some(Self::Fragment),
            _ => None,
        }
    }
}

/// The side of `map.comp`'s square workgroups on `ctx`'s device: 8 on a GPU (as measured on an H200), 16 on a CPU
/// device, where lavapipe ran the Elaphe map's baked 1024² shading in 50.6 ms with 8×8 groups, 30.6–34.3 with
/// 16×16 and 26–32 as fragments (its rasteriser walks tiles whose texels stay in cache).
pub(crate) fn map_workgroup(ctx: &Context) -> u32 {
    if ctx.info.kind == vk::PhysicalDeviceType::CPU {
        16
    } else {
        8
    }
}

/// The BRDF-map compute pipeline for one material (glsl/map.comp.glsl): linear RGB into an RGBA32F storage image
/// ([`ImageState::STORAGE`]) the size of the target, the map being its largest centred square.
pub(crate) struct MapCompute {
    pipeline: Pipeline,
    /// The workgroups' side ([`map_workgroup`]).
    group: u32,
}

impl MapCompute {
    pub const NAME: &'static str = "brdf map (compute)";

    /// `footprint`: a baked material averages over each pixel's footprint instead of reading its point value.
    pub fn new(ctx: &Context, material: &Material, footprint: bool) -> Result<Self> {
        let baked = material.table.is_some();
        let group = map_workgroup(ctx);
        let specialization =
            material.spec_constants(false).u32(SPEC_FOOTPRINT, u32::from(footprint)).u32(SPEC_MAP_LOCAL_SIZE, group);
        let pipeline = ctx.create_compute_pipeline(&ComputePipelineDesc {
            name: Self::NAME,
            shader: if baked { &shaders::MAP_BAKED_COMP } else { &shaders::MAP_COMP },
            specialization,
            push_constant_size: std::mem::size_of::<MapPush>() as u32,
        })?;
        Ok(Self { pipeline, group })
    }

    /// Records the rows `rows` of the map into `image` (in [`ImageState::STORAGE`]).
    pub fn record(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        patch: &PatchResources,
        image: &Image,
        rows: std::ops::Range<u32>,
    ) {
        let vk::Extent2D { width, height } = image.extent();
        let (w, h) = (width as f32, height as f32);
        let side = w.min(h);
        let push = MapPush {
            size: [side, side],
            offset: [0.5 * (w - side), 0.5 * (h - side)],
            origin: [0.0, rows.start as f32],
        };
        let mut writes: Vec<DescriptorWrite<'_>> = patch.writes().into();
        writes.push(DescriptorWrite::StorageImage(BINDING_MAP_IMAGE, image));
        ctx.bind(cmd, &self.pipeline, &writes, bytemuck::bytes_of(&push));
        let rows = rows.end.min(height).saturating_sub(rows.start);
        let groups = (width.div_ceil(self.group), rows.div_ceil(self.group));
        // SAFETY: recording outside a render pass with the pipeline bound.
        unsafe { ctx.device().cmd_dispatch(cmd, groups.0, groups.1, 1) };
    }

    /// # Safety
    /// No pending work may use the pass.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.pipeline.destroy(ctx);
    }
}

/// A BRDF map's pipeline, of either kind.
pub(crate) enum MapPipeline {
    Fragment(MapPass),
    Compute(MapCompute),
}

impl MapPipeline {
    /// Linear output; `footprint` as in [`MapPass::new`].
    pub fn new(ctx: &Context, material: &Material, footprint: bool, shader: MapShader) -> Result<Self> {
        Ok(match shader {
            MapShader::Fragment => Self::Fragment(MapPass::new(ctx, material, LINEAR_FORMAT, false, footprint)?),
            MapShader::Compute => Self::Compute(MapCompute::new(ctx, material, footprint)?),
        })
    }

    pub fn shader(&self) -> MapShader {
        match self {
            Self::Fragment(_) => MapShader::Fragment,
            Self::Compute(_) => MapShader::Compute,
        }
    }

    /// The name its submissions are labelled and timed with.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Fragment(_) => MapPass::NAME,
            Self::Compute(_) => MapCompute::NAME,
        }
    }

    /// The state [`Self::record`] leaves the target's colour image in (to copy it back from).
    pub fn target_state(&self) -> ImageState {
        match self {
            Self::Fragment(_) => ImageState::COLOR_ATTACHMENT,
            Self::Compute(_) => ImageState::STORAGE,
        }
    }

    /// Records the rows `rows` of the map into `target` (a [`map_target`]); `first`: the target's earlier
    /// contents are discarded, else this continues the rows an earlier submission drew.
    pub fn record(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        patch: &PatchResources,
        target: &OffscreenTarget,
        rows: std::ops::Range<u32>,
        first: bool,
    ) {
        match self {
            Self::Fragment(pass) => {
                if first {
                    target.begin(ctx, cmd);
                } else {
                    target.continue_rendering(ctx, cmd);
                }
                let extent = target.color.extent();
                let area = vk::Rect2D {
                    offset: vk::Offset2D { x: 0, y: rows.start as i32 },
                    extent: vk::Extent2D { width: extent.width, height: rows.end.min(extent.height) - rows.start },
                };
                pass.record(ctx, cmd, patch, &target.view(), Some(area), None);
            }
            Self::Compute(compute) => {
                let from = if first { ImageState::UNDEFINED } else { ImageState::STORAGE };
                ctx.barrier_image(cmd, &target.color, from, ImageState::STORAGE);
                compute.record(ctx, cmd, patch, &target.color, rows);
            }
        }
    }

    /// # Safety
    /// No pending work may use the pipeline.
    pub unsafe fn destroy(self, ctx: &Context) {
        match self {
            Self::Fragment(p) => p.destroy(ctx),
            Self::Compute(p) => p.destroy(ctx),
        }
    }
}

/// A map's colour target that both pipelines can draw into (an attachment and a storage image), and read back.
pub(crate) fn map_target(ctx: &Context, width: u32, height: u32) -> Result<OffscreenTarget> {
    let mut desc = ImageDesc::render_target(width, height, LINEAR_FORMAT);
    desc.usage |= vk::ImageUsageFlags::STORAGE;
    OffscreenTarget::with_color(ctx, desc)
}

/// Renders the BRDF map of `material` for a light from `light` (unit, patch frame), `size`×`size` pixels, with the
/// device's pipeline ([`MapShader::for_device`]); `footprint`: a baked material averages over each pixel (else each
/// pixel is the point value at its centre).
pub fn render_map(ctx: &Context, material: &Material, size: u32, light: DVec3, footprint: bool) -> Result<MapImage> {
    let shader = MapShader::for_device(ctx);
    render_map_with(ctx, &MapSpec { material, size, light, footprint, shader })
}

/// What a BRDF map shows and how it is drawn.
#[derive(Clone, Copy)]
pub struct MapSpec<'a> {
    pub material: &'a Material,
    /// Pixels on a side.
    pub size: u32,
    /// Towards the light (unit, patch frame).
    pub light: DVec3,
    /// A baked material averages over each pixel (else each pixel is the point value at its centre).
    pub footprint: bool,
    pub shader: MapShader,
}

impl MapSpec<'_> {
    /// The map's patch resources, lit from its light, and its pipeline, each held by a guard until kept.
    pub(crate) fn parts<'a>(&self, ctx: &'a Context) -> Result<(Guard<'a, PatchResources>, Guard<'a, MapPipeline>)> {
        let mut patch = Guard::new(ctx, PatchResources::new(ctx, self.material)?);
        patch.update(&light_params(self.material, self.light))?;
        let pipeline = Guard::new(ctx, MapPipeline::new(ctx, self.material, self.footprint, self.shader)?);
        Ok((patch, pipeline))
    }
}

/// The map `spec` asks for.
pub fn render_map_with(ctx: &Context, spec: &MapSpec<'_>) -> Result<MapImage> {
    let (patch, pipeline) = spec.parts(ctx)?;
    draw_map_bands(ctx, &pipeline, &patch, spec.size)
}

/// Draws the map band by band.
fn draw_map_bands(ctx: &Context, pipeline: &MapPipeline, patch: &PatchResources, size: u32) -> Result<MapImage> {
    let target = Guard::new(ctx, map_target(ctx, size, size)?);
    let mut gpu_ms = Some(0.0);
    let bands = size.div_ceil(MAP_BAND_ROWS);
    let bar = Progress::new_if(size >= 128, format!("rendering map {size}²"), bands as usize);
    bar.detail(format!("bands of {MAP_BAND_ROWS} rows"));
    for band in 0..bands {
        let y0 = band * MAP_BAND_ROWS;
        let rows = y0..(y0 + MAP_BAND_ROWS).min(size);
        let band_ms =
            ctx.one_shot_timed(pipeline.name(), |cmd| pipeline.record(ctx, cmd, patch, &target, rows, band == 0))?;
        gpu_ms = gpu_ms.zip(band_ms).map(|(total, ms)| total + ms);
        bar.step();
    }
    bar.finish();
    let bytes = ctx.read_image(&target.color, pipeline.target_state())?;
    Ok(MapImage { size, rgba: bytemuck::pod_collect_to_vec(&bytes), gpu_ms })
}

crate::impl_destroy!(MapPass, MapCompute, MapPipeline);
