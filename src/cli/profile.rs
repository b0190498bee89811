//! `diffract profile`: GPU timings, fetch counts and the error against an exact reference for a list of
//! settings (see [`crate::profile`]).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Context as _};
use clap::Args;
use glam::DVec3;

use super::args::{AccuracyArgs, HeightFieldArgs};
use super::{parse, GpuArgs};
use crate::physics::{optics, spectrum};
use crate::profile::exact_image::{self, PixelQuery, ReferenceImage, ReferenceJob, ReferenceMaterial};
use crate::profile::{self as prof, Config, Row, Sweep};
use crate::render::capture::{material_inputs, prepare_materials, scene_objects, scene_reaches, Overrides};
use crate::render::gbuffer::{GBuffer, Seen};
use crate::render::profile::{
    fetch_probe, Counts, FrameSample, MapWorkload, ProbeResult, SceneView, SceneWorkload, Workload,
};
use crate::scene::Scene;
use crate::shading::{Approach, Material, Reach, Settings};
use crate::stats::Spread;
use crate::vk::Context;

#[derive(Args, Debug)]
pub struct ProfileArgs {
    /// Scene file (TOML) to profile; default: a BRDF map of --heightfield, else the built-in Elaphe snake
    #[arg(value_name = "SCENE", conflicts_with = "heightfield")]
    pub scene: Option<PathBuf>,
    /// Profile the BRDF map of this height field (see `diffract map`) instead of a scene
    #[arg(long, value_name = "FILE")]
    pub heightfield: Option<PathBuf>,
    /// PNG only: pixel size in µm
    #[arg(value_parser = parse::finite, long, value_name = "P", requires = "heightfield")]
    pub pixel_size_um: Option<f64>,
    /// PNG only: height in µm of the brightest grey value
    #[arg(value_parser = parse::finite, long, value_name = "H", requires = "heightfield")]
    pub height_um: Option<f64>,
    /// Repeat the patch NX times along x and NY along y
    #[arg(long, value_name = "NX[,NY]", value_parser = super::parse::tile, requires = "heightfield")]
    pub tile: Option<(usize, usize)>,
    /// BRDF map: light inclination θ_i in degrees
    #[arg(value_parser = parse::finite, long, value_name = "DEG", default_value_t = 0.0)]
    pub light_theta: f64,
    /// BRDF map: light azimuth φ_i in degrees
    #[arg(value_parser = parse::finite, long, value_name = "DEG", default_value_t = 0.0)]
    pub light_phi: f64,
    /// Image width in pixels (a BRDF map is square: its side)
    #[arg(long, default_value_t = 128, value_parser = clap::value_parser!(u32).range(1..=prof::MAX_SIZE as i64))]
    pub width: u32,
    /// Image height in pixels (default: the width)
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=prof::MAX_SIZE as i64))]
    pub height: Option<u32>,
    /// Timed frames per configuration (median, p10 and p90 over them)
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub frames: u32,
    /// Untimed frames first, per configuration
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(0..=1000))]
    pub warmup: u32,
    /// Vary settings: KEY=V1,V2,... items (keys: approach, order (or terms), lambda_step_nm, window_radius, size); one
    /// --sweep runs the cross product of its items, several --sweep flags run one list after the other
    #[arg(long, value_name = "KEY=V1,V2,...", num_args = 1.., action = clap::ArgAction::Append)]
    pub sweep: Vec<String>,
    /// The `--sweep` flags' items, one list per flag (filled from clap's occurrences by `cli::main`).
    #[arg(skip)]
    pub sweep_groups: Vec<Vec<String>>,
    /// Write the results as CSV (device, driver and resolution as `#` lines before the header)
    #[arg(long, value_name = "FILE.csv")]
    pub csv: Option<PathBuf>,
    /// Draw time against error (one point per configuration) as PNG
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
    /// TrueType font for the plot's text (default: DejaVu Sans or Liberation Sans from the system)
    #[arg(long, value_name = "FILE.ttf")]
    pub plot_font: Option<PathBuf>,
    /// Also measure the device's RG32F texel-fetch throughput and each configuration's share of it
    #[arg(long)]
    pub roofline: bool,
    /// Base shading approach (a sweep may vary it)
    #[arg(long, value_enum, default_value_t = Approach::Flss)]
    pub approach: Approach,
    #[command(flatten)]
    pub accuracy: AccuracyArgs,
    /// Base wavelength step in nm
    #[arg(value_parser = parse::finite, long, value_name = "NM", default_value_t = 5.0)]
    pub lambda_step: f64,
    /// Exposure in stops at which ΔE is measured (the image as displayed; default: the scene's, maps 0)
    #[arg(value_parser = parse::finite, long, value_name = "EV")]
    pub exposure: Option<f64>,
    /// Profile even where f32 sums cannot reach --tolerance
    #[arg(long)]
    pub accept_f32_error: bool,
    /// Folder of cached reference images (default: $XDG_CACHE_HOME/diffract or ~/.cache/diffract)
    #[arg(long, value_name = "DIR", conflicts_with = "no_reference_cache")]
    pub reference_cache: Option<PathBuf>,
    /// Recompute the reference and do not cache it
    #[arg(long)]
    pub no_reference_cache: bool,
    /// Evaluate the exact reference at S×S positions inside each pixel and average them (the pixel's area, so
    /// footprint filtering and point-sampling aliasing are both measured); baked maps then filter over each
    /// pixel's footprint too
    /// (default: 1 for maps; for scenes the frames' own coverage, 2×2 under 4× anti-aliasing)
    #[arg(long, value_name = "S", value_parser = clap::value_parser!(u32).range(1..=8))]
    pub reference_samples: Option<u32>,
    /// Samples per pixel of a scene's timed frames (multisample anti-aliasing, as `render` and `view` draw
    /// them; default: the scene's, else 4). Maps have one.
    #[arg(long, value_name = "N", value_parser = parse::samples)]
    pub samples: Option<u32>,
    /// Time only: no exact reference and no error columns (an exact 800² snake costs CPU-hours)
    #[arg(long, conflicts_with_all = ["plot", "reference_samples"])]
    pub no_reference: bool,
}

/// What is profiled.
enum Subject {
    Map { heightfield: crate::physics::HeightField, light: DVec3, coherence_um: f64 },
    Scene { scene: Box<Scene>, name: String },
}

impl Subject {
    fn describe(&self, args: &ProfileArgs) -> String {
        match self {
            Subject::Map { heightfield: hf, coherence_um, .. } => {
                let (lx, ly) = hf.size_um();
                format!(
                    "BRDF map of {} ({}×{} px, {lx:.1}×{ly:.1} µm), light θ_i = {}°, φ_i = {}°, coherence {coherence_um} µm",
                    args.heightfield.as_ref().map_or(String::new(), |p| p.display().to_string()),
                    hf.nx,
                    hf.ny,
                    args.light_theta,
                    args.light_phi
                )
            }
            Subject::Scene { scene, name } => format!(
                "scene {name} ({} objects, {} materials; each material's approach, Taylor order, Δλ and window radius set \
                 by the configuration)",
                scene.objects.len(),
                scene.materials.len()
            ),
        }
    }

    /// The image of `config`: a map is square; a scene's height follows the width at the command line's aspect.
    fn image_size(&self, config: &Config, args: &ProfileArgs) -> (u32, u32) {
        match self {
            Subject::Map { .. } => (config.size, config.size),
            Subject::Scene { scene, .. } => {
                let aspect = match args.height {
                    Some(h) => f64::from(h) / f64::from(args.width),
                    None => f64::from(scene.render.height) / f64::from(scene.render.width),
                };
                (config.size, ((f64::from(config.size) * aspect).round() as u32).clamp(1, prof::MAX_SIZE))
            }
        }
    }

    /// Samples per pixel of the timed frames.
    fn frame_samples(&self, args: &ProfileArgs) -> anyhow::Result<u32> {
        match self {
            Subject::Map { .. } if args.samples.is_some_and(|n| n > 1) => {
                bail!("--samples is for scenes: a BRDF map's pixels are directions (--reference-samples averages them)")
            }
            Subject::Map { .. } => Ok(1),
            Subject::Scene { scene, .. } => Ok(args.samples.unwrap_or(scene.render.samples)),
        }
    }

    /// Positions per pixel axis of the exact reference: as asked, else as many as the frames' multisampling
    /// covers (its sample count's square root, rounded up), so that both average over the same pixel area.
    fn reference_samples(&self, args: &ProfileArgs, frame_samples: u32) -> u32 {
        args.reference_samples.unwrap_or_else(|| (f64::from(frame_samples).sqrt().ceil() as u32).max(1))
    }

    fn exposure(&self) -> f64 {
        match self {
            Subject::Map { .. } => 0.0,
            Subject::Scene { scene, .. } => scene.render.exposure_ev,
        }
    }
}

pub fn profile(gpu: &GpuArgs, args: &ProfileArgs) -> anyhow::Result<std::process::ExitCode> {
    if let Some(path) = &args.csv {
        crate::output::check_path(path, "csv")?;
    }
    if let Some(p) = &args.plot {
        crate::output::check_png_path(p)?;
        prof::plot::register_font(args.plot_font.as_deref())?;
    }
    let sweeps: Vec<Sweep> = args.sweep_groups.iter().map(|items| Sweep::parse(items)).collect::<crate::Result<_>>()?;
    let base = Config {
        approach: args.approach,
        order: args.accuracy.order,
        lambda_step_nm: args.lambda_step,
        window_radius: args.accuracy.window_radius,
        size: args.width,
    };
    let configs = prof::configurations(base, &sweeps)?;
    let subject = load_subject(args)?;
    let frame_samples = subject.frame_samples(args)?;
    let reference_samples = subject.reference_samples(args, frame_samples);
    let exposure = args.exposure.unwrap_or(subject.exposure());
    if !exposure.is_finite() {
        bail!("--exposure must be a finite number of stops");
    }
    let cache = if args.no_reference_cache {
        None
    } else {
        args.reference_cache.clone().or_else(exact_image::default_cache_dir)
    };

    let ctx = Context::new(&gpu.context_desc())?;
    let samples = ctx.sample_count(frame_samples, crate::render::LINEAR_FORMAT)?;
    let probe = if args.roofline {
        eprintln!("roofline: measuring RG32F texel-fetch throughput …");
        let p = fetch_probe(&ctx, args.frames.max(3) as usize).context("the fetch probe")?;
        if p.is_none() {
            eprintln!("roofline: the device has no timestamps; no throughput figures");
        }
        p
    } else {
        None
    };

    let mut references: Vec<((u32, u32), ReferenceImage)> = Vec::new();
    let mut rows = Vec::with_capacity(configs.len());
    let show = std::io::stderr().is_terminal();
    for (i, config) in configs.iter().enumerate() {
        let size = subject.image_size(config, args);
        let progress = |what: &str| {
            if show {
                eprint!("\r[{}/{}] {}: {what}{:20}", i + 1, configs.len(), config.label(), "");
            }
        };
        progress("precomputing");
        let start = Instant::now();
        let materials =
            prepare(&ctx, &subject, config, args, size).with_context(|| format!("configuration {}", config.label()))?;
        let precompute_ms = start.elapsed().as_secs_f64() * 1e3;
        for line in materials.iter().filter_map(Material::table_line) {
            if show {
                eprint!("\r{:100}\r", "");
            }
            eprintln!("[{}/{}] {line}", i + 1, configs.len());
        }
        if !args.no_reference && !references.iter().any(|(s, _)| *s == size) {
            let start = Instant::now();
            let image = reference_for(&ctx, &subject, size, reference_samples, cache.as_deref())?;
            eprintln!(
                "reference {}×{} ({:.1} s): {}",
                size.0,
                size.1,
                start.elapsed().as_secs_f64(),
                image.description
            );
            references.push((size, image));
        }
        let reference = references.iter().find(|(s, _)| *s == size).map(|r| &r.1);
        let measured = Measured {
            materials: &materials,
            precompute_ms,
            reference,
            probe: probe.as_ref(),
            exposure,
            samples,
            reference_samples,
        };
        let row = profile_one(&ctx, &subject, args, config, size, &measured, &progress)
            .with_context(|| format!("configuration {}", config.label()))?;
        if show {
            eprint!("\r{:100}\r", "");
        }
        eprintln!(
            "[{}/{}] {}: GPU {} ms{}",
            i + 1,
            configs.len(),
            config.label(),
            row.gpu_ms.map_or("n/a".into(), |s| prof::ms(s.median)),
            row.error.map(|e| format!(", ΔE00 mean {:.3}", e.mean_de)).unwrap_or_default()
        );
        rows.push(row);
    }

    let mut comments = vec![
        format!("device: {}", ctx.info.name),
        format!("driver: {}", ctx.info.driver),
        format!("vulkan: {}", ctx.info.api_version_string()),
        format!("resolution: {}", resolutions(&rows)),
        format!("workload: {}", subject.describe(args)),
        format!("frames: {} timed after {} warm-up", args.frames, args.warmup),
        format!("delta_e: CIEDE2000 at exposure {exposure} EV against D65 white Y = 1, pixels showing the surface"),
    ];
    for (size, image) in &references {
        comments.push(format!("reference {}x{}: {}", size.0, size.1, image.description));
    }
    if let Some(p) = &probe {
        comments.push(roofline_line(p));
    }
    println!("{}", comments.iter().map(|c| format!("- {c}")).collect::<Vec<_>>().join("\n"));
    println!();
    print!("{}", prof::markdown(&rows));
    if let Some(path) = &args.csv {
        let mut all = comments.clone();
        all.push(format!("command: diffract {}", std::env::args().skip(1).collect::<Vec<_>>().join(" ")));
        crate::output::write_file(path, prof::csv(&all, &rows).as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        let title = format!("{} — {}", short_workload(&subject, args), ctx.info.name);
        prof::plot::plot(path, &title, &rows, args.plot_font.as_deref())?;
        eprintln!("wrote {}", path.display());
    }
    let log = ctx.validation();
    drop(ctx);
    Ok(super::validation_status(&log))
}

fn load_subject(args: &ProfileArgs) -> anyhow::Result<Subject> {
    match &args.heightfield {
        Some(path) => {
            let hf_args = HeightFieldArgs {
                heightfield: path.clone(),
                pixel_size_um: args.pixel_size_um,
                height_um: args.height_um,
                tile: args.tile,
            };
            optics::check_theta("light", args.light_theta)?;
            if args.height.is_some_and(|h| h != args.width) {
                bail!("a BRDF map is square: give --width alone (or the same --height)");
            }
            Ok(Subject::Map {
                heightfield: hf_args.load()?,
                light: optics::direction(args.light_theta, args.light_phi),
                coherence_um: args.accuracy.coherence_um,
            })
        }
        None => {
            let scene = match &args.scene {
                Some(path) => Scene::load(path)?,
                None => Scene::default_scene()?,
            };
            let name =
                args.scene.as_ref().map_or(crate::scene::DEFAULT_SCENE_NAME.to_string(), |p| p.display().to_string());
            Ok(Subject::Scene { scene: Box::new(scene), name })
        }
    }
}

/// The materials `config` asks for (the Taylor terms and everything else the GPU needs).
/// A scene's materials are sized (baked tables) for the views its frame at `size` shows.
fn prepare(
    ctx: &Context,
    subject: &Subject,
    config: &Config,
    args: &ProfileArgs,
    size: (u32, u32),
) -> crate::Result<Vec<Material>> {
    match subject {
        Subject::Map { heightfield, light, .. } => {
            let reach = Reach::Map { light: *light, size: config.size };
            Ok(vec![Material::prepare(heightfield, settings_of(config, args), &reach)?])
        }
        Subject::Scene { scene, .. } => {
            let reaches = scene_reaches(ctx, scene, &[(scene.camera, scene.light_dir)], size.0, size.1)?;
            prepare_materials(scene, &overrides_of(config, args), &reaches)
        }
    }
}

/// The exact reference of `subject` at `size`. With `samples` > 1 it is evaluated at `samples`² positions per
/// pixel (an image that many times larger) and averaged.
fn reference_for(
    ctx: &Context,
    subject: &Subject,
    size: (u32, u32),
    samples: u32,
    cache: Option<&std::path::Path>,
) -> anyhow::Result<ReferenceImage> {
    let fine = (size.0 * samples, size.1 * samples);
    let image = match subject {
        Subject::Map { heightfield, light, coherence_um } => {
            let job = ReferenceJob {
                materials: vec![ReferenceMaterial { heightfield, coherence_um: *coherence_um }],
                width: fine.0,
                height: fine.1,
                pixels: ReferenceJob::map_pixels(fine.0, *light),
            };
            job.compute(cache)?
        }
        Subject::Scene { scene, .. } => {
            // The directions each pixel sees come from the GPU's rasteriser (the same triangles, the same
            // fragments, at `samples` times the resolution); everything after them is evaluated on the CPU.
            let gbuffer = GBuffer::draw(ctx, scene, &scene.camera, scene.light_dir, fine.0, fine.1)?;
            let pixels = gbuffer
                .pixels
                .iter()
                .map(|seen| {
                    let Seen { omega_i, omega_r, material, albedo, normal_up, .. } = (*seen)?;
                    let ambient = f64::from(scene.ambient);
                    let extra_rgb = optics::pigment_rgb(omega_i, omega_r, normal_up, albedo, ambient);
                    Some(PixelQuery { omega_i, omega_r, material, extra_xyz: spectrum::linear_srgb_to_xyz(extra_rgb) })
                })
                .collect();
            let job = ReferenceJob {
                materials: scene
                    .materials
                    .iter()
                    .map(|m| ReferenceMaterial { heightfield: &m.heightfield, coherence_um: m.settings.coherence_um })
                    .collect(),
                width: fine.0,
                height: fine.1,
                pixels,
            };
            job.compute(cache)?
        }
    };
    Ok(image.downsample(samples))
}

fn overrides_of(config: &Config, args: &ProfileArgs) -> Overrides {
    Overrides {
        approach: Some(config.approach),
        order: config.order,
        lambda_step_nm: Some(config.lambda_step_nm),
        window_radius: config.window_radius,
        accept_f32_error: args.accept_f32_error,
    }
}

fn scene_workload<'a>(
    ctx: &Context,
    scene: &'a Scene,
    materials: &'a [Material],
    size: (u32, u32),
    samples: ash::vk::SampleCountFlags,
) -> crate::Result<SceneWorkload<'a>> {
    let [r, g, b] = scene.render.background;
    let view = SceneView {
        camera: scene.camera,
        light_dir: scene.light_dir,
        ambient: scene.ambient,
        models: scene.objects.iter().map(|o| o.model).collect(),
        background: [r, g, b, 1.0],
    };
    SceneWorkload::new(ctx, material_inputs(scene, materials), scene_objects(scene), view, size, samples)
}

fn settings_of(config: &Config, args: &ProfileArgs) -> Settings {
    Settings {
        approach: config.approach,
        order: config.order,
        tolerance: args.accuracy.tolerance,
        lambda_step_nm: config.lambda_step_nm,
        window_radius: config.window_radius,
        coherence_um: args.accuracy.coherence_um,
        exposure_ev: 0.0,
        accept_f32_error: args.accept_f32_error,
        table_tolerance: crate::physics::baked::DEFAULT_TABLE_TOLERANCE,
    }
}

/// What one configuration is measured with and against.
struct Measured<'a> {
    materials: &'a [Material],
    precompute_ms: f64,
    reference: Option<&'a ReferenceImage>,
    probe: Option<&'a ProbeResult>,
    exposure: f64,
    /// Samples per pixel of the timed frames, and positions per pixel axis of the reference.
    samples: ash::vk::SampleCountFlags,
    reference_samples: u32,
}

fn profile_one(
    ctx: &Context,
    subject: &Subject,
    args: &ProfileArgs,
    config: &Config,
    size: (u32, u32),
    with: &Measured<'_>,
    progress: &dyn Fn(&str),
) -> anyhow::Result<Row> {
    let Measured { materials, precompute_ms, reference, probe, exposure, samples, reference_samples } = *with;
    let mut workload: Box<dyn Workload + '_> = match subject {
        Subject::Map { light, .. } => {
            // Against an area-sampled reference a baked map averages over its pixels too.
            let footprint = reference_samples > 1;
            Box::new(MapWorkload::new(ctx, &materials[0], size.0, *light, footprint)?)
        }
        Subject::Scene { scene, .. } => Box::new(scene_workload(ctx, scene, materials, size, samples)?),
    };
    let measured = measure(ctx, workload.as_mut(), args, progress);
    let result = measured.and_then(|(samples, image, fetches)| {
        let error = reference.map(|r| exact_image::image_error(r, &image, exposure)).transpose()?;
        Ok((samples, error, fetches))
    });
    // SAFETY: every frame was waited for.
    unsafe { workload.destroy(ctx) };
    let (samples, error, fetches) = result?;
    let gpu: Vec<f64> = samples.iter().filter_map(|s| s.gpu_ms).collect();
    let gpu_ms = (gpu.len() == samples.len()).then(|| Spread::of(&gpu)).flatten();
    let cpu_ms = Spread::of(&samples.iter().map(|s| s.cpu_ms).collect::<Vec<_>>()).expect("at least one frame");
    let total_fetches: u64 = fetches.iter().map(|c| u64::from(c.fetches)).sum();
    // Covered pixels are those shaded at least once (the counting shaders run only where the surface is seen).
    let covered = fetches.iter().filter(|c| c.shaded > 0).count();
    let shaded: u64 = fetches.iter().map(|c| u64::from(c.shaded)).sum();
    let fetches_per_s = gpu_ms.filter(|s| s.median > 0.0).map(|s| total_fetches as f64 / (s.median * 1e-3));
    let m = &materials[0];
    Ok(Row {
        config: *config,
        width: size.0,
        height: size.1,
        order: m.plan.map(|p| p.order),
        lambda_count: m.sampling.count,
        taps: 2 * m.window.radius_x.max(m.window.radius_y) as u32 + 1,
        frames: samples.len(),
        precompute_ms,
        gpu_ms,
        cpu_ms,
        fragment_invocations: samples.last().and_then(|s| s.fragment_invocations),
        shaded_per_pixel: shaded as f64 / covered.max(1) as f64,
        fetches_per_pixel: total_fetches as f64 / f64::from(size.0 * size.1),
        fetches_per_s,
        roofline_fraction: fetches_per_s.zip(probe).map(|(rate, p)| rate / p.fetches_per_s),
        error,
        table: prof::TableSummary::of(m),
    })
}

/// Warm-up, timed frames, the last frame's image and one counting frame.
fn measure(
    ctx: &Context,
    workload: &mut dyn Workload,
    args: &ProfileArgs,
    progress: &dyn Fn(&str),
) -> crate::Result<(Vec<FrameSample>, Vec<f32>, Vec<Counts>)> {
    for w in 0..args.warmup {
        progress(&format!("warm-up {}/{}", w + 1, args.warmup));
        workload.frame(ctx)?;
    }
    let mut samples = Vec::with_capacity(args.frames as usize);
    for f in 0..args.frames {
        progress(&format!("frame {}/{}", f + 1, args.frames));
        samples.push(workload.frame(ctx)?);
    }
    let image = workload.image(ctx)?;
    if let Some(bad) = image.iter().position(|v| !v.is_finite()) {
        return Err(crate::Error::Invalid(format!(
            "pixel {} of the image is not a finite number (a bug in diffract)",
            bad / 4
        )));
    }
    progress("counting fetches");
    let fetches = workload.count_fetches(ctx)?;
    Ok((samples, image, fetches))
}

fn resolutions(rows: &[Row]) -> String {
    let mut sizes: Vec<String> = Vec::new();
    for r in rows {
        let s = format!("{}x{}", r.width, r.height);
        if !sizes.contains(&s) {
            sizes.push(s);
        }
    }
    sizes.join(", ")
}

fn roofline_line(p: &ProbeResult) -> String {
    format!(
        "roofline: {:.3e} RG32F texel fetches/s (fetch_probe.frag: {} fetches per frame on {}x{}, median {:.3} ms)",
        p.fetches_per_s, p.fetches_per_frame, p.side, p.side, p.median_gpu_ms
    )
}

fn short_workload(subject: &Subject, args: &ProfileArgs) -> String {
    match subject {
        Subject::Map { .. } => format!(
            "BRDF map of {}",
            args.heightfield.as_ref().and_then(|p| p.file_name()).map_or(String::new(), |n| n.to_string_lossy().into())
        ),
        Subject::Scene { name, .. } => format!("scene {name}"),
    }
}
