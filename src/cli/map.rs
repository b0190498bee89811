//! `diffract map`: the BRDF map of a height field for one light, or under an environment, on the GPU.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context as _;
use clap::Args;

use crate::cli::args::{HeightFieldArgs, MaterialArgs};
use crate::cli::parse;
use crate::cli::GpuArgs;
use crate::material::Approach;
use crate::material::{Material, Reach};
use crate::physics::optics;
use crate::physics::spectrum::Sampling;
use crate::render::map;

#[derive(Args, Debug)]
pub struct MapArgs {
    #[command(flatten)]
    pub heightfield: HeightFieldArgs,
    /// Light inclination θ_i in degrees (0 = normal incidence); not with --environment
    #[arg(value_parser = parse::finite, long, value_name = "DEG", required_unless_present = "environment")]
    pub light_theta: Option<f64>,
    /// Light azimuth φ_i in degrees
    #[arg(value_parser = parse::finite, long, value_name = "DEG", default_value_t = 0.0)]
    pub light_phi: f64,
    /// The light's angular radius in degrees (the sun's is 0.267°): its coherence length follows, 65 µm × 0.267°/DEG
    /// (docs/model.md §1.13), where --coherence-um would set it directly
    #[arg(value_parser = parse::finite, long, value_name = "DEG", conflicts_with_all = ["environment", "lamp_radius_m"])]
    pub light_radius_deg: Option<f64>,
    /// A lamp of this radius, metres, at --lamp-distance-m from the patch in the light's direction: its angular
    /// radius atan(r/d) sets the coherence as --light-radius-deg does (the map stays a BRDF, in its relative units)
    #[arg(value_parser = parse::finite, long, value_name = "M", requires = "lamp_distance_m", conflicts_with = "environment")]
    pub lamp_radius_m: Option<f64>,
    /// The lamp's distance from the patch, metres (with --lamp-radius-m)
    #[arg(value_parser = parse::finite, long, value_name = "M", requires = "lamp_radius_m")]
    pub lamp_distance_m: Option<f64>,
    /// Light the patch by an equirectangular HDR map (.exr or .hdr, linear RGB in cd/m², like `diffract gen sky`
    /// writes) instead of one light: its zenith is the patch normal, azimuth 0 the patch's −y and 90° its +x. The
    /// map is then radiance in the map's units (the baked approach)
    #[arg(long, value_name = "FILE.exr|FILE.hdr", conflicts_with = "light_theta")]
    pub environment: Option<PathBuf>,
    /// Turn the environment about the normal, degrees (a texel at azimuth φ lights from φ + rotation)
    #[arg(value_parser = parse::finite, long, value_name = "DEG", default_value_t = 0.0, requires = "environment")]
    pub env_rotation: f64,
    /// Scale the environment's radiance
    #[arg(value_parser = parse::finite, long, value_name = "X", default_value_t = 1.0, requires = "environment")]
    pub env_intensity: f64,
    /// Samples per pixel of the environment's integral (half drawn from the BRDF, half from the environment)
    #[arg(long, value_name = "N", default_value_t = crate::light::sampling::DEFAULT_ENV_SAMPLES, requires = "environment",
          value_parser = clap::value_parser!(u32).range(2..=i64::from(crate::light::sampling::MAX_ENV_SAMPLES)))]
    pub env_samples: u32,
    /// Also integrate the exact BRDF (f64, on the CPU) over the environment at N random pixels and print the mean
    /// ΔE00 of the map against it, with the reference's standard error
    #[arg(long, value_name = "N", requires = "environment", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub env_reference: Option<u32>,
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
    /// measured from the map (its lit pixels' brightest channel, 99.5th percentile, shown at 0.9)
    #[arg(value_parser = parse::exposure, long, value_name = "EV", alias = "exposure-ev")]
    pub exposure: Option<f64>,
    /// How the 8-bit output shows light: clip (the sRGB transfer function, clipped at white: a map is a plot of
    /// the BRDF, proportional up to white) or filmic (AgX: highlights roll off over four stops above white, bright
    /// spectral colours desaturate towards white); the EXR stays linear
    #[arg(long, value_name = "CURVE", value_parser = crate::cli::parse::tone, default_value = "clip")]
    pub tone: crate::display::Tone,
    #[command(flatten)]
    pub material: MaterialArgs,
}

pub fn map(gpu: &GpuArgs, args: &MapArgs) -> anyhow::Result<std::process::ExitCode> {
    crate::io::output::check_png_path(&args.out)?;
    if let Some(exr) = &args.exr {
        crate::io::output::check_exr_path(exr)?;
    }
    let mut outputs = vec![("--out", args.out.clone())];
    outputs.extend(args.exr.iter().map(|e| ("--exr", e.clone())));
    let reads = [
        ("the height field", Some(args.heightfield.heightfield.as_path())),
        ("the environment map", args.environment.as_deref()),
    ];
    crate::cli::args::check_outputs(&outputs, &crate::cli::args::inputs(&args.material.patch, &reads))?;
    if args.material.patch.sky_at.is_some() {
        anyhow::bail!("--sky-at has no effect on `diffract map` (a map's pixels are views of one patch, not a mesh's)");
    }
    if let Some(path) = &args.environment {
        return environment_map(gpu, args, path);
    }
    let theta = args.light_theta.context("--light-theta is needed without --environment")?;
    optics::check_theta("light", theta)?;
    let hf = args.heightfield.load()?;
    let light = optics::direction(theta, args.light_phi);
    let start = Instant::now();
    let mut settings = args.material.patch.apply(crate::material::Settings::default());
    if let Some((radius_deg, flag)) = light_radius_deg(args)? {
        settings.coherence_um =
            crate::cli::args::coherence_of_light(radius_deg, args.material.patch.coherence_um, flag)?;
    }
    let material = Material::prepare(&hf, settings, &Reach::Map { light, size: args.size, filtered: args.footprint })?;
    let prep_ms = start.elapsed().as_secs_f64() * 1e3;
    let ctx = crate::gpu::vk::Context::new(&gpu.context_desc())?;
    let map = map::render_map(&ctx, &material, args.size, light, args.footprint).context("rendering the BRDF map")?;
    write_map(args, &map)?;
    if let Some(line) = material.table_line() {
        errln!("{line}");
    }
    let plan = material.plan.map(|p| format!("N = {} ({} terms), ", p.order, p.order + 1)).unwrap_or_default();
    let shader = map::MapShader::for_device(&ctx).name();
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
    outln!(
        "wrote {} ({size}×{size} {approach}: {plan}{sampling}{window}; precompute {prep_ms:.0} ms{gpu_time} on {device})",
        args.out.display(),
        size = args.size,
        approach = material.settings.approach.name(),
        device = ctx.info.name
    );
    let log = ctx.validation();
    drop(ctx);
    Ok(crate::cli::validation_status(&log))
}

/// Writes the map's PNG (at --exposure, else one measured from it) and EXR; refuses a map with non-finite pixels.
/// Returns the exposure used.
fn write_map(args: &MapArgs, map: &map::MapImage) -> anyhow::Result<f64> {
    let bad = map.non_finite();
    if bad > 0 {
        anyhow::bail!("{bad} pixels of the map are not finite numbers (a bug in diffract; nothing was written)");
    }
    let exposure = match args.exposure {
        Some(ev) => ev,
        None => {
            let (ev, line) = crate::display::measure(&map.rgba, None, "the map", args.tone);
            errln!("{line}");
            ev
        }
    };
    if let Some(line) = crate::display::verdict(&map.rgba, exposure, args.tone) {
        errln!("{line}");
    }
    crate::io::output::write_png_rgba8(&args.out, args.size, args.size, &map.to_rgba8(exposure, args.tone))?;
    if let Some(exr) = &args.exr {
        crate::io::output::write_exr_rgb(exr, args.size, args.size, &map.rgba)?;
    }
    Ok(exposure)
}

/// The light's angular radius, degrees, from --light-radius-deg or a lamp's --lamp-radius-m at --lamp-distance-m,
/// with the flag that set it.
fn light_radius_deg(args: &MapArgs) -> anyhow::Result<Option<(f64, &'static str)>> {
    match (args.lamp_radius_m, args.lamp_distance_m) {
        (Some(r), Some(d)) => {
            if !(r > 0.0 && d > 0.0) {
                anyhow::bail!(
                    "--lamp-radius-m and --lamp-distance-m must be above 0, got {} and {} m",
                    crate::error::number(r),
                    crate::error::number(d)
                );
            }
            Ok(Some((r.atan2(d).to_degrees(), "--lamp-radius-m")))
        }
        _ => Ok(args.light_radius_deg.map(|deg| (deg, "--light-radius-deg"))),
    }
}

/// The map under the environment in `path` (`light::sampling`): a table for every pair of directions, the GPU's
/// estimate, and with --env-reference the exact BRDF's at random pixels.
fn environment_map(gpu: &GpuArgs, args: &MapArgs, path: &std::path::Path) -> anyhow::Result<std::process::ExitCode> {
    use crate::light::sampling::EnvLight;
    let settings = environment_settings(args)?;
    let map = crate::light::environment::EnvironmentMap::load(path)?;
    let env = EnvLight::new(&map, args.env_intensity, args.env_rotation)?;
    // The same search as a scene's: here the sun stays in the map, which the integral samples (its share of the
    // environment's samples goes where the light is).
    match crate::light::sun::find(&map).sun {
        Some(sun) => errln!("note: {}: {}; integrated with the rest of the map", path.display(), sun.describe()),
        None => errln!("note: {}: no sun in the map (no compact cap holds a quarter of its light)", path.display()),
    }
    if env.width < map.width {
        errln!(
            "note: the {}×{} environment lights the map averaged down to {}×{} texels",
            map.width,
            map.height,
            env.width,
            env.height
        );
    }
    let hf = args.heightfield.load()?;
    let start = Instant::now();
    // Texels no wider than the map's pixels, nor than ENV_TABLE_TEXEL: the integral's accuracy depends on them
    // (coarse texels spread each lobe over angles where the gain and cos θ_i differ).
    let footprint = (2.0 / f64::from(args.size)).min(crate::light::sampling::ENV_TABLE_FOOTPRINT);
    let material = Material::prepare(&hf, settings, &Reach::Hemisphere { footprint })?;
    let prep_ms = start.elapsed().as_secs_f64() * 1e3;
    let ctx = crate::gpu::vk::Context::new(&gpu.context_desc())?;
    let n_brdf = args.env_samples / 2;
    let spec = crate::render::env_map::EnvMapSpec {
        material: &material,
        env: &env,
        size: args.size,
        n_brdf,
        n_env: args.env_samples - n_brdf,
        seed: 1,
    };
    let image =
        crate::render::env_map::render_env_map(&ctx, &spec).context("integrating the map over the environment")?;
    let exposure = write_map(args, &image)?;
    if let Some(line) = material.table_line() {
        errln!("{line}");
    }
    let gpu_time = image.gpu_ms.map(|ms| format!(", GPU {ms:.1} ms")).unwrap_or_default();
    outln!(
        "wrote {} ({size}×{size} baked under {}: {} samples per pixel; precompute {prep_ms:.0} ms{gpu_time} on {device})",
        args.out.display(),
        path.display(),
        args.env_samples,
        size = args.size,
        device = ctx.info.name
    );
    if let Some(count) = args.env_reference {
        environment_reference(args, (&hf, &material, &env), (&image, exposure), count)?;
    }
    let log = ctx.validation();
    drop(ctx);
    Ok(crate::cli::validation_status(&log))
}

/// The settings of a map under an environment: baked unless another approach is asked for (and refused), the
/// light in physical units.
fn environment_settings(args: &MapArgs) -> anyhow::Result<crate::material::Settings> {
    let baked = crate::material::Settings { approach: Approach::Baked, ..crate::material::Settings::default() };
    let mut settings = args.material.patch.apply(baked);
    if settings.approach != Approach::Baked {
        anyhow::bail!(
            "--environment needs --approach baked: {} evaluates one pair of directions per pixel, and an environment \
             needs thousands (the exact reference is --env-reference)",
            settings.approach.name()
        );
    }
    settings.illuminant = settings.illuminant.physical();
    Ok(settings)
}

/// --env-reference: the exact BRDF integrated over the environment at `count` random pixels of `image` (drawn at
/// `exposure`), and how far the GPU's estimate lies from it.
fn environment_reference(
    args: &MapArgs,
    (hf, material, env): (&crate::physics::heightfield::HeightField, &Material, &crate::light::sampling::EnvLight),
    (image, exposure): (&map::MapImage, f64),
    count: u32,
) -> anyhow::Result<()> {
    let table = material.table.as_ref().context("the baked material has a table")?;
    let proposal = crate::light::sampling::TableProposal::new(table)?;
    let pixels = crate::reference::exact_env::random_map_pixels(args.size, count as usize, 0x5eed);
    let start = Instant::now();
    let samples = crate::light::sampling::REFERENCE_SAMPLES;
    let reference = crate::reference::exact_env::reference_map_pixels(
        hf,
        &material.settings,
        &proposal,
        env,
        args.size,
        &pixels,
        samples,
    )?;
    let check = crate::reference::exact_env::compare(image, &pixels, &reference, exposure);
    outln!(
        "exact reference at {} random pixels ({samples} samples each, {} nm, {:.1} s): mean ΔE00 {:.3} (largest \
         {:.2}) at {exposure:+.2} EV; the reference's own standard error {:.2} % of luminance (median)",
        pixels.len(),
        crate::reference::exact_env::REFERENCE_STEP_NM,
        start.elapsed().as_secs_f64(),
        check.mean,
        check.worst,
        100.0 * check.median_relative_error
    );
    Ok(())
}
