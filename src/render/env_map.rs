//! The BRDF map under an environment on the GPU (`glsl/map_env.comp.glsl`): the baked table integrated against
//! the environment by multiple importance sampling ([`crate::light::sampling`]), one invocation per pixel, band by band.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::interface::{
    EnvMapPush, BINDING_ENV_RADIANCE, BINDING_ENV_SAMPLING, BINDING_MAP_IMAGE, BINDING_TABLE_SAMPLING,
    SPEC_MAP_LOCAL_SIZE,
};
use crate::gpu::shaders;
use crate::gpu::vk::{ComputePipelineDesc, Context, DescriptorWrite, Guard, ImageState};
use crate::io::progress::Progress;
use crate::light::sampling::{env_gain, floor_samples, EnvLight, TableProposal};
use crate::material::Material;
use crate::render::diffraction::PatchResources;
use crate::render::map::{map_target, map_workgroup, MapImage};

/// Rows per submission: at most this many pixels × samples per dispatch (no driver watchdog, progress on long
/// maps).
const BAND_SAMPLES: u64 = 1 << 24;
/// Loop iterations one invocation may run on llvmpipe, which ends an invocation's loops (all of them together)
/// after 65535 iterations, its guard against endless loops: a dispatch adds a chunk of each strategy's samples
/// that stays well below it ([`chunk_samples`]).
const LLVMPIPE_LOOP_LIMIT: u32 = 65535;

/// Samples of each strategy one dispatch adds: the three strategies' loops, each sample's Chebyshev and layer
/// loops (`TERMS` and `TABLE_LAYERS` iterations, where the compiler keeps them as loops), with a factor 2 to spare.
fn chunk_samples(terms: usize) -> u32 {
    let per_sample = 1 + terms as u32 + (3 * terms as u32).div_ceil(4) + 4;
    (LLVMPIPE_LOOP_LIMIT / (2 * 3 * per_sample)).clamp(16, 4096)
}

/// What an environment-lit map shows and how many samples each pixel takes.
#[derive(Clone, Copy)]
pub struct EnvMapSpec<'a> {
    pub material: &'a Material,
    pub env: &'a EnvLight,
    /// Pixels on a side.
    pub size: u32,
    /// Samples per pixel from the BRDF's strategy and from the environment's.
    pub n_brdf: u32,
    pub n_env: u32,
    pub seed: u32,
}

/// Renders the map `spec` asks for: linear sRGB radiance in the environment's units (rows top first).
pub fn render_env_map(ctx: &Context, spec: &EnvMapSpec<'_>) -> Result<MapImage> {
    let material = spec.material;
    let table = material.table.as_ref().ok_or_else(|| {
        Error::setting(
            "approach",
            format!("{} cannot integrate over an environment; use --approach baked", material.settings.approach.name()),
        )
    })?;
    let proposal = TableProposal::new(table)?;
    let gain = env_gain(&material.sampling, material.settings.coherence_um)?;
    let patch = Guard::new(ctx, PatchResources::new(ctx, material)?);
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let buffer =
        |bytes: &[u8], name: &str| -> Result<_> { Ok(Guard::new(ctx, ctx.create_buffer_init(storage, bytes, name)?)) };
    let table_sampling = buffer(bytemuck::cast_slice(&proposal.distribution.gpu_words()), "baked table's CDF")?;
    let env_sampling = buffer(bytemuck::cast_slice(&spec.env.distribution.gpu_words()), "environment's CDF")?;
    let env_radiance = buffer(bytemuck::cast_slice(&spec.env.radiance), "environment's radiance")?;
    let group = map_workgroup(ctx);
    let pipeline = Guard::new(
        ctx,
        ctx.create_compute_pipeline(&ComputePipelineDesc {
            name: "brdf map under an environment",
            shader: &shaders::MAP_ENV_COMP,
            specialization: material.spec_constants(false).u32(SPEC_MAP_LOCAL_SIZE, group),
            push_constant_size: std::mem::size_of::<EnvMapPush>() as u32,
        })?,
    );
    let size = spec.size;
    let target = Guard::new(ctx, map_target(ctx, size, size)?);
    let chunk = chunk_samples(table.terms);
    let most = (spec.n_brdf - floor_samples(spec.n_brdf)).max(spec.n_env).max(1);
    let chunks = most.div_ceil(chunk);
    let band_rows = (BAND_SAMPLES / (u64::from(3 * chunk) * u64::from(size))).clamp(1, u64::from(size)) as u32;
    let bands = size.div_ceil(band_rows);
    let steps = (bands * chunks) as usize;
    let bar = Progress::new_if(steps > 1, format!("integrating map {size}² over the environment"), steps);
    bar.detail(format!("{} + {} samples per pixel, {chunk} per dispatch", spec.n_brdf, spec.n_env));
    let mut gpu_ms = Some(0.0);
    let side = size as f32;
    for step in 0..bands * chunks {
        let (band, part) = (step / chunks, step % chunks);
        let y0 = band * band_rows;
        let push = EnvMapPush {
            size: [side, side],
            offset: [0.0, 0.0],
            origin: [0.0, y0 as f32],
            nu: proposal.nu as u32,
            nv: proposal.nv as u32,
            env_width: spec.env.width,
            env_height: spec.env.height,
            rotation: spec.env.rotation as f32,
            n_brdf: spec.n_brdf,
            n_env: spec.n_env,
            gain: gain as f32,
            n_floor: floor_samples(spec.n_brdf),
            seed: spec.seed,
            first: part * chunk,
            chunk,
        };
        let mut writes: Vec<DescriptorWrite<'_>> = patch.writes().into();
        writes.push(DescriptorWrite::StorageImage(BINDING_MAP_IMAGE, &target.color));
        writes.push(DescriptorWrite::StorageBuffer(BINDING_TABLE_SAMPLING, &table_sampling));
        writes.push(DescriptorWrite::StorageBuffer(BINDING_ENV_SAMPLING, &env_sampling));
        writes.push(DescriptorWrite::StorageBuffer(BINDING_ENV_RADIANCE, &env_radiance));
        let rows = band_rows.min(size - y0);
        let band_ms = ctx.one_shot_timed("brdf map under an environment", |cmd| {
            let from = if step == 0 { ImageState::UNDEFINED } else { ImageState::STORAGE };
            ctx.barrier_image(cmd, &target.color, from, ImageState::STORAGE);
            ctx.bind(cmd, &pipeline, &writes, bytemuck::bytes_of(&push));
            // SAFETY: recording outside a render pass with the pipeline bound.
            unsafe { ctx.device().cmd_dispatch(cmd, size.div_ceil(group), rows.div_ceil(group), 1) };
        })?;
        gpu_ms = gpu_ms.zip(band_ms).map(|(total, ms)| total + ms);
        bar.step();
    }
    bar.finish();
    let bytes = ctx.read_image(&target.color, ImageState::STORAGE)?;
    Ok(MapImage { size, rgba: bytemuck::pod_collect_to_vec(&bytes), gpu_ms })
}
