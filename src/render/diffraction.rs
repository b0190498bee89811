//! Diffraction shading on the GPU: a patch's resources (the Taylor terms as one RG32F 2D-array image, or the
//! baked colour table as a mip-mapped RGBA32F 2D-array image; the spectral table, the `DiffractionParams`
//! uniforms), the BRDF-map pass and the compute evaluation behind `diffract brdf --gpu`.

use ash::vk;
use glam::DVec3;

use crate::error::{Error, Result};
use crate::gpu::interface::{
    EvalPush, MapPush, BINDING_FETCH_COUNTS, BINDING_MAP_IMAGE, BINDING_PARAMS, BINDING_QUERIES, BINDING_RESULTS,
    BINDING_SPECTRUM, BINDING_TABLE, LOCAL_SIZE_X, SPEC_COUNT_STRIDE, SPEC_FOOTPRINT, SPEC_MAP_LOCAL_SIZE,
    SPEC_TABLE_TEXELS,
};
use crate::gpu::shaders;
use crate::gpu::vk::{
    Blend, Buffer, BufferDesc, ComputePipelineDesc, Context, DescriptorWrite, GraphicsPipelineDesc, Guard, Image,
    ImageDesc, ImageState, MemoryState, Pipeline, Sampler, SpecConstants,
};
use crate::io::progress::Progress;
use crate::material::Material;
use crate::physics::baked::sample::MipFilter;
use crate::physics::exact::Query;
use crate::physics::spectrum;
use crate::render::{begin_rendering, end_rendering, OffscreenTarget, TargetView, LINEAR_FORMAT};

/// Rows per submission of a BRDF map: keeps each submission short (no driver watchdog) and lets long maps
/// report progress.
const MAP_BAND_ROWS: u32 = 32;

/// The baked table's texel format: filtered linearly in every Vulkan driver diffract targets (checked).
pub const TABLE_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// A material's GPU resources, uploaded once.
pub(crate) struct PatchResources {
    pub terms: Image,
    pub sampler: Sampler,
    /// The material's moments against the environment (`light::prefilter`), or one black texel where it has none;
    /// filtered linearly.
    pub moments: Image,
    pub moments_sampler: Sampler,
    /// Whether `moments` holds a material's (else the black texel).
    pub has_moments: bool,
    pub spectrum: Buffer,
    pub params: Buffer,
    /// What uploading the Taylor terms or the baked table cost.
    pub upload: Upload,
}

/// A texture's upload: its bytes, the copy's GPU time (where the queue has timestamps) and the wall time of
/// staging, copying and waiting.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Upload {
    pub bytes: u64,
    pub gpu_ms: Option<f64>,
    pub wall_ms: f64,
}

/// How `ctx`'s frames read `material`'s baked table between its mip levels (its `table_mips` setting).
pub(crate) fn table_filter(ctx: &Context, material: &Material) -> MipFilter {
    material.settings.table_mips.filter(ctx.info.kind == vk::PhysicalDeviceType::CPU)
}

/// `material`'s specialization constants for a counting variant on `ctx` (texels per table read).
pub(crate) fn counting_constants(
    ctx: &Context,
    material: &Material,
    specialization: SpecConstants,
    stride: u32,
) -> SpecConstants {
    specialization.u32(SPEC_COUNT_STRIDE, stride).u32(SPEC_TABLE_TEXELS, table_filter(ctx, material).texels_per_read())
}

impl PatchResources {
    pub fn new(ctx: &Context, material: &Material) -> Result<Self> {
        let limits = &ctx.info.limits;
        let (what, desc, sampler_name) = match &material.table {
            Some(table) => {
                if !ctx.filters_linearly(TABLE_FORMAT) {
                    return Err(Error::unsupported(
                        &ctx.info.name,
                        format!(
                            "{} cannot filter RGBA32F textures linearly, which the baked approach needs; use \
                         --approach flss",
                            ctx.info.name
                        ),
                    ));
                }
                let (w, h) = (table.grid.nu as u32, table.grid.nv as u32);
                let desc = ImageDesc::texture_array(w, h, table.layers() as u32, TABLE_FORMAT)
                    .with_mips(table.levels.len() as u32);
                ("baked table", desc, "baked table")
            }
            None => {
                let (nx, ny) = (material.nx as u32, material.ny as u32);
                let desc = ImageDesc::texture_array(nx, ny, material.layers, vk::Format::R32G32_SFLOAT);
                ("taylor terms", desc, "taylor terms (nearest)")
            }
        };
        if desc.width > limits.max_image_dimension2_d || desc.height > limits.max_image_dimension2_d {
            return Err(Error::unsupported(
                &ctx.info.name,
                format!(
                    "a {}×{} {what} exceeds the device's {}-texel image limit",
                    desc.width, desc.height, limits.max_image_dimension2_d
                ),
            ));
        }
        if desc.layers > limits.max_image_array_layers {
            return Err(Error::unsupported(
                &ctx.info.name,
                format!(
                    "{} layers of {what} exceed the device's {} image layers",
                    desc.layers, limits.max_image_array_layers
                ),
            ));
        }
        let terms = Guard::new(ctx, ctx.create_image(desc, what)?);
        let start = std::time::Instant::now();
        let gathered: Vec<f32>;
        let texels = match &material.table {
            Some(table) => {
                gathered = table.levels.iter().flat_map(|l| l.texels.iter().copied()).collect();
                &gathered
            }
            None => &material.texels,
        };
        let gpu_ms = ctx.upload_image(&terms, bytemuck::cast_slice(texels), ImageState::SHADER_READ)?;
        let upload = Upload {
            bytes: std::mem::size_of_val(&texels[..]) as u64,
            gpu_ms,
            wall_ms: start.elapsed().as_secs_f64() * 1e3,
        };
        let sampler = match material.table {
            Some(_) => {
                let mip = match table_filter(ctx, material) {
                    MipFilter::Linear => vk::SamplerMipmapMode::LINEAR,
                    MipFilter::Nearest => vk::SamplerMipmapMode::NEAREST,
                };
                ctx.create_table_sampler(sampler_name, mip)?
            }
            None => ctx.create_sampler(sampler_name)?,
        };
        let sampler = Guard::new(ctx, sampler);
        let layers = crate::light::prefilter::MOMENT_LAYERS as u32;
        let (moment_side, moment_texels) = match &material.moments {
            Some(m) => (m.grid as u32, m.gpu_texels()),
            None => (1, vec![0.0; layers as usize * 4]),
        };
        let moments_desc = ImageDesc::texture_array(moment_side, moment_side, layers, TABLE_FORMAT);
        let moments = Guard::new(ctx, ctx.create_image(moments_desc, "environment moments")?);
        ctx.upload_image(&moments, bytemuck::cast_slice(&moment_texels), ImageState::SHADER_READ)?;
        let moments_sampler = Guard::new(ctx, ctx.create_filtered_sampler("environment moments (bilinear)", true)?);
        let table = spectrum::gpu_table(&material.sampling);
        let spectrum = Guard::new(
            ctx,
            ctx.create_buffer_init(
                vk::BufferUsageFlags::STORAGE_BUFFER,
                bytemuck::cast_slice(&table),
                "CIE 1931 × the illuminant",
            )?,
        );
        let size = std::mem::size_of_val(&material.params) as u64;
        let mut params = Guard::new(
            ctx,
            ctx.create_buffer(BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER), "diffraction params")?,
        );
        params.write(bytemuck::bytes_of(&material.params))?;
        Ok(Self {
            terms: terms.keep(),
            sampler: sampler.keep(),
            moments: moments.keep(),
            moments_sampler: moments_sampler.keep(),
            has_moments: material.moments.is_some(),
            spectrum: spectrum.keep(),
            params: params.keep(),
            upload,
        })
    }

    /// Writes the uniforms (the light direction of a map, say); no submitted work may be reading them.
    pub fn update(&mut self, params: &crate::gpu::interface::DiffractionParams) -> Result<()> {
        self.params.write(bytemuck::bytes_of(params))
    }

    pub fn writes(&self) -> [DescriptorWrite<'_>; 3] {
        [
            DescriptorWrite::UniformBuffer(BINDING_PARAMS, &self.params),
            DescriptorWrite::SampledImage(BINDING_TABLE, &self.terms, &self.sampler),
            DescriptorWrite::StorageBuffer(BINDING_SPECTRUM, &self.spectrum),
        ]
    }

    /// The moments' descriptor (the surface pass's).
    pub fn moments_write(&self) -> DescriptorWrite<'_> {
        DescriptorWrite::SampledImage(crate::gpu::interface::BINDING_MOMENTS, &self.moments, &self.moments_sampler)
    }

    /// # Safety
    /// The GPU must be done with the resources.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.terms.destroy(ctx);
        self.sampler.destroy(ctx);
        self.moments.destroy(ctx);
        self.moments_sampler.destroy(ctx);
        self.spectrum.destroy(ctx);
        self.params.destroy(ctx);
    }
}

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

/// The material's uniforms with the light direction `light` (unit, patch frame).
pub(crate) fn light_params(material: &Material, light: DVec3) -> crate::gpu::interface::DiffractionParams {
    let mut params = material.params;
    params.light = [light.x as f32, light.y as f32, light.z as f32, 0.0];
    params
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

/// One query as `glsl/brdf_eval.comp.glsl` reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuQuery {
    omega_i_lambda: [f32; 4],
    omega_r: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuQuery>() == 32);

/// Evaluates (power, reflectance) of the Taylor sum for each query on the GPU, in f32.
pub fn evaluate_brdf(ctx: &Context, material: &Material, queries: &[Query]) -> Result<Vec<(f64, f64)>> {
    if queries.is_empty() {
        return Ok(Vec::new());
    }
    let gpu: Vec<GpuQuery> = queries
        .iter()
        .map(|q| {
            let (i, r) = (q.omega_i(), q.omega_r());
            GpuQuery {
                omega_i_lambda: [i.x as f32, i.y as f32, i.z as f32, q.lambda_nm as f32],
                omega_r: [r.x as f32, r.y as f32, r.z as f32, 0.0],
            }
        })
        .collect();
    let patch = Guard::new(ctx, PatchResources::new(ctx, material)?);
    let input =
        ctx.create_buffer_init(vk::BufferUsageFlags::STORAGE_BUFFER, bytemuck::cast_slice(&gpu), "brdf queries");
    let input = Guard::new(ctx, input?);
    let output = Guard::new(ctx, ctx.create_buffer(BufferDesc::readback(8 * queries.len() as u64), "brdf results")?);
    let pipeline = Guard::new(
        ctx,
        ctx.create_compute_pipeline(&ComputePipelineDesc {
            name: "brdf evaluation",
            shader: &shaders::BRDF_EVAL_COMP,
            specialization: material.spec_constants(false),
            push_constant_size: std::mem::size_of::<EvalPush>() as u32,
        })?,
    );
    let [p, t, s] = patch.writes();
    let writes = [
        p,
        t,
        s,
        DescriptorWrite::StorageBuffer(BINDING_QUERIES, &input),
        DescriptorWrite::StorageBuffer(BINDING_RESULTS, &output),
    ];
    let count = queries.len() as u32;
    ctx.one_shot("brdf evaluation", |cmd| {
        ctx.bind(cmd, &pipeline, &writes, bytemuck::bytes_of(&EvalPush { count }));
        // SAFETY: recording with the pipeline bound.
        unsafe { ctx.device().cmd_dispatch(cmd, count.div_ceil(LOCAL_SIZE_X), 1, 1) };
        ctx.barrier_memory(cmd, MemoryState::COMPUTE_WRITE, MemoryState::HOST_READ);
    })?;
    let bytes = ctx.read_buffer(&output)?;
    let values: Vec<f32> = bytemuck::pod_collect_to_vec(&bytes);
    Ok(values.chunks(2).map(|v| (f64::from(v[0]), f64::from(v[1]))).collect())
}

crate::impl_destroy!(PatchResources, MapPass, MapCompute, MapPipeline);
