//! A diffraction material on the GPU: its patch's resources (the Taylor terms as one RG32F 2D-array image, or the
//! baked colour table as a mip-mapped RGBA32F 2D-array image; the environment's moments; the spectral table; the
//! `DiffractionParams` uniforms), uploaded once and bound by every pass that shades it, and the compute evaluation
//! of the BRDF behind `diffract brdf --gpu`.

use ash::vk;
use glam::DVec3;

use crate::error::{Error, Result};
use crate::gpu::interface::{
    DiffractionParams, EvalPush, BINDING_MOMENTS, BINDING_PARAMS, BINDING_QUERIES, BINDING_RESULTS, BINDING_SPECTRUM,
    BINDING_TABLE, LOCAL_SIZE_X, SPEC_COUNT_STRIDE, SPEC_TABLE_TEXELS,
};
use crate::gpu::shaders;
use crate::gpu::vk::{
    Buffer, BufferDesc, ComputePipelineDesc, Context, DescriptorWrite, Guard, Image, ImageDesc, ImageState,
    MemoryState, Sampler, SpecConstants,
};
use crate::material::Material;
use crate::physics::baked::sample::MipFilter;
use crate::physics::exact::Query;
use crate::physics::spectrum;

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
        let (terms, upload) = upload_terms(ctx, material)?;
        let terms = Guard::new(ctx, terms);
        let sampler = match material.table {
            Some(_) => {
                let mip = match table_filter(ctx, material) {
                    MipFilter::Linear => vk::SamplerMipmapMode::LINEAR,
                    MipFilter::Nearest => vk::SamplerMipmapMode::NEAREST,
                };
                ctx.create_table_sampler("baked table", mip)?
            }
            None => ctx.create_sampler("taylor terms (nearest)")?,
        };
        let sampler = Guard::new(ctx, sampler);
        let moments = Guard::new(ctx, upload_moments(ctx, material)?);
        let moments_sampler = Guard::new(ctx, ctx.create_filtered_sampler("environment moments (bilinear)", true)?);
        let table = spectrum::gpu_table(&material.sampling);
        let spectrum = ctx.create_buffer_init(
            vk::BufferUsageFlags::STORAGE_BUFFER,
            bytemuck::cast_slice(&table),
            "CIE 1931 × the illuminant",
        );
        let spectrum = Guard::new(ctx, spectrum?);
        let size = std::mem::size_of_val(&material.params) as u64;
        let params =
            ctx.create_buffer(BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER), "diffraction params");
        let mut params = Guard::new(ctx, params?);
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
    pub fn update(&mut self, params: &DiffractionParams) -> Result<()> {
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
        DescriptorWrite::SampledImage(BINDING_MOMENTS, &self.moments, &self.moments_sampler)
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

/// The material's Taylor terms or baked table as a texture array, checked against the device's limits, and what
/// the upload cost.
fn upload_terms(ctx: &Context, material: &Material) -> Result<(Image, Upload)> {
    let (what, desc) = match &material.table {
        Some(table) => {
            if !ctx.filters_linearly(TABLE_FORMAT) {
                return Err(Error::unsupported(
                    &ctx.info.name,
                    format!(
                        "{} cannot filter RGBA32F textures linearly, which the baked approach needs; use --approach \
                         flss",
                        ctx.info.name
                    ),
                ));
            }
            let (w, h) = (table.grid.nu as u32, table.grid.nv as u32);
            let desc = ImageDesc::texture_array(w, h, table.layers() as u32, TABLE_FORMAT)
                .with_mips(table.levels.len() as u32);
            ("baked table", desc)
        }
        None => {
            let (nx, ny) = (material.nx as u32, material.ny as u32);
            ("taylor terms", ImageDesc::texture_array(nx, ny, material.layers, vk::Format::R32G32_SFLOAT))
        }
    };
    check_limits(ctx, &desc, what)?;
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
    let bytes = std::mem::size_of_val(&texels[..]) as u64;
    let upload = Upload { bytes, gpu_ms, wall_ms: start.elapsed().as_secs_f64() * 1e3 };
    Ok((terms.keep(), upload))
}

/// Refuses an image of `desc` (`what`) larger than the device's 2D images or array layers.
pub(crate) fn check_limits(ctx: &Context, desc: &ImageDesc, what: &str) -> Result<()> {
    let limits = &ctx.info.limits;
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
    Ok(())
}

/// The material's moments against the environment, or one black texel where it has none.
fn upload_moments(ctx: &Context, material: &Material) -> Result<Image> {
    let layers = crate::light::prefilter::MOMENT_LAYERS as u32;
    let (side, texels) = match &material.moments {
        Some(m) => (m.grid as u32, m.gpu_texels()),
        None => (1, vec![0.0; layers as usize * 4]),
    };
    let desc = ImageDesc::texture_array(side, side, layers, TABLE_FORMAT);
    let moments = Guard::new(ctx, ctx.create_image(desc, "environment moments")?);
    ctx.upload_image(&moments, bytemuck::cast_slice(&texels), ImageState::SHADER_READ)?;
    Ok(moments.keep())
}

/// The material's uniforms with the light direction `light` (unit, patch frame).
pub(crate) fn light_params(material: &Material, light: DVec3) -> DiffractionParams {
    let mut params = material.params;
    params.light = [light.x as f32, light.y as f32, light.z as f32, 0.0];
    params
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

crate::impl_destroy!(PatchResources);
