//! `diffract gen`: generated nanostructures (`gen patch`), the procedural snake as an OBJ mesh (`gen snake`) and the
//! clear sky as an HDR environment map (`gen sky`).

use std::path::PathBuf;

use anyhow::bail;
use clap::{Args, Subcommand};

use crate::cli::parse;
use crate::physics::formats::gsf;
use crate::physics::generate::{generate, PatchKind, PatchSpec};
use crate::scene::mesh::snake::{Pattern, SnakeSpec};

#[derive(Subcommand, Debug)]
pub enum GenCommand {
    /// A height-field patch in physical units, written as Gwyddion Simple Field (.gsf)
    #[command(after_help = "Examples:
  diffract gen patch blazed --out blaze.gsf                       2.5 µm period, 0.25 µm, 65 µm square
  diffract gen patch sinusoidal --period-um 1.6 --height-um 0.1 --size-um 32 --out sine.gsf
  diffract gen patch elaphe --size-um 65 --pixel-um 0.065 --seed 7 --out elaphe.gsf --preview elaphe.png")]
    Patch(PatchArgs),
    /// The procedural snake as Wavefront OBJ (UVs run along the body, so readers derive tangents along it)
    #[command(after_help = "Examples:
  diffract gen snake --out snake.obj                     domed overlapping scales, a corn snake's pattern
  diffract gen snake --pattern plain --out plain.obj     one colour (vertex colours untinted)
  diffract gen snake --smooth --out smooth-snake.obj     a smooth body")]
    Snake(SnakeArgs),
    /// A clear sky and its sun (Hosek–Wilkie 2012, or Preetham et al. 1999) as an equirectangular environment map: OpenEXR of linear
    /// sRGB radiance whose luminance is in cd/m², or a PNG preview at a measured exposure
    #[command(after_help = "Layout: x is the azimuth from -180° (left) to +180° (right), 0 along +z and 90° along +x;
y the elevation from +90° (top) to -90° (bottom); +y is up, as in scenes. Below the horizon: a Lambertian ground
of --ground-albedo lit by the sun and sky. The sun's disc (0.53°) keeps its energy whatever the map's size.

Examples:
  diffract gen sky --out sky.exr                                   sun 50° high, turbidity 3, 1024×512
  diffract gen sky --sun-elevation-deg 15 --turbidity 2 --out low-sun.exr --width 2048
  diffract gen sky --sun-elevation-deg 35 --sun-azimuth-deg 120 --out sky.png        a preview
  diffract gen sky --sun-elevation-deg 35 --no-sun --out around.exr   a scene's environment = \"around.exr\"
  diffract gen sky --sky-model preetham --out preetham.exr        the 1999 model (brighter than measured skies)")]
    Sky(SkyArgs),
}

#[derive(Args, Debug)]
pub struct SkyArgs {
    /// Output: .exr or .hdr (Radiance RGBE, about 1 % resolution) (linear radiance, luminance in cd/m²) or .png
    /// (a preview at a measured exposure)
    #[arg(long, value_name = "FILE.exr|FILE.hdr|FILE.png")]
    pub out: PathBuf,
    /// The sun's elevation above the horizon, degrees (0–90)
    #[arg(long, value_parser = parse::finite, default_value_t = 50.0, allow_negative_numbers = true)]
    pub sun_elevation_deg: f64,
    /// The sun's azimuth, degrees (0 along +z, 90 along +x)
    #[arg(long, value_parser = parse::finite, default_value_t = 0.0, allow_negative_numbers = true)]
    pub sun_azimuth_deg: f64,
    /// Atmospheric turbidity: 1 (exceptionally clear; 2 for Preetham's sky) to 10 (light haze)
    #[arg(long, value_parser = parse::finite, default_value_t = 3.0)]
    pub turbidity: f64,
    /// The sky model: hosek-wilkie (Hosek & Wilkie 2012) or preetham (Preetham et al. 1999)
    #[arg(long, default_value = "hosek-wilkie", value_parser = ["hosek-wilkie", "preetham"])]
    pub sky_model: String,
    /// Width of the map in texels (its height is half of it), 8 to 8192: the widest map a scene loads
    #[arg(long, default_value_t = 1024,
          value_parser = clap::value_parser!(u32).range(8..=i64::from(crate::light::environment::MAX_FILE_WIDTH)))]
    pub width: u32,
    /// The ground's albedo below the horizon (0: black)
    #[arg(long, value_parser = parse::finite, default_value_t = 0.2)]
    pub ground_albedo: f64,
    /// Leave the sun's disc out: the sky around it alone (what a scene's `environment = "FILE.exr"` takes, whose
    /// sun is the scene's light)
    #[arg(long)]
    pub no_sun: bool,
    /// The PNG preview's exposure, stops (default: measured from the map)
    #[arg(long, value_parser = parse::finite, value_name = "EV", allow_negative_numbers = true)]
    pub exposure: Option<f64>,
}

#[derive(Args, Debug)]
pub struct SnakeArgs {
    /// Output .obj
    #[arg(long, value_name = "FILE.obj")]
    pub out: PathBuf,
    /// Body length (scene units)
    #[arg(long, default_value_t = 4.0)]
    pub length: f32,
    /// A smooth body instead of flat scales
    #[arg(long)]
    pub smooth: bool,
    /// Rows of scales along the body (neighbouring rows offset by half a scale)
    #[arg(long, default_value_t = SnakeSpec::default().scale_rows)]
    pub scale_rows: u32,
    /// Scales around the body
    #[arg(long, default_value_t = SnakeSpec::default().scales_around)]
    pub scales_around: u32,
    /// Height of each scale's dome relative to its half-width (0: flat scales)
    #[arg(long, value_parser = parse::finite, default_value_t = f64::from(SnakeSpec::default().scale_dome))]
    pub dome: f64,
    /// The skin's pattern, as vertex colours that tint the material's pigment
    #[arg(long, value_enum, default_value_t = Pattern::Corn)]
    pub pattern: Pattern,
    /// Seed of the scales' random turns and of the pattern
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

#[derive(Args, Debug)]
pub struct PatchArgs {
    /// What to generate
    #[arg(value_enum)]
    pub kind: PatchKind,
    /// Output .gsf
    #[arg(long, value_name = "FILE.gsf")]
    pub out: PathBuf,
    /// Edge length of the square patch, µm (65 µm is the coherence length of sunlight)
    #[arg(value_parser = parse::finite, long, default_value_t = 65.0)]
    pub size_um: f64,
    /// Pixel size, µm (≤ 0.095 µm samples every direction at 380 nm)
    #[arg(value_parser = parse::finite, long, default_value_t = 0.065)]
    pub pixel_um: f64,
    /// Period, µm (default per kind: sinusoidal 2, blazed 2.5, cd 1.6, elaphe 1.14, xenopeltis 1.55)
    #[arg(value_parser = parse::finite, long)]
    pub period_um: Option<f64>,
    /// Peak-to-valley height, µm (default per kind: 0.2, 0.25, 0.12, 0.375, 0.44)
    #[arg(value_parser = parse::finite, long)]
    pub height_um: Option<f64>,
    /// Seed of the random structures (cd, elaphe, xenopeltis)
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Also write a greyscale 16-bit PNG preview (black = lowest)
    #[arg(long, value_name = "FILE.png")]
    pub preview: Option<PathBuf>,
}

pub fn run(command: &GenCommand) -> anyhow::Result<()> {
    match command {
        GenCommand::Patch(args) => patch(args),
        GenCommand::Snake(args) => snake(args),
        GenCommand::Sky(args) => sky(args),
    }
}

fn png_path(path: &std::path::Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

fn sky(args: &SkyArgs) -> anyhow::Result<()> {
    if args.exposure.is_some() && !png_path(&args.out) {
        bail!("--exposure sets the PNG preview's exposure; an EXR or HDR file holds the radiance itself");
    }
    let png = png_path(&args.out);
    let extension = args.out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let hdr = extension.as_deref() == Some("hdr");
    if !matches!(extension.as_deref(), Some("exr" | "hdr" | "png")) {
        bail!("cannot write {}: a sky is written as .exr or .hdr (radiance) or .png (a preview)", args.out.display());
    }
    crate::io::output::check_path(
        &args.out,
        if png {
            "png"
        } else if hdr {
            "hdr"
        } else {
            "exr"
        },
    )?;
    let model = crate::physics::sky::SkyModel::named(&args.sky_model)?;
    let sky = crate::physics::sky::Sky::at_of_model(
        model,
        args.turbidity,
        args.sun_elevation_deg,
        args.sun_azimuth_deg,
        args.ground_albedo,
    )?;
    let map = if args.no_sun {
        crate::light::environment::EnvironmentMap::of_sky(&sky, args.width, args.ground_albedo)?
    } else {
        crate::light::environment::EnvironmentMap::of_sky_and_sun(&sky, args.width, args.ground_albedo)?
    };
    let (sun, sky_lux) = sky.horizontal_illuminance(180);
    outln!(
        "sky ({}): turbidity {}, sun {}° high at azimuth {}°: zenith {:.0} cd/m², sun {:.3e} cd/m²; a horizontal \
         surface gets {:.1} klx from the sun and {:.1} klx from the sky",
        model.citation(),
        crate::error::number(args.turbidity),
        crate::error::number(args.sun_elevation_deg),
        crate::error::number(args.sun_azimuth_deg),
        sky.zenith.0,
        sky.sun_xyz().y,
        sun * 1e-3,
        sky_lux * 1e-3
    );
    let rgba = map.to_rgba();
    if png {
        let ev = args.exposure.unwrap_or_else(|| {
            let (ev, line) = crate::display::measure(&rgba, None, "the map", crate::display::Tone::Clip);
            outln!("{line}");
            ev
        });
        crate::io::output::write_png_rgba8(
            &args.out,
            map.width,
            map.height,
            &crate::display::tone::to_rgba8(&rgba, ev, crate::display::Tone::Clip),
        )?;
    } else if hdr {
        crate::io::output::write_hdr_rgb(&args.out, map.width, map.height, &rgba)?;
    } else {
        crate::io::output::write_exr_rgb(&args.out, map.width, map.height, &rgba)?;
    }
    let without = if args.no_sun { ", without its sun" } else { "" };
    outln!("wrote {} ({}×{} texels{without})", args.out.display(), map.width, map.height);
    Ok(())
}

/// The most scales a generated snake may have (each is 25 vertices: 2·10⁵ scales are ~300 MB in memory).
const MAX_SCALES: u64 = 200_000;

fn snake(args: &SnakeArgs) -> anyhow::Result<()> {
    crate::io::output::check_path(&args.out, "obj")?;
    if !(args.length.is_finite() && args.length > 0.0 && args.length <= 1e6)
        || args.scale_rows > 10_000
        || args.scales_around > 1000
        || u64::from(args.scale_rows) * u64::from(args.scales_around) > MAX_SCALES
    {
        bail!(
            "--length must lie in (0, 1e6], --scale-rows at most 10000, --scales-around at most 1000 and their \
             product (the number of scales) at most {MAX_SCALES}"
        );
    }
    if !(0.0..=2.0).contains(&args.dome) {
        bail!("--dome is a height relative to the scale's half-width, from 0 (flat) to 2");
    }
    let spec = SnakeSpec {
        length: args.length,
        seed: args.seed,
        scale_rows: if args.smooth { 0 } else { args.scale_rows },
        scales_around: args.scales_around,
        scale_dome: args.dome as f32,
        pattern: args.pattern,
        ..Default::default()
    };
    let mesh = crate::scene::mesh::snake::snake(&spec);
    crate::scene::mesh::obj::save(&args.out, &mesh, "diffract gen snake: tangents along the body follow increasing u")?;
    outln!("wrote {} ({} vertices, {} triangles)", args.out.display(), mesh.vertices.len(), mesh.indices.len() / 3);
    Ok(())
}

fn patch(args: &PatchArgs) -> anyhow::Result<()> {
    crate::io::output::check_path(&args.out, "gsf")?;
    if let Some(p) = &args.preview {
        crate::io::output::check_png_path(p)?;
    }
    let mut spec = PatchSpec::new(args.kind, args.size_um, args.pixel_um);
    spec.period_um = args.period_um.unwrap_or(spec.period_um);
    spec.depth_um = args.height_um.unwrap_or(spec.depth_um);
    spec.seed = args.seed;
    let hf = generate(&spec)?;
    gsf::write(&args.out, &hf, &format!("diffract gen patch {:?} seed {}", args.kind, args.seed))?;
    if let Some(p) = &args.preview {
        let (lo, hi) = hf.range();
        let span = (hi - lo).max(1e-12);
        let grey = hf.heights_um.iter().map(|h| ((h - lo) / span * 65535.0).round() as u16).collect();
        crate::io::output::write_png_gray16(p, hf.nx as u32, hf.ny as u32, grey)?;
    }
    let (lo, hi) = hf.range();
    outln!(
        "wrote {} ({}×{} pixels of {} µm, {:.2}×{:.2} µm, heights {lo:.3}..{hi:.3} µm)",
        args.out.display(),
        hf.nx,
        hf.ny,
        hf.dx_um,
        hf.size_um().0,
        hf.size_um().1
    );
    Ok(())
}
