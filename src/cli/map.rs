//! `diffract map`: the BRDF map of a height field for one light, on the GPU.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context as _;
use clap::Args;

use super::args::{HeightFieldArgs, LightArgs, MaterialArgs};
use super::parse;
use super::GpuArgs;
use crate::physics::optics;
use crate::physics::spectrum::Sampling;
use crate::render::diffraction;
use crate::shading::{Approach, Material, Reach};

#[derive(Args, Debug)]
pub struct MapArgs {
    #[command(flatten)]
    pub heightfield: HeightFieldArgs,
    #[command(flatten)]
    pub light: LightArgs,
    /// Output PNG (display-referred 8-bit sRGB after --exposure)
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
    /// Also write the linear scene-referred RGB (sRGB primaries, before exposure) as 32-bit float EXR
    #[arg(long, value_name = "FILE.exr")]
    pub exr: Option<PathBuf>,
    /// Baked: average each pixel over its footprint (else the table's point value at the pixel's centre)
    #[arg(long)]
    pub footprint: bool,
    /// Map size in pixels (odd sizes put a pixel exactly at normal view)
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub size: u32,
    /// Exposure in stops applied before the sRGB transfer function (PNG only; the EXR stays linear); default:
    /// measured from the map (its lit pixels' 99.5th percentile of luminance shown at 0.9)
    #[arg(value_parser = parse::finite, long, value_name = "EV", alias = "exposure-ev")]
    pub exposure: Option<f64>,
    #[command(flatten)]
    pub material: MaterialArgs,
}

pub fn map(gpu: &GpuArgs, args: &MapArgs) -> anyhow::Result<std::process::ExitCode> {
    crate::output::check_png_path(&args.out)?;
    if let Some(exr) = &args.exr {
        crate::output::check_exr_path(exr)?;
    }
    optics::check_theta("light", args.light.light_theta)?;
    let hf = args.heightfield.load()?;
    let light = optics::direction(args.light.light_theta, args.light.light_phi);
    let start = Instant::now();
    let material = Material::prepare(
        &hf,
        args.material.patch.apply(crate::shading::Settings::default()),
        &Reach::Map { light, size: args.size, filtered: args.footprint },
    )?;
    let prep_ms = start.elapsed().as_secs_f64() * 1e3;
    let ctx = crate::vk::Context::new(&gpu.context_desc())?;
    let map =
        diffraction::render_map(&ctx, &material, args.size, light, args.footprint).context("rendering the BRDF map")?;
    let bad = map.non_finite();
    if bad > 0 {
        anyhow::bail!("{bad} pixels of the map are not finite numbers (a bug in diffract; nothing was written)");
    }
    let exposure = match args.exposure {
        Some(ev) => ev,
        None => {
            let (ev, line) = crate::exposure::measure(&map.rgba, "the map");
            eprintln!("{line}");
            ev
        }
    };
    if let Some(line) = crate::exposure::verdict(&map.rgba, exposure) {
        eprintln!("{line}");
    }
    crate::output::write_png_rgba8(&args.out, args.size, args.size, &map.to_rgba8(exposure))?;
    if let Some(exr) = &args.exr {
        crate::output::write_exr_rgb(exr, args.size, args.size, &map.rgba)?;
    }
    if let Some(line) = material.table_line() {
        eprintln!("{line}");
    }
    let plan = material.plan.map(|p| format!("N = {} ({} terms), ", p.order, p.order + 1)).unwrap_or_default();
    let shader = diffraction::MapShader::for_device(&ctx).name();
    let gpu_time = map.gpu_ms.map(|ms| format!(", GPU {ms:.1} ms ({shader} shader)")).unwrap_or_default();
    let taps = 2 * material.window.radius_x + 1;
    let sampling = match material.settings.approach {
        Approach::Nmm => format!("one λ per DFT bin crossed ({} λ near specular)", material.sampling.count),
        Approach::Gem => format!("orders of the {:.3} µm spacing", material.params.gem[2]),
        // The table's own integration (the shader samples no λ), over the full window (no taps either).
        Approach::Baked => {
            let step = crate::physics::baked::TABLE_LAMBDA_STEP_NM;
            format!("a table of {} λ at {step} nm, the full window", Sampling::visible(step).count)
        }
        _ => format!("{} λ", material.sampling.count),
    };
    let window =
        if material.settings.approach == Approach::Baked { String::new() } else { format!(", {taps}×{taps} taps") };
    println!(
        "wrote {} ({size}×{size} {approach}: {plan}{sampling}{window}; precompute {prep_ms:.0} ms{gpu_time} on {device})",
        args.out.display(),
        size = args.size,
        approach = material.settings.approach.name(),
        device = ctx.info.name
    );
    let log = ctx.validation();
    drop(ctx);
    Ok(super::validation_status(&log))
}
