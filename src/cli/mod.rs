//! The `diffract` command line. `anyhow` is used here only; every failure ends as one line on stderr and a
//! non-zero exit code.

mod args;
mod brdf;
mod generate;
mod map;
mod parse;
mod profile;
mod render;
mod view;

use std::process::ExitCode;

use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};

use crate::gpu::vk;
use crate::gpu::vk::{ContextDesc, DeviceSelector};

const EXAMPLES: &str = "\
Examples:
  diffract devices                                   list Vulkan devices
  diffract render --out frame.png                    the default scene (under a clear sky), 512x512
  diffract render --out small.png --width 128 --height 128 --validation
  diffract render --device llvmpipe --out cpu.png    force lavapipe (the CPU driver)
  diffract brdf --heightfield grating.gsf --light-theta 0 --view-theta 0:60:0.5 --lambda 550
  diffract brdf --heightfield elaphe.png --pixel-size-um 0.065 --height-um 0.375 --tile 10 \
                --light-theta 30 --light-phi 180 --view 20,0 --view 25,0 --lambda 380:780:5 --method taylor
  diffract terms --heightfield elaphe.png --pixel-size-um 0.065 --height-um 0.375 --tile 10
  diffract profile --width 96 --sweep approach=flss,nmm,pq,gem --csv p.csv --plot p.png
                                                     speed against accuracy on the default scene";

#[derive(Parser, Debug)]
#[command(name = "diffract", version, about = "Render diffraction colours of measured nanostructures with Vulkan", after_help = EXAMPLES)]
pub struct Cli {
    #[command(flatten)]
    pub gpu: GpuArgs,
    #[command(subcommand)]
    pub command: Command,
}

/// Options of every subcommand that touches Vulkan.
#[derive(Args, Debug, Clone)]
pub struct GpuArgs {
    /// Vulkan device: an index from `diffract devices` or a substring of its name (default: discrete GPU,
    /// then integrated, then CPU)
    #[arg(long, global = true, value_name = "N|NAME")]
    pub device: Option<String>,
    /// Enable the Khronos validation layer and print its messages (also DIFFRACT_VALIDATION=1)
    #[arg(long, global = true)]
    pub validation: bool,
}

impl GpuArgs {
    pub fn context_desc(&self) -> ContextDesc {
        let selector = self.device.as_deref().map(DeviceSelector::parse).unwrap_or_default();
        ContextDesc::new(selector, self.validation)
    }
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// List every Vulkan device with its index, name, type, Vulkan version and driver
    Devices,
    /// Render a scene (default: the Elaphe snake under a clear sky) headless to PNG and EXR, one frame or a sequence
    #[command(after_help = RENDER_HELP, allow_negative_numbers = true)]
    Render(render::RenderArgs),
    /// Evaluate the diffraction BRDF on the CPU (exact reference or Taylor sum) and print CSV
    #[command(after_help = BRDF_HELP, allow_negative_numbers = true)]
    Brdf(brdf::BrdfArgs),
    /// Report a height field's units, the Taylor order a scene needs and what f32 can reach
    #[command(allow_negative_numbers = true)]
    Terms(brdf::TermsArgs),
    /// Open a scene in a window: orbit camera, light and live speed/accuracy controls (H for help)
    #[command(after_help = VIEW_HELP, allow_negative_numbers = true)]
    View(view::ViewArgs),
    /// Generate nanostructure patches
    #[command(subcommand)]
    Gen(generate::GenCommand),
    /// Render the BRDF map of a height field (the hemisphere of views for one light) on the GPU
    #[command(after_help = MAP_HELP, allow_negative_numbers = true)]
    Map(map::MapArgs),
    /// Measure speed against accuracy: GPU timings, texel fetches and the error against an exact reference
    #[command(
        after_help = PROFILE_HELP,
        allow_negative_numbers = true,
        override_usage = "diffract profile [OPTIONS] [SCENE | --heightfield FILE [HEIGHT-FIELD OPTIONS]]"
    )]
    Profile(profile::ProfileArgs),
}

const PROFILE_HELP: &str = "\
For each configuration: GPU ms per frame (timestamps: median, p10, p90), CPU ms per frame, Taylor-term texel
fetches per pixel (counted by the shaders), their share of the device's peak (--roofline) and the error of the
image against an exact reference (f64, Taylor remainder <= 1e-10, full window, 1 nm steps; computed on the CPU
once and cached): mean and 99th-percentile CIEDE2000 at --exposure, and the relative XYZ RMSE.

Examples:
  diffract profile --heightfield elaphe.png --pixel-size-um 0.065 --height-um 0.375 --tile 10 --width 64 \\
                   --exposure 8 --frames 5 --sweep approach=flss,nmm,pq,gem --sweep order=4,8,16 lambda_step_nm=10,5
  diffract profile --heightfield blaze.gsf --roofline --csv blaze.csv --plot blaze.png
  diffract profile assets/scenes/blazed-disk.toml --width 96 --height 64 --sweep approach=flss,gem
  diffract profile --width 800 --height 800 --no-reference --sweep samples=1,4 target=linear,display
                   the default scene's frames pass by pass, as `render` and as `view` draw them";

const RENDER_HELP: &str = "\
Examples:
  diffract render --out snake.png                            the built-in Elaphe snake under a clear sky, 512x512
  diffract render assets/scenes/elaphe-snake-sun.toml --out sun.png   the same under the sun alone (relative units)
  diffract render --out bright.png --exposure 14 --tone filmic   glints past white keep their colours (AgX)
  diffract render assets/scenes/xenopeltis-snake.toml --out x.png --exr x.exr --approach nmm
  diffract render assets/scenes/blazed-disk.toml --out turn.png --frames 36 --orbit
  diffract render my-scene.toml --out quick.png --preview      lit without diffraction, to frame the camera";

const VIEW_HELP: &str = "\
Examples:
  diffract view                                     the Elaphe snake in a 640x480 window
  diffract view assets/scenes/blazed-disk.toml --vsync off
  diffract view --frames 30 --screenshot shot.png   render 30 frames, save the last, exit

Controls (also printed at start and by H):
  mouse: left drag orbit · right drag (or shift + left drag) pan · wheel zoom · ctrl + left drag move the light
  1 2 3 4 5 approach (flss nmm pq gem baked) · T/shift+T Taylor order · L/shift+L wavelength step · R/shift+R window radius · +/- exposure
  arrows light · M BRDF map <-> geometry · P screenshot · H help · Esc quit";

const MAP_HELP: &str = "\
The map's inscribed disk is the hemisphere of view directions: the pixel at (x, y) from the centre (x right, y up,
radius 1) looks along sin θ_r = √(x²+y²), φ_r = atan2(y, x), so the patch's x axis points right.

Examples:
  diffract map --heightfield blaze.gsf --light-theta 0 --out blaze.png --exposure 4
  diffract map --heightfield elaphe.png --pixel-size-um 0.065 --height-um 0.375 --tile 10 \\
               --light-theta 20 --approach nmm --out elaphe-nmm.png --exr elaphe-nmm.exr
  diffract map --heightfield blaze.gsf --light-theta 45 --lamp-radius-m 0.01 --lamp-distance-m 0.2 \\
               --out blaze-lamp.png      under a bulb 2 cm across at 20 cm: its size sets the coherence
  diffract gen sky --sun-elevation-deg 50 --out sky.exr
  diffract map --heightfield blaze.gsf --environment sky.exr --out blaze-sky.png \
               --env-samples 1024 --env-reference 32      the map under a sky, checked against the exact BRDF";

const BRDF_HELP: &str = "\
Conventions: patch x along image columns, y along rows, z the normal. Directions point from the surface to
the light (θ_i, φ_i) and to the viewer (θ_r, φ_r). (u,v,w) = −ω_i − ω_r. power = |P(u/λ, v/λ)|², 1 for a flat
mirror at specular; reflectance = C(ω_i, ω_r)·power, relative to a mirror at normal incidence (model.md §1.5);
brdf_sr = the BRDF in sr⁻¹, reflectance·R₀(kσ_s)²/(π cos θ_i), energy-conserving in the coherence length.

Examples:
  diffract brdf --heightfield grating.gsf --light-theta 0 --view-theta 0:60:0.5 --lambda 550
  diffract brdf --heightfield elaphe.png --pixel-size-um 0.065 --height-um 0.375 --tile 10 \\
                --light-theta 30 --light-phi 180 --view 20,0 --lambda 380:780:5 --method taylor";

/// Runs the command line; returns the process exit code.
pub fn main() -> ExitCode {
    // A closed pipe on stdout or stderr (`diffract terms … | head -1`) ends the command quietly with the status a
    // shell reports for SIGPIPE (141), as every Unix filter does; Rust's runtime ignores the signal, which turns
    // the next print into a panic.
    // SAFETY: restoring a signal's default disposition at start-up, before any other thread exists.
    unsafe { libc::signal(libc::SIGPIPE, libc::SIG_DFL) };
    // A file-size limit (`ulimit -f`) reached while writing: the write fails with EFBIG instead of the process
    // being killed, so the atomic writer removes its temporary file and the run ends with its `error:` line.
    // SAFETY: as above.
    unsafe { libc::signal(libc::SIGXFSZ, libc::SIG_IGN) };
    // Ctrl-C and SIGTERM: no temporary file left behind (a second handler, a test's, is theirs to keep).
    let _ = ctrlc::set_handler(|| crate::io::output::remove_temporaries_and_exit());
    // What the library logs is shown on stderr, one line each.
    if log::set_logger(&STDERR_LOG).is_ok() {
        log::set_max_level(log::LevelFilter::Info);
    }
    let matches = match command().try_get_matches() {
        Ok(m) => m,
        Err(e) => return usage_error(e),
    };
    let mut cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    // A sweep is one --sweep flag's items: clap's derive merges the flags, its occurrences keep them apart.
    if let (Command::Profile(args), Some(("profile", m))) = (&mut cli.command, matches.subcommand()) {
        args.sweep_groups = m
            .get_occurrences::<String>("sweep")
            .map(|groups| groups.map(|g| g.cloned().collect()).collect())
            .unwrap_or_default();
    }
    let code = match run(&cli) {
        Ok(code) => code,
        Err(e) => {
            errln!("error: {e:#}");
            ExitCode::FAILURE
        }
    };
    // A line that could not be written (stdout or stderr on a full disk) fails the run, once everything else is
    // done: what went to files is kept.
    match crate::io::stream::failure() {
        Some(why) => {
            errln!("error: {why}");
            ExitCode::FAILURE
        }
        None => code,
    }
}

/// The command line: clap's derive, with the setting flags a command does not read hidden from its help.
pub fn command() -> clap::Command {
    Cli::command()
        .mut_subcommand("brdf", |c| args::hide_unused_settings(c, &brdf::BRDF_SETTINGS))
        .mut_subcommand("terms", |c| args::hide_unused_settings(c, &brdf::TERMS_SETTINGS))
}

/// The command line's logger: the library's warnings as `warning: …` lines and its notes as `note: …`, the
/// validation layer's messages and plain lines as they are, all on stderr.
struct StderrLog;

static STDERR_LOG: StderrLog = StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::Level::Info
    }

    fn log(&self, record: &log::Record<'_>) {
        if !self.enabled(record.metadata()) {
            return;
        }
        let prefix = match (record.target(), record.level()) {
            (crate::io::LOG_VALIDATION | crate::io::LOG_PLAIN, _) => "",
            (_, log::Level::Error) => "error: ",
            (_, log::Level::Warn) => "warning: ",
            _ => "note: ",
        };
        // A stderr that cannot be written (a full disk) loses the line, and fails the run at its end.
        errln!("{prefix}{}", record.args());
    }

    fn flush(&self) {}
}

/// Help and version go to stdout through the same writer as every other line (a full stdout ends the run with an
/// `error:` line and status 1, as any command's output does); a usage error becomes one line on stderr (clap's own
/// first line, which names the argument and the reason) and exit status 2.
fn usage_error(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        crate::io::stream::out_text(&e.render().to_string());
        return match crate::io::stream::failure() {
            Some(why) => {
                errln!("error: {why}");
                ExitCode::FAILURE
            }
            None => ExitCode::SUCCESS,
        };
    }
    if matches!(e.kind(), ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand) {
        let text = e.render().to_string();
        crate::io::stream::err_text(&text);
        return ExitCode::from(2);
    }
    // Clap's first paragraph is the error (a missing argument's name is on the lines after the first).
    let text = e.render().to_string();
    let paragraph: Vec<&str> =
        text.lines().skip_while(|l| l.trim().is_empty()).take_while(|l| !l.trim().is_empty()).map(str::trim).collect();
    let line = if paragraph.is_empty() { "error: invalid arguments".to_string() } else { paragraph.join(" ") };
    errln!("{line} (diffract --help)");
    ExitCode::from(2)
}

fn run(cli: &Cli) -> anyhow::Result<ExitCode> {
    match &cli.command {
        Command::Devices => devices(&cli.gpu),
        Command::Render(args) => render::render(&cli.gpu, args),
        Command::Brdf(args) => brdf::brdf(&cli.gpu, args),
        Command::Map(args) => map::map(&cli.gpu, args),
        Command::Profile(args) => profile::profile(&cli.gpu, args),
        Command::View(args) => view::view(&cli.gpu, args),
        Command::Gen(command) => generate::run(command).map(|()| ExitCode::SUCCESS),
        Command::Terms(args) => brdf::terms(args).map(|()| ExitCode::SUCCESS),
    }
}

/// Exit status after Vulkan work: with validation on, any message makes the run fail.
fn validation_status(log: &vk::ValidationLog) -> ExitCode {
    validation_count_status(log.count())
}

/// The same for a count of messages (the viewer's log ends with its window).
fn validation_count_status(count: usize) -> ExitCode {
    match count {
        0 => ExitCode::SUCCESS,
        n => {
            errln!("error: the validation layer reported {n} message(s)");
            ExitCode::FAILURE
        }
    }
}

fn devices(gpu: &GpuArgs) -> anyhow::Result<ExitCode> {
    let (devices, log) = vk::list_devices(gpu.context_desc().validation)?;
    if devices.is_empty() {
        return Err(crate::Error::NoDevice.into());
    }
    outln!("{:<5} {:<40} {:<15} {:<8} driver", "index", "name", "type", "vulkan");
    for d in &devices {
        outln!("{:<5} {:<40} {:<15} {:<8} {}", d.index, d.name, d.kind_name(), d.api_version_string(), d.driver);
    }
    Ok(validation_status(&log))
}
