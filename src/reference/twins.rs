//! The functions that exist twice, in Rust and in GLSL (ARCHITECTURE.md, "Twins", lists every pair): [`Twin`] names
//! each GLSL function and its Rust twin, and [`evaluate`] runs the GLSL one on the GPU at chosen points through
//! `glsl/twins.comp.glsl`, which compiles the frames' own includes. The tests below set every pair against each
//! other at points that cover its range, so that a change to one side alone fails; on another device,
//! `DIFFRACT_TEST_DEVICE` runs them there.

use ash::vk;

use crate::error::Result;
use crate::gpu::interface::{self as gi, SurfaceUniforms, TwinPush, BINDING_FRAME, BINDING_TWIN_IN, BINDING_TWIN_OUT};
use crate::gpu::shaders;
use crate::gpu::vk::{BufferDesc, ComputePipelineDesc, Context, DescriptorWrite, Guard, MemoryState, SpecConstants};
use crate::light::sampling::Distribution2D;
use crate::material::Material;
use crate::physics::spectrum::Sampling;
use crate::render::diffraction::PatchResources;

/// A GLSL function with a Rust twin, as `twins.comp` evaluates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Twin {
    FresnelReflectance,
    FresnelRatio,
    GainFactor,
    ShadowMask,
    Transmittance,
    PigmentRgb,
    PigmentSkyRgb,
    SkyOverPi,
    SrgbOetf,
    Agx,
    DisplayEncode,
    XyzToLinearSrgb,
    SpectrumAt,
    PanoramaUv,
    MapView,
    MomentGridOfView,
    SkyCoefficients,
    SampleCell,
    R2,
    Tent,
    TableLod,
    TableSegment,
    BakedXyz,
    SpotFactor,
    LampLight,
    LampCoherence,
    WideningVariance,
    WidenSteps,
}

impl Twin {
    pub const ALL: [Twin; 28] = [
        Twin::FresnelReflectance,
        Twin::FresnelRatio,
        Twin::GainFactor,
        Twin::ShadowMask,
        Twin::Transmittance,
        Twin::PigmentRgb,
        Twin::PigmentSkyRgb,
        Twin::SkyOverPi,
        Twin::SrgbOetf,
        Twin::Agx,
        Twin::DisplayEncode,
        Twin::XyzToLinearSrgb,
        Twin::SpectrumAt,
        Twin::PanoramaUv,
        Twin::MapView,
        Twin::MomentGridOfView,
        Twin::SkyCoefficients,
        Twin::SampleCell,
        Twin::R2,
        Twin::Tent,
        Twin::TableLod,
        Twin::TableSegment,
        Twin::BakedXyz,
        Twin::SpotFactor,
        Twin::LampLight,
        Twin::LampCoherence,
        Twin::WideningVariance,
        Twin::WidenSteps,
    ];

    /// The GLSL function (its include under `glsl/include/`) and its Rust twin (under the crate's root).
    pub fn names(self) -> (&'static str, &'static str) {
        match self {
            Twin::FresnelReflectance => ("brdf.glsl: fresnel_reflectance", "physics::optics::fresnel_reflectance"),
            Twin::FresnelRatio => ("brdf.glsl: fresnel_ratio", "physics::optics::fresnel_ratio"),
            Twin::GainFactor => ("brdf.glsl: gain_factor", "physics::optics::gain_factor"),
            Twin::ShadowMask => ("brdf.glsl: shadow_mask", "physics::optics::shadow_mask"),
            Twin::Transmittance => ("pigment.glsl: transmittance", "physics::optics::transmittance"),
            Twin::PigmentRgb => ("pigment.glsl: pigment_rgb", "physics::optics::pigment_rgb"),
            Twin::PigmentSkyRgb => ("pigment.glsl: pigment_sky_rgb", "physics::optics::pigment_sky_rgb"),
            Twin::SkyOverPi => ("pigment.glsl: sky_over_pi", "physics::sh::Irradiance::over_pi"),
            Twin::SrgbOetf => ("display.glsl: srgb_oetf", "physics::spectrum::srgb_oetf"),
            Twin::Agx => ("display.glsl: agx", "display::tone::agx"),
            Twin::DisplayEncode => ("display.glsl: display_encode", "display::tone::Tone::encode"),
            Twin::XyzToLinearSrgb => ("spectrum.glsl: xyz_to_linear_srgb", "physics::colour::xyz_to_linear_srgb"),
            Twin::SpectrumAt => ("spectrum.glsl: spectrum_at", "physics::spectrum::Sampling::weights_at"),
            Twin::PanoramaUv => ("panorama.glsl: panorama_uv", "light::environment::panorama_uv"),
            Twin::MapView => ("map_view.glsl: map_view", "light::sampling::map_view"),
            Twin::MomentGridOfView => ("sky_diffraction.glsl: moment_grid_of_view", "light::prefilter::grid_of_view"),
            Twin::SkyCoefficients => {
                ("sky_diffraction.glsl: sky_coefficients", "light::prefilter::Quadratic::coefficients")
            }
            Twin::SampleCell => ("env_sampling.glsl: sample_cell", "light::sampling::Distribution2D::sample"),
            Twin::R2 => ("env_sampling.glsl: r2", "light::sampling::r2"),
            Twin::Tent => ("env_sampling.glsl: tent", "light::sampling::tent"),
            Twin::TableLod => ("baked.glsl: table_lod", "physics::baked::BakedTable::lod"),
            Twin::TableSegment => ("baked.glsl: table_segment", "physics::baked::Grid::segment_of"),
            Twin::BakedXyz => ("baked.glsl: baked_xyz", "physics::baked::BakedTable::xyz_filtered"),
            Twin::SpotFactor => ("lamps.glsl: spot_factor", "light::lamp::spot_factor"),
            Twin::LampLight => ("lamps.glsl: lamp_light", "light::lamp::Lamp::light_at"),
            Twin::LampCoherence => ("lamps.glsl: lamp_coherence_um", "light::lamp::Lamp::coherence_at"),
            Twin::WideningVariance => ("footprint.glsl: widening_variance", "light::lamp::widening_variance"),
            Twin::WidenSteps => ("footprint.glsl: widen_steps", "light::lamp::widen_steps"),
        }
    }

    /// Its `TWIN_*` id.
    fn id(self) -> u32 {
        match self {
            Twin::FresnelReflectance => gi::TWIN_FRESNEL_REFLECTANCE,
            Twin::FresnelRatio => gi::TWIN_FRESNEL_RATIO,
            Twin::GainFactor => gi::TWIN_GAIN_FACTOR,
            Twin::ShadowMask => gi::TWIN_SHADOW_MASK,
            Twin::Transmittance => gi::TWIN_TRANSMITTANCE,
            Twin::PigmentRgb => gi::TWIN_PIGMENT_RGB,
            Twin::PigmentSkyRgb => gi::TWIN_PIGMENT_SKY_RGB,
            Twin::SkyOverPi => gi::TWIN_SKY_OVER_PI,
            Twin::SrgbOetf => gi::TWIN_SRGB_OETF,
            Twin::Agx => gi::TWIN_AGX,
            Twin::DisplayEncode => gi::TWIN_DISPLAY_ENCODE,
            Twin::XyzToLinearSrgb => gi::TWIN_XYZ_TO_LINEAR_SRGB,
            Twin::SpectrumAt => gi::TWIN_SPECTRUM_AT,
            Twin::PanoramaUv => gi::TWIN_PANORAMA_UV,
            Twin::MapView => gi::TWIN_MAP_VIEW,
            Twin::MomentGridOfView => gi::TWIN_MOMENT_GRID_OF_VIEW,
            Twin::SkyCoefficients => gi::TWIN_SKY_COEFFICIENTS,
            Twin::SampleCell => gi::TWIN_SAMPLE_CELL,
            Twin::R2 => gi::TWIN_R2,
            Twin::Tent => gi::TWIN_TENT,
            Twin::TableLod => gi::TWIN_TABLE_LOD,
            Twin::TableSegment => gi::TWIN_TABLE_SEGMENT,
            Twin::BakedXyz => gi::TWIN_BAKED_XYZ,
            Twin::SpotFactor => gi::TWIN_SPOT_FACTOR,
            Twin::LampLight => gi::TWIN_LAMP_LIGHT,
            Twin::LampCoherence => gi::TWIN_LAMP_COHERENCE,
            Twin::WideningVariance => gi::TWIN_WIDENING_VARIANCE,
            Twin::WidenSteps => gi::TWIN_WIDEN_STEPS,
        }
    }

    /// Whether it reads a material's baked table (the `BAKED` build of `twins.comp`).
    pub fn baked(self) -> bool {
        matches!(self, Twin::TableLod | Twin::TableSegment | Twin::BakedXyz)
    }
}

/// One point's arguments: four vec4s, each function reading its own (`twins.comp`'s `switch`).
pub type Point = [[f32; 4]; 4];

/// What a GLSL function reads besides its arguments.
#[derive(Clone, Copy, Default)]
pub struct Resources<'a> {
    /// The surface pass's uniforms (`frame`: the sky's SH coefficients and quadratic form); zero if None.
    pub frame: Option<&'a SurfaceUniforms>,
    /// The wavelength table `spectrum_at` reads (`physics::spectrum`'s for this sampling); zero if None.
    pub sampling: Option<&'a Sampling>,
    /// The distribution `sample_cell` draws from.
    pub distribution: Option<&'a Distribution2D>,
    /// The baked material the `baked` twins read (required for them).
    pub material: Option<&'a Material>,
}

/// `twin`'s GLSL at `points` (one vec4 each: the function's value, in the order its GLSL returns it).
pub fn evaluate(ctx: &Context, twin: Twin, points: &[Point], resources: Resources<'_>) -> Result<Vec<[f32; 4]>> {
    if points.is_empty() {
        return Ok(Vec::new());
    }
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let input = Guard::new(ctx, ctx.create_buffer_init(storage, bytemuck::cast_slice(points), "twin points")?);
    let output = Guard::new(ctx, ctx.create_buffer(BufferDesc::readback(16 * points.len() as u64), "twin values")?);
    let frame = resources.frame.copied().unwrap_or(bytemuck::Zeroable::zeroed());
    let frame = ctx.create_buffer_init(vk::BufferUsageFlags::UNIFORM_BUFFER, bytemuck::bytes_of(&frame), "twin frame");
    let frame = Guard::new(ctx, frame?);
    let table = match resources.sampling {
        Some(sampling) => crate::physics::spectrum::gpu_table(sampling),
        None => vec![[0.0f32; 4]; gi::TABLE_ROWS],
    };
    let spectrum = Guard::new(ctx, ctx.create_buffer_init(storage, bytemuck::cast_slice(&table), "twin spectrum")?);
    let words = resources.distribution.map_or(vec![0.0f32; 4], Distribution2D::gpu_words);
    let sampling = Guard::new(ctx, ctx.create_buffer_init(storage, bytemuck::cast_slice(&words), "twin sampling")?);
    let material = match (twin.baked(), resources.material) {
        (true, Some(m)) if m.table.is_some() => Some(m),
        (true, _) => return Err(crate::Error::Invalid(format!("the twin {twin:?} reads a baked material's table"))),
        (false, _) => None,
    };
    let patch = Guard::new(ctx, material.map(|m| PatchResources::new(ctx, m)).transpose()?);
    let pipeline = ctx.create_compute_pipeline(&ComputePipelineDesc {
        name: "twins",
        shader: if material.is_some() { &shaders::TWINS_BAKED_COMP } else { &shaders::TWINS_COMP },
        specialization: material.map_or_else(SpecConstants::default, |m| m.spec_constants(false)),
        push_constant_size: std::mem::size_of::<TwinPush>() as u32,
    });
    let pipeline = Guard::new(ctx, pipeline?);
    let mut writes = vec![
        DescriptorWrite::StorageBuffer(BINDING_TWIN_IN, &input),
        DescriptorWrite::StorageBuffer(BINDING_TWIN_OUT, &output),
        DescriptorWrite::UniformBuffer(BINDING_FRAME, &frame),
        DescriptorWrite::StorageBuffer(gi::BINDING_TABLE_SAMPLING, &sampling),
        DescriptorWrite::StorageBuffer(gi::BINDING_ENV_SAMPLING, &sampling),
    ];
    match patch.as_ref() {
        // The material's own table, parameters and wavelength table.
        Some(patch) => writes.extend(patch.writes()),
        None => writes.push(DescriptorWrite::StorageBuffer(gi::BINDING_SPECTRUM, &spectrum)),
    }
    let push = TwinPush { function: twin.id(), count: points.len() as u32 };
    ctx.one_shot("twins", |cmd| {
        ctx.bind(cmd, &pipeline, &writes, bytemuck::bytes_of(&push));
        // SAFETY: recording outside a render pass with the pipeline bound.
        unsafe { ctx.device().cmd_dispatch(cmd, push.count.div_ceil(gi::LOCAL_SIZE_X), 1, 1) };
        ctx.barrier_memory(cmd, MemoryState::COMPUTE_WRITE, MemoryState::HOST_READ);
    })?;
    Ok(bytemuck::pod_collect_to_vec(&ctx.read_buffer(&output)?))
}

#[cfg(test)]
mod tests;
