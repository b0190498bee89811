//! `diffract render`: scenes captured offscreen to PNG (display-referred) and EXR (linear), single frames or
//! sequences (turntables and light sweeps).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context as _;
use clap::Args;
use glam::{Mat4, Quat, Vec3};

use crate::cli::args::SceneOverrideArgs;
use crate::cli::GpuArgs;
use crate::gpu::vk::Owned;
use crate::io::progress::Progress;
use crate::render::capture::{prepare_materials, scene_reaches, SceneCapture};
use crate::render::preview::{render_offscreen, PreviewScene};
use crate::render::visibility::ShadingPath;
use crate::render::SceneView;
use crate::scene::mesh::Mesh;
use crate::scene::Scene;

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (TOML); default: the built-in Elaphe snake under a clear sky
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// Output PNG (8-bit sRGB after the exposure); sequences number it: NAME_0001.png
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
    /// Also write linear scene-referred RGB as 32-bit float OpenEXR
    #[arg(long, value_name = "FILE.exr")]
    pub exr: Option<PathBuf>,
    /// Width in pixels (default: the scene's, else 512)
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=crate::render::MAX_EDGE as i64))]
    pub width: Option<u32>,
    /// Height in pixels (default: the scene's, else 512)
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=crate::render::MAX_EDGE as i64))]
    pub height: Option<u32>,
    #[command(flatten)]
    pub settings: SceneOverrideArgs,
    /// How the 8-bit output shows light: filmic (AgX, as a camera's picture: highlights roll off over four stops
    /// above white, bright spectral colours desaturate towards white; a measured exposure puts the objects' median
    /// at middle grey) or clip (the sRGB transfer function, clipped at white; a measured exposure puts the 99.5th
    /// percentile at 0.9); the EXR stays linear
    #[arg(
        long,
        value_name = "CURVE",
        value_parser = crate::cli::parse::tone,
        default_value = "filmic",
        conflicts_with = "preview"
    )]
    pub tone: crate::display::Tone,
    /// Number of frames: a sequence with --orbit or --light-sweep
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    /// Turn the camera once around the target (about the world's up axis) over the frames
    #[arg(long, conflicts_with = "light_sweep")]
    pub orbit: bool,
    /// Turn the light once around the up axis over the frames
    #[arg(long)]
    pub light_sweep: bool,
    /// How far --orbit or --light-sweep turns, degrees: 360 (the default) a full turn, less an arc centred on the
    /// scene's camera or light, first and last frame at its ends
    #[arg(long, value_name = "DEG", default_value_t = 360.0, value_parser = parse_turn)]
    pub turn_deg: f32,
    /// Draw the scene lit without diffraction (fast: for framing the camera)
    #[arg(long)]
    pub preview: bool,
    /// How the frame is shaded: forward (each fragment as it is drawn), visibility (the triangles first, then
    /// each pixel's visible triangles shaded once: on lavapipe the default scene's 4-sample frame in about 0.6 of
    /// the time, at the same error against the exact reference), or auto: visibility on a CPU device with several
    /// samples per pixel (lavapipe offers 4), forward at one sample and on GPUs (not measured there yet)
    #[arg(long, value_name = "PATH", default_value = "auto", value_parser = parse_path, conflicts_with = "preview")]
    pub path: PathChoice,
    /// Let a sequence replace frames (NAME_0001.png, …) that exist already; without it a sequence refuses to
    /// overwrite a file it did not create
    #[arg(long)]
    pub overwrite: bool,
}

/// `NAME.png` → `NAME_0007.png` for frame 7 of a sequence, byte for byte (a name that is not UTF-8 keeps its
/// bytes).
fn numbered(path: &Path, frame: u32, frames: u32) -> PathBuf {
    if frames == 1 {
        return path.to_path_buf();
    }
    let mut name = path.file_stem().unwrap_or_default().to_os_string();
    name.push(format!("_{:04}", frame + 1));
    if let Some(ext) = path.extension() {
        name.push(".");
        name.push(ext);
    }
    path.with_file_name(name)
}

/// Refuses, before any work, a sequence whose frame files exist already (the user named NAME.png, not the
/// numbered files beside it), unless `--overwrite`.
fn check_sequence_names(args: &RenderArgs) -> anyhow::Result<()> {
    if args.frames == 1 || args.overwrite {
        return Ok(());
    }
    let outputs = std::iter::once(&args.out).chain(&args.exr);
    for (path, f) in outputs.flat_map(|p| (0..args.frames).map(move |f| (p, f))) {
        let frame = numbered(path, f, args.frames);
        if std::fs::symlink_metadata(&frame).is_ok() {
            anyhow::bail!(
                "{}: exists, and a sequence writes its frames beside {} without overwriting files it did not \
                 create; remove them or pass --overwrite",
                frame.display(),
                path.display()
            );
        }
    }
    Ok(())
}

/// `--path`: a shading path, or `auto` for the one [`ShadingPath::for_frame`] picks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathChoice {
    Auto,
    Fixed(ShadingPath),
}

fn parse_path(s: &str) -> std::result::Result<PathChoice, String> {
    if s == "auto" {
        return Ok(PathChoice::Auto);
    }
    ShadingPath::parse(s)
        .map(PathChoice::Fixed)
        .ok_or_else(|| format!("the shading path is auto, {}", ShadingPath::NAMES.join(" or ")))
}

/// `--turn-deg`: an angle in (0, 360].
fn parse_turn(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(deg) if deg > 0.0 && deg <= 360.0 => Ok(deg),
        _ => Err(format!("{text:?} is not an angle in degrees in (0, 360]")),
    }
}

/// The turn of frame `f` of `n`, radians: a full turn in n equal steps (the last frame one step short of the
/// first), or an arc of `turn_deg` centred on 0 from end to end.
fn frame_angle(turn_deg: f32, f: u32, n: u32) -> f32 {
    if turn_deg >= 360.0 {
        std::f32::consts::TAU * f as f32 / n as f32
    } else if n > 1 {
        turn_deg.to_radians() * (f as f32 / (n - 1) as f32 - 0.5)
    } else {
        0.0
    }
}

/// Camera and light of frame `f` of `n`.
fn frame_setup(scene: &Scene, args: &RenderArgs, f: u32) -> (crate::scene::camera::Camera, Vec3) {
    let angle = frame_angle(args.turn_deg, f, args.frames);
    let turn = Quat::from_axis_angle(scene.camera.up.normalize(), angle);
    let mut camera = scene.camera;
    let mut light = scene.light_dir;
    if args.orbit {
        camera.position = scene.camera.target + turn * (scene.camera.position - scene.camera.target);
    }
    if args.light_sweep {
        light = turn * light;
    }
    (camera, light)
}

pub fn render(gpu: &GpuArgs, args: &RenderArgs) -> anyhow::Result<std::process::ExitCode> {
    check_args(args)?;
    let scene = args.settings.load_scene(args.scene.as_deref())?;
    let outputs: Vec<(&str, PathBuf)> = (0..args.frames)
        .flat_map(|f| {
            let exr = args.exr.as_ref().map(|e| ("--exr", numbered(e, f, args.frames)));
            std::iter::once(("--out", numbered(&args.out, f, args.frames))).chain(exr)
        })
        .collect();
    let mut inputs = crate::cli::args::inputs(&args.settings.patch, &[]);
    inputs.extend(scene.files.iter().cloned());
    crate::cli::args::check_outputs(&outputs, &inputs)?;
    let width = args.width.unwrap_or(scene.render.width);
    let height = args.height.unwrap_or(scene.render.height);
    let exposure = args.settings.exposure.or(scene.render.exposure_ev);
    let ctx = crate::gpu::vk::Context::new(&gpu.context_desc())?;
    if args.preview {
        let samples = args.settings.sample_count(&ctx, &scene, crate::render::COLOR_FORMAT)?;
        return preview(&ctx, &scene, args, (width, height), samples);
    }
    let samples = args.settings.sample_count(&ctx, &scene, crate::render::LINEAR_FORMAT)?;
    let start = Instant::now();
    let materials = prepare(&ctx, &scene, args, (width, height))?;
    let prep_ms = start.elapsed().as_secs_f64() * 1e3;
    let path = match args.path {
        PathChoice::Fixed(path) => path,
        PathChoice::Auto => {
            let (path, why) = ShadingPath::for_scene(&ctx, samples, scene.objects.iter().map(|o| &o.mesh));
            if let Some(e) = why {
                errln!("drawing forward: {e}");
            }
            path
        }
    };
    let capture = SceneCapture::with_path(&ctx, &scene, &materials, (width, height), samples, path)?;
    let mut capture = Owned::new(&ctx, capture);
    let uploads = capture.uploads();
    let result = render_frames(&ctx, &scene, args, &mut capture, (width, height), exposure);
    drop(capture);
    let times = result?;
    let totals: Vec<f64> = times.iter().map(crate::gpu::vk::FrameTimes::total_ms).collect();
    // A lone frame pays the driver's first-use costs (lavapipe compiles its shader variants and its resolve while
    // drawing it: the default scene at 256² took 116 ms alone and 41 per frame in a four-frame orbit), which the
    // line says.
    let lone = totals.len() == 1;
    let median = crate::io::stats::median(&totals)
        .map(|ms| format!(", GPU {ms:.1} ms {}", if lone { "for its one frame" } else { "per frame (median)" }))
        .unwrap_or_default();
    let first_use = if lone && !median.is_empty() {
        ", first-use costs included: `diffract profile` times repeated frames"
    } else {
        ""
    };
    let what = if args.frames == 1 { args.out.display().to_string() } else { format!("{} frames", args.frames) };
    outln!(
        "wrote {what} ({width}×{height}, {} sample(s) per pixel{}, {} object(s), {} material(s); precompute \
         {prep_ms:.0} ms{median} on {}{first_use})",
        samples.as_raw(),
        if path == ShadingPath::Visibility { " through a visibility buffer" } else { "" },
        scene.objects.len(),
        scene.materials.len(),
        ctx.info.name
    );
    if let Some(line) = pass_line(&times, &uploads) {
        outln!("{line}");
    }
    let log = ctx.validation();
    drop(ctx);
    Ok(crate::cli::validation_status(&log))
}

/// The flags checked against each other before any work: outputs that can be written, a turn or a sequence with
/// something that turns, sequence names that do not overwrite.
fn check_args(args: &RenderArgs) -> anyhow::Result<()> {
    crate::io::output::check_png_path(&args.out)?;
    if let Some(exr) = &args.exr {
        crate::io::output::check_exr_path(exr)?;
    }
    if args.turn_deg < 360.0 && !(args.orbit || args.light_sweep) {
        anyhow::bail!("--turn-deg {} needs --orbit or --light-sweep (what should turn?)", args.turn_deg);
    }
    if args.frames > 1 && !(args.orbit || args.light_sweep) {
        anyhow::bail!("--frames {} needs --orbit or --light-sweep (what should change between frames?)", args.frames);
    }
    check_sequence_names(args)
}

/// The scene's materials prepared for the frames: each baked table covering what one frame's pixels see (a
/// G-buffer says), or any view for a sequence; a line per material says what it is.
fn prepare(
    ctx: &crate::gpu::vk::Context,
    scene: &Scene,
    args: &RenderArgs,
    (width, height): (u32, u32),
) -> anyhow::Result<Vec<crate::material::Material>> {
    let reaches = if args.frames == 1 {
        scene_reaches(ctx, scene, &[(scene.camera, scene.light_dir)], width, height)?
    } else {
        vec![crate::material::Reach::ANY]
    };
    let materials = prepare_materials(scene, &args.settings.patch, &reaches)?;
    if let Some(environment) = &scene.environment {
        errln!("{}", environment.describe());
    }
    if !scene.lamps.is_empty() {
        errln!("{}", crate::light::lamp::describe(&scene.lamps, scene.sun));
    }
    for (m, material) in scene.materials.iter().zip(&materials) {
        if m.matte {
            errln!("material {:?}: matte (its pigment only: no grating, no skin)", m.name);
        } else if let Some(line) = material.table_line() {
            errln!("material {:?}: {line}", m.name);
        }
    }
    Ok(materials)
}

fn render_frames(
    ctx: &crate::gpu::vk::Context,
    scene: &Scene,
    args: &RenderArgs,
    capture: &mut SceneCapture,
    (width, height): (u32, u32),
    exposure: Option<f64>,
) -> anyhow::Result<Vec<crate::gpu::vk::FrameTimes>> {
    let bar = Progress::new_if(args.frames > 1, "rendering frames", args.frames as usize);
    let mut times = Vec::new();
    // Set by the flag or the scene, else measured from the first frame and kept for the sequence.
    let mut exposure = exposure;
    let mut warned = false;
    for f in 0..args.frames {
        let (camera, light) = frame_setup(scene, args, f);
        let view = SceneView::lit(scene, camera, light);
        let frame = capture.render(ctx, &view).with_context(|| format!("frame {}", f + 1))?;
        let linear = frame.linear().expect("scene frames are captured linear");
        let png = numbered(&args.out, f, args.frames);
        let ev = match exposure {
            Some(ev) => ev,
            None => {
                let (ev, line) = capture.meter(ctx, &view, linear, args.tone)?;
                bar.line(&line);
                *exposure.insert(ev)
            }
        };
        // One verdict per sequence is enough: the rest would repeat it.
        if let Some(line) = crate::display::verdict(linear, ev, args.tone).filter(|_| !warned) {
            bar.line(&format!("{line} (frame {})", f + 1));
            warned = true;
        }
        crate::io::output::write_png_rgba8(
            &png,
            width,
            height,
            &crate::display::tone::to_rgba8(linear, ev, args.tone),
        )?;
        if let Some(exr) = &args.exr {
            let units = scene.frame_units(view.light_dir);
            crate::io::output::write_exr_rgb_in(&numbered(exr, f, args.frames), width, height, linear, &units)?;
        }
        times.extend(frame.times);
        bar.detail(png.display().to_string());
        bar.step();
    }
    bar.finish();
    Ok(times)
}

/// Where a frame's GPU time went, pass by pass (medians over the frames), and what uploading the materials'
/// textures cost once: None where the device has no timestamps.
fn pass_line(times: &[crate::gpu::vk::FrameTimes], uploads: &[crate::render::diffraction::Upload]) -> Option<String> {
    let passes = crate::render::pass_medians(times)?;
    let bytes: u64 = uploads.iter().map(|u| u.bytes).sum();
    let gpu: Option<f64> = uploads.iter().map(|u| u.gpu_ms).sum();
    let upload = gpu.map_or(String::new(), |ms| {
        format!("; textures uploaded once: {:.1} MiB, GPU {ms:.2} ms", bytes as f64 / f64::from(1u32 << 20))
    });
    Some(format!("GPU ms per pass (median): {passes}{upload}"))
}

/// What a material of diffraction alone (no pigment) shows as in a preview: a grey-green.
const PREVIEW_GREY: Vec3 = Vec3::new(0.18, 0.32, 0.25);

/// The scene lit without diffraction: every object merged into one preview mesh, each in its material's pigment.
fn preview(
    ctx: &crate::gpu::vk::Context,
    scene: &Scene,
    args: &RenderArgs,
    (width, height): (u32, u32),
    samples: ash::vk::SampleCountFlags,
) -> anyhow::Result<std::process::ExitCode> {
    let mut mesh = Mesh::default();
    for o in &scene.objects {
        let mut part = o.mesh.clone();
        let normal = glam::Mat3::from_mat4(o.model).inverse().transpose();
        // Each object in its material's pigment (under its tints); a material of diffraction alone in the
        // preview's grey-green, so that it shows.
        let pigment = Vec3::from(scene.materials[o.material].pigment);
        let pigment = if pigment == Vec3::ZERO { PREVIEW_GREY } else { pigment };
        for v in &mut part.vertices {
            v.position = o.model.transform_point3(Vec3::from(v.position)).to_array();
            v.normal = (normal * Vec3::from(v.normal)).normalize_or_zero().to_array();
            let t = glam::Mat3::from_mat4(o.model) * Vec3::from_slice(&v.tangent[..3]);
            v.tangent = [t.x, t.y, t.z, v.tangent[3]];
            v.pigment = (Vec3::from(v.pigment) * pigment).to_array();
        }
        mesh.append(&part);
    }
    for f in 0..args.frames {
        let (camera, light) = frame_setup(scene, args, f);
        let bg = scene.render.background;
        let preview = PreviewScene {
            mesh: mesh.clone(),
            model: Mat4::IDENTITY,
            camera,
            light_dir: light,
            base_color: Vec3::ONE,
            background: [bg[0], bg[1], bg[2], 1.0],
        };
        let frame = render_offscreen(ctx, &preview, width, height, samples)?;
        crate::io::output::write_png_rgba8(
            &numbered(&args.out, f, args.frames),
            width,
            height,
            frame.rgba8().expect("preview frames are RGBA8"),
        )?;
    }
    outln!("wrote a preview of {} ({width}×{height}, lit without diffraction)", scene.name);
    Ok(crate::cli::validation_status(&ctx.validation()))
}

#[cfg(test)]
mod tests {
    use super::frame_angle;

    #[test]
    fn a_full_turn_steps_evenly_and_an_arc_runs_end_to_end_about_the_setup() {
        let deg = |turn, f, n| frame_angle(turn, f, n).to_degrees();
        assert_eq!([0, 1, 3].map(|f| deg(360.0, f, 4).round()), [0.0, 90.0, 270.0]);
        assert_eq!([0, 2, 4].map(|f| deg(60.0, f, 5).round()), [-30.0, 0.0, 30.0]);
        assert_eq!(deg(60.0, 0, 1), 0.0, "one frame: the scene's own setup");
    }
}
