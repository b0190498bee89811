//! `diffract view`: a scene in a window.

use std::path::PathBuf;

use anyhow::bail;
use clap::{Args, ValueEnum};

use crate::cli::args::SceneOverrideArgs;
use crate::cli::GpuArgs;
use crate::view;
use crate::view::ViewOptions;

#[derive(Copy, Clone, Debug, ValueEnum)]
pub enum OnOff {
    On,
    Off,
}

#[derive(Args, Debug)]
pub struct ViewArgs {
    /// Scene file (TOML); default: the built-in Elaphe snake under a clear sky
    #[arg(value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// Window width in pixels
    #[arg(long, default_value_t = 640, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub width: u32,
    /// Window height in pixels
    #[arg(long, default_value_t = 480, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub height: u32,
    /// Wait for the display's refresh (FIFO) or not (MAILBOX/IMMEDIATE where offered)
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub vsync: OnOff,
    /// Render this many frames, then exit (with --screenshot: write the last one)
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// With --frames: the PNG to write the last frame to
    #[arg(long, value_name = "FILE.png", requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// The settings at start (the keys change them while the window is open)
    #[command(flatten)]
    pub settings: SceneOverrideArgs,
    /// How the window shows light: filmic (AgX, as `render` shows it: highlights roll off over four stops above
    /// white, bright spectral colours desaturate towards white) or clip (the sRGB transfer function, clipped)
    #[arg(long, value_name = "CURVE", value_parser = crate::cli::parse::tone, default_value = "filmic")]
    pub tone: crate::display::Tone,
    /// Ask the window to shrink to 3/4 after N frames (tests that a resize is survived)
    #[arg(long, hide = true, value_name = "N")]
    pub resize_after: Option<u32>,
    /// With --frames: every 50 frames resize the window and switch to the next approach, and print resident
    /// memory (a soak test of the swapchain, the pipelines and the tables; `scripts/soak-view.sh`)
    #[arg(long, hide = true, requires = "frames")]
    pub soak: bool,
}

pub fn view(gpu: &GpuArgs, args: &ViewArgs) -> anyhow::Result<std::process::ExitCode> {
    if let Some(p) = &args.screenshot {
        crate::io::output::check_png_path(p)?;
    }
    let no_display = std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty())
        && std::env::var_os("WAYLAND_DISPLAY").is_none_or(|d| d.is_empty());
    if no_display {
        bail!("no display (neither DISPLAY nor WAYLAND_DISPLAY is set): `diffract view` opens a window; use `diffract render` for headless images");
    }
    let scene = args.settings.load_scene(args.scene.as_deref())?;
    if let Some(p) = &args.screenshot {
        let mut inputs = crate::cli::args::inputs(&args.settings.patch, &[]);
        inputs.extend(scene.files.iter().cloned());
        crate::cli::args::check_outputs(&[("--screenshot", p.clone())], &inputs)?;
    }
    // None: measured from the first frame of the prepared materials.
    let exposure_ev = args.settings.exposure.or(scene.render.exposure_ev);
    let options = ViewOptions {
        scene,
        width: args.width,
        height: args.height,
        vsync: matches!(args.vsync, OnOff::On),
        context: gpu.context_desc(),
        overrides: args.settings.patch,
        exposure_ev,
        tone: args.tone,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        resize_after: args.resize_after,
        soak: args.soak,
        samples: args.settings.samples,
    };
    Ok(crate::cli::validation_count_status(view::run(options)?))
}
