//! `diffract profile`: GPU timings, fetch counts and the error against an exact reference for a list of
//! settings. This file parses and prints; the loop is [`crate::reference::profiler::run`].

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{bail, Context as _};
use clap::Args;

use crate::cli::args::{HeightFieldArgs, SceneOverrideArgs};
use crate::cli::{parse, GpuArgs};
use crate::gpu::vk::Context;
use crate::material::Settings;
use crate::physics::optics;
use crate::reference::exact_image;
use crate::reference::profiler as prof;
use crate::reference::profiler::run;
use crate::reference::profiler::run::{Options, Progress, ReferenceOptions, Report, Subject};
use crate::reference::profiler::{Config, Row, Sweep};
use crate::render::offscreen::FrameTarget;
use crate::render::workload::{fetch_probe, ProbeResult};

#[derive(Args, Debug)]
pub struct ProfileArgs {
    /// Scene file (TOML) to profile; default: a BRDF map of --heightfield, else the built-in Elaphe snake
    #[arg(value_name = "SCENE", conflicts_with = "heightfield")]
    pub scene: Option<PathBuf>,
    // The height field's arguments are [`HeightFieldArgs`]'s, declared again because here they are optional: clap
    // keeps a flattened group's required argument required even where the group itself is optional.
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
    #[arg(long, value_name = "NX[,NY]", value_parser = crate::cli::parse::tile, requires = "heightfield")]
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
    /// Vary settings: KEY=V1,V2,... items (keys: every material setting by its scene key, e.g. approach, order,
    /// lambda_step_nm, window_radius, coherence_um; and size, samples, a map's shader=compute,fragment, and a
    /// scene's target=linear,display: RGBA32F frames as `render` reads back, or the 8-bit sRGB frames `view`
    /// presents, timed without a window, and path=forward,visibility: each fragment shaded as drawn, or a
    /// visibility buffer shading each pixel's visible triangles once); one --sweep runs the cross product of its
    /// items, several --sweep flags run one list after the other
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
    /// The base settings every configuration starts from (a sweep varies them); ΔE is measured at the exposure
    #[command(flatten)]
    pub settings: SceneOverrideArgs,
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
    /// Evaluate the exact reference at N pixels only, chosen at random (a fixed seed) among those the surface
    /// covers: a large map's or frame's error in minutes instead of CPU-days; the mean ΔE00 is then printed with
    /// its standard error
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub reference_pixels: Option<u64>,
    /// Time only: no exact reference and no error columns (an exact 800² snake costs CPU-hours)
    #[arg(long, conflicts_with_all = ["plot", "reference_samples", "reference_pixels"])]
    pub no_reference: bool,
    /// A scene's baked tables built for any light and view, as the viewer and rendered sequences use them,
    /// instead of for the views of the profiled frame
    #[arg(long, conflicts_with = "heightfield")]
    pub any_view: bool,
}

pub fn profile(gpu: &GpuArgs, args: &ProfileArgs) -> anyhow::Result<ExitCode> {
    if let Some(path) = &args.csv {
        crate::io::output::check_path(path, "csv")?;
    }
    if let Some(p) = &args.plot {
        crate::io::output::check_png_path(p)?;
        prof::plot::register_font(args.plot_font.as_deref())?;
    }
    let sweeps: Vec<Sweep> = args.sweep_groups.iter().map(|items| Sweep::parse(items)).collect::<crate::Result<_>>()?;
    let base = Config {
        overrides: args.settings.patch,
        size: args.width,
        samples: None,
        shader: None,
        target: None,
        path: None,
    };
    let configs = prof::configurations(base, &sweeps)?;
    let subject = load_subject(args)?;
    let mut outputs = Vec::new();
    outputs.extend(args.csv.iter().map(|p| ("--csv", p.clone())));
    outputs.extend(args.plot.iter().map(|p| ("--plot", p.clone())));
    let reads = [("the height field", args.heightfield.as_deref()), ("the plot's font", args.plot_font.as_deref())];
    let mut inputs = crate::cli::args::inputs(&args.settings.patch, &reads);
    if let Subject::Scene { scene, .. } = &subject {
        inputs.extend(scene.files.iter().cloned());
    }
    crate::cli::args::check_outputs(&outputs, &inputs)?;
    let frame_samples = subject.frame_samples(args.settings.samples)?;
    for config in &configs {
        subject.check_frame_keys(config)?;
    }
    if let Subject::Scene { scene, .. } = &subject {
        if let Some(environment) = &scene.environment {
            errln!("{}", environment.describe());
        }
    }
    // The reference covers each pixel as the frames' multisampling does (its sample count's square root per axis).
    let reference = (!args.no_reference).then(|| ReferenceOptions {
        samples: args.reference_samples.unwrap_or_else(|| (f64::from(frame_samples).sqrt().ceil() as u32).max(1)),
        pixels: args.reference_pixels.map(|n| usize::try_from(n).unwrap_or(usize::MAX)),
        cache: match args.no_reference_cache {
            true => None,
            false => args.reference_cache.clone().or_else(exact_image::default_cache_dir),
        },
    });
    let exposure = args.settings.exposure.or(subject.exposure());

    let ctx = Context::new(&gpu.context_desc())?;
    let samples = ctx.sample_count(frame_samples, crate::render::LINEAR_FORMAT)?;
    let probe = if args.roofline { roofline(&ctx, args.frames)? } else { None };
    let options = Options { frames: args.frames, warmup: args.warmup, exposure, samples, reference, probe };
    let bar = crate::io::progress::Progress::new("profiling", configs.len());
    let report = run::run(&ctx, &subject, &configs, &options, &|p| match p {
        Progress::Step { index, count: _, label, what } => {
            bar.set(index - 1, configs.len());
            bar.detail(format!("{label}: {what}"));
        }
        Progress::Line(line) => bar.line(&line),
    })?;
    bar.finish();
    print_report(&ctx, args, &subject, &options, &report)?;
    let log = ctx.validation();
    drop(ctx);
    Ok(crate::cli::validation_status(&log))
}

fn load_subject(args: &ProfileArgs) -> anyhow::Result<Subject> {
    if let Some(path) = &args.heightfield {
        let heightfield = HeightFieldArgs {
            heightfield: path.clone(),
            pixel_size_um: args.pixel_size_um,
            height_um: args.height_um,
            tile: args.tile,
            extend_um: args.settings.extend_um,
        };
        let (theta, phi) = (args.light_theta, args.light_phi);
        optics::check_theta("light", theta)?;
        if args.height.is_some_and(|h| h != args.width) {
            bail!("a BRDF map is square: give --width alone (or the same --height)");
        }
        return Ok(Subject::Map {
            heightfield: heightfield.load()?,
            light: optics::direction(theta, phi),
            settings: Settings::default(),
            name: path.display().to_string(),
            light_deg: (theta, phi),
        });
    }
    // Refused here, not by clap: a `requires = "heightfield"` lets them through beside SCENE (which conflicts
    // with --heightfield), tried with clap 4.6.
    if args.light_theta != 0.0 || args.light_phi != 0.0 {
        bail!("--light-theta and --light-phi are a BRDF map's (--heightfield); a scene has its own light");
    }
    let scene = args.settings.load_scene(args.scene.as_deref())?;
    let name = args.scene.as_ref().map_or(crate::scene::DEFAULT_SCENE_NAME.to_string(), |p| p.display().to_string());
    let aspect = match args.height {
        Some(h) => f64::from(h) / f64::from(args.width),
        None => f64::from(scene.render.height) / f64::from(scene.render.width),
    };
    Ok(Subject::Scene { scene: Box::new(scene), name, aspect, any_view: args.any_view })
}

fn roofline(ctx: &Context, frames: u32) -> anyhow::Result<Option<ProbeResult>> {
    errln!("roofline: measuring RG32F texel-fetch throughput …");
    let p = fetch_probe(ctx, frames.max(3) as usize).context("the fetch probe")?;
    if p.is_none() {
        errln!("roofline: the device has no timestamps; no throughput figures");
    }
    Ok(p)
}

/// What the counts of a multisampled frame leave out on a CPU device: llvmpipe tests each sample's depth without
/// skipping the shader where all of a block's samples failed, so hidden fragments (under the depth pre-pass's
/// surface, or under a surface drawn before them) are shaded too, with their results (and the counting shaders'
/// atomics) masked (docs/performance.md, "Why four samples cost three times one on lavapipe").
const CPU_MSAA_COUNTS: &str = "multisampling: on a CPU device a multisampled frame also runs the fragment shader \
                               where a nearer surface hides it; fetches/px and shaded per pixel count \
                               only what is seen";

/// Why a display target's rows have no error against the reference.
const DISPLAY_TARGET: &str = "target display: the 8-bit sRGB frames a window presents (encoded by the shaders), \
                              timed; ΔE00 is measured on linear frames only";

/// Whether the reference's positions limit the ΔE00 figures: each row's mean against the reference from a quarter
/// of its positions beside its mean against all of them, the largest move against the standard error.
fn convergence(rows: &[Row], options: &Options) -> Option<String> {
    let s = options.reference.as_ref()?.samples;
    let moves: Vec<(String, f64, f64, Option<f64>)> = rows
        .iter()
        .filter_map(|r| r.error.and_then(|e| e.mean_de_half_positions.map(|h| (r.label(), e.mean_de, h, e.mean_de_se))))
        .collect();
    let (label, mean, half, se) = moves.iter().max_by(|a, b| (a.1 - a.2).abs().total_cmp(&(b.1 - b.2).abs()))?;
    let moved = (mean - half).abs();
    let verdict = match se {
        Some(se) if moved <= *se => {
            format!("within its standard error ({se:.3}): more positions would not move the figures")
        }
        Some(se) => format!(
            "more than its standard error ({se:.3}): the reference has not converged; raise --reference-samples"
        ),
        None => "(every covered pixel compared: no standard error)".to_string(),
    };
    Some(format!(
        "reference convergence: against {h}×{h} of the {s}×{s} positions per pixel the means move by at most {moved:.3} \
         ({label}: {mean:.3} → {half:.3}), {verdict}",
        h = s / 2
    ))
}

/// The sizes at which docs/performance.md tables the default scene's ΔE00 ("The trade on the default scene").
const TABLED_SIZES: [u32; 3] = [256, 512, 800];

/// What a scene's ΔE00 figures mean, and where the docs' table of the default scene puts this frame's size.
fn meaning(rows: &[Row]) -> String {
    let size = rows.iter().map(|r| r.width.max(r.height)).max().unwrap_or(0);
    let nearest = TABLED_SIZES.iter().min_by_key(|&&s| s.abs_diff(size)).copied().unwrap_or(size);
    format!(
        "what the figures mean: a mean ΔE00 near 1 is about what a viewer tells apart side by side, above 3 plain to \
         see; the p99 is the few pixels at silhouettes and glints. They grow with the pixel (the more the normal turns \
         within it, above, the more a pixel's colours a frame must average) and fall with more samples; \
         docs/performance.md (\"The trade on the default scene\") tables the default scene at {sizes}² × 1 and 4 \
         samples, the nearest to this frame's {size} px being {nearest}²",
        sizes = TABLED_SIZES.map(|s| s.to_string()).join("², ")
    )
}

/// The header lines and the markdown table on stdout; the CSV and the plot where asked.
fn print_report(
    ctx: &Context,
    args: &ProfileArgs,
    subject: &Subject,
    options: &Options,
    report: &Report,
) -> anyhow::Result<()> {
    let rows = &report.rows;
    let mut comments = vec![
        format!("device: {}", ctx.info.name),
        format!("driver: {}", ctx.info.driver),
        format!("vulkan: {}", ctx.info.api_version_string()),
        format!("resolution: {}", resolutions(rows)),
        format!("workload: {}", subject.describe()),
        format!("frames: {} timed after {} warm-up", args.frames, args.warmup),
        match report.exposure {
            Some((ev, measured)) => format!(
                "delta_e: CIEDE2000 at exposure {ev:+.2} EV{} against the display's D65 white (a mirror under the \
                 illuminant has Y = 1), pixels showing a diffracting surface (a matte material's, the same in every \
                 approach, are left out)",
                if measured { " (measured from the reference: the scene sets none)" } else { "" }
            ),
            None => "delta_e: none (no reference)".to_string(),
        },
    ];
    if ctx.info.kind == ash::vk::PhysicalDeviceType::CPU && rows.iter().any(|r| r.samples > 1) {
        comments.push(CPU_MSAA_COUNTS.to_string());
    }
    if rows.iter().any(|r| r.frame_target == Some(FrameTarget::Display)) {
        comments.push(DISPLAY_TARGET.to_string());
    }
    for (size, description) in &report.references {
        comments.push(format!("reference {}x{}: {description}", size.0, size.1));
    }
    if let Some(line) = convergence(rows, options) {
        comments.push(line);
    }
    if let (Subject::Scene { .. }, Some(_)) = (subject, &options.reference) {
        comments.push(meaning(rows));
    }
    if let Some(p) = &options.probe {
        comments.push(roofline_line(p));
    }
    outln!("{}", comments.iter().map(|c| format!("- {c}")).collect::<Vec<_>>().join("\n"));
    outln!();
    crate::io::stream::out_text(&prof::markdown(rows));
    let passes = prof::markdown_passes(rows);
    if !passes.is_empty() {
        outln!();
        outln!("Where each frame's GPU time goes (median ms per pass; the passes of a frame sum to its time):");
        outln!();
        crate::io::stream::out_text(&passes);
    }
    if let Some(path) = &args.csv {
        let mut all = comments.clone();
        all.push(format!("command: diffract {}", std::env::args().skip(1).collect::<Vec<_>>().join(" ")));
        crate::io::output::write_file(path, prof::csv(&all, rows).as_bytes())?;
        errln!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        let title = format!("{} — {}", subject.short_name(), ctx.info.name);
        prof::plot::plot(path, &title, rows, args.plot_font.as_deref())?;
        errln!("wrote {}", path.display());
    }
    Ok(())
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
