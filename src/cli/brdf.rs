//! `diffract brdf` (the CPU reference as CSV) and `diffract terms` (what the precomputation would do).

use std::io::Write;

use anyhow::bail;
use clap::{Args, ValueEnum};

use crate::cli::args::{HeightFieldArgs, LightArgs, MaterialArgs};
use crate::cli::parse;
use crate::physics::coherence::CoherenceWindow;
use crate::physics::exact::{Method, Query};
use crate::physics::heightfield::HeightField;
use crate::reference::brdf::Evaluator;

#[derive(Copy, Clone, Debug, ValueEnum)]
pub enum MethodArg {
    /// DFT of exp(i k w h) itself, f64, no Taylor series
    Exact,
    /// Sum of the precomputed Taylor terms (as the GPU does), f64
    Taylor,
    /// The same sum in f32 arithmetic, emulating the GPU
    TaylorF32,
}

#[derive(Args, Debug)]
pub struct BrdfArgs {
    #[command(flatten)]
    pub heightfield: HeightFieldArgs,
    #[command(flatten)]
    pub light: LightArgs,
    /// A view direction θ_r,φ_r in degrees (repeatable)
    #[arg(long, value_name = "THETA,PHI", value_parser = parse::pair, conflicts_with = "view_theta")]
    pub view: Vec<(f64, f64)>,
    /// Sweep the view inclination: FROM:TO:STEP in degrees (or a list)
    #[arg(long, value_name = "FROM:TO:STEP")]
    pub view_theta: Option<String>,
    /// View azimuth for --view-theta, degrees
    #[arg(value_parser = parse::finite, long, value_name = "DEG", default_value_t = 0.0, requires = "view_theta")]
    pub view_phi: f64,
    /// Wavelengths in nm: NM, NM,NM,... or FROM:TO:STEP
    #[arg(long, value_name = "NM")]
    pub lambda: String,
    /// How P is evaluated (default: exact on the CPU, taylor with --gpu)
    #[arg(long, value_enum)]
    pub method: Option<MethodArg>,
    /// Evaluate the Taylor sum on the GPU with the shaders' code (f32), printing the same CSV
    #[arg(long)]
    pub gpu: bool,
    #[command(flatten)]
    pub material: MaterialArgs,
}

/// The settings `brdf` reads (the others are refused): an exact or Taylor evaluation at given wavelengths.
pub const BRDF_SETTINGS: [&str; 5] = ["order", "tolerance", "coherence_um", "window_radius", "accept_f32_error"];
/// The settings `terms` reads.
pub const TERMS_SETTINGS: [&str; 6] =
    ["order", "tolerance", "coherence_um", "window_radius", "table_tolerance", "strict_table"];

pub fn brdf(gpu: &crate::cli::GpuArgs, args: &BrdfArgs) -> anyhow::Result<std::process::ExitCode> {
    let hf = args.heightfield.load()?;
    let lambdas = parse::values(&args.lambda).map_err(|e| anyhow::anyhow!("--lambda {e}"))?;
    let views: Vec<(f64, f64)> = match &args.view_theta {
        Some(t) => parse::values(t)
            .map_err(|e| anyhow::anyhow!("--view-theta {e}"))?
            .into_iter()
            .map(|t| (t, args.view_phi))
            .collect(),
        None if !args.view.is_empty() => args.view.clone(),
        None => bail!("give the views with --view THETA,PHI (repeatable) or --view-theta FROM:TO:STEP"),
    };
    let rows = lambdas.len().saturating_mul(views.len());
    if rows > parse::MAX_VALUES {
        bail!("{} wavelengths × {} views is {rows} rows (at most {})", lambdas.len(), views.len(), parse::MAX_VALUES);
    }
    let queries: Vec<Query> = lambdas
        .iter()
        .flat_map(|&lambda_nm| {
            views.iter().map(move |&(theta_r, phi_r)| Query {
                lambda_nm,
                theta_i: args.light.light_theta,
                phi_i: args.light.light_phi,
                theta_r,
                phi_r,
            })
        })
        .collect();
    let mut acc = args.material.settings("brdf", &BRDF_SETTINGS)?;
    if let Some(radius_deg) = args.light.light_radius_deg {
        let explicit = args.material.patch.coherence_um;
        acc.coherence_um = crate::cli::args::coherence_of_light(radius_deg, explicit, "--light-radius-deg")?;
    }
    let method = args.method.unwrap_or(if args.gpu { MethodArg::Taylor } else { MethodArg::Exact });
    let evaluator = match (args.gpu, method) {
        (true, MethodArg::Taylor) => Evaluator::Gpu,
        (true, _) => bail!("--gpu evaluates the Taylor sum; use --method taylor (or leave --method out)"),
        (false, MethodArg::Exact) => Evaluator::Cpu(Method::Exact),
        (false, MethodArg::Taylor) => Evaluator::Cpu(Method::Taylor),
        (false, MethodArg::TaylorF32) => Evaluator::Cpu(Method::TaylorF32),
    };
    // Every refusal comes before the device is opened (a machine without one still hears why).
    let prepared = crate::reference::brdf::prepare(&hf, &queries, evaluator, &acc)?;
    let ctx = match evaluator {
        Evaluator::Gpu => Some(crate::gpu::vk::Context::new(&gpu.context_desc())?),
        Evaluator::Cpu(_) => None,
    };
    let evaluation = prepared.run(ctx.as_ref())?;
    if let Some(plan) = &evaluation.plan {
        errln!("note: {}", plan.describe());
        if !plan.f32_suffices() && matches!(evaluator, Evaluator::Gpu | Evaluator::Cpu(Method::TaylorF32)) {
            errln!("warning: f32 cannot reach the tolerance here (see the note); these rows carry that error");
        }
    }
    write_csv(&hf, &evaluation.samples)?;
    match ctx {
        Some(ctx) => {
            let log = ctx.validation();
            drop(ctx);
            Ok(crate::cli::validation_status(&log))
        }
        None => Ok(std::process::ExitCode::SUCCESS),
    }
}

fn write_csv(hf: &HeightField, samples: &[crate::physics::exact::Sample]) -> anyhow::Result<()> {
    csv_rows(hf, samples).map_err(|e| anyhow::anyhow!(crate::io::stream::failed("standard output", &e)))
}

/// The CSV of [`write_csv`] on stdout (the warning above it on stderr).
fn csv_rows(hf: &HeightField, samples: &[crate::physics::exact::Sample]) -> std::io::Result<()> {
    let out_of_band = samples.iter().filter(|s| !s.in_band).count();
    if out_of_band > 0 {
        errln!(
            "note: {out_of_band} of {} rows ask for frequencies beyond what {:.4}×{:.4} µm pixels sample \
             (|u/λ| ≤ {:.3}/µm): their power is 0",
            samples.len(),
            hf.dx_um,
            hf.dy_um,
            0.5 / hf.dx_um.max(hf.dy_um)
        );
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    writeln!(out, "lambda_nm,theta_i_deg,phi_i_deg,theta_r_deg,phi_r_deg,u,v,w,power,reflectance,brdf_sr")?;
    for s in samples {
        let q = &s.query;
        let fields = [
            q.lambda_nm,
            q.theta_i,
            q.phi_i,
            q.theta_r,
            q.phi_r,
            s.uvw.x,
            s.uvw.y,
            s.uvw.z,
            s.power,
            s.reflectance,
            s.brdf_sr,
        ];
        let line: Vec<String> = fields.iter().map(|&x| crate::error::number(x)).collect();
        writeln!(out, "{}", line.join(","))?;
    }
    out.flush()
}

#[derive(Args, Debug)]
pub struct TermsArgs {
    #[command(flatten)]
    pub heightfield: HeightFieldArgs,
    /// Shortest wavelength in use, nm
    #[arg(value_parser = parse::finite, long, default_value_t = 380.0)]
    pub lambda_min: f64,
    /// Largest |w| in use (2 covers every pair of directions)
    #[arg(value_parser = parse::finite, long, default_value_t = 2.0)]
    pub w_max: f64,
    /// Also run the precomputation (Taylor terms and baked table) and report its time
    #[arg(long)]
    pub compute: bool,
    #[command(flatten)]
    pub material: MaterialArgs,
}

pub fn terms(args: &TermsArgs) -> anyhow::Result<()> {
    let hf = args.heightfield.load()?;
    if !(args.w_max > 0.0 && args.w_max <= 2.0) {
        bail!("--w-max must lie in (0, 2]");
    }
    if !(args.lambda_min.is_finite() && (100.0..=10_000.0).contains(&args.lambda_min)) {
        bail!("--lambda-min must lie between 100 and 10000 nm");
    }
    let (lx, ly) = hf.size_um();
    let acc = args.material.settings("terms", &TERMS_SETTINGS)?;
    let window = CoherenceWindow::new(lx, ly, acc.coherence_um, acc.window_radius)?;
    let gain = crate::physics::exact::window_gain(&window, &hf);
    let plan = crate::physics::taylor::TaylorPlan::new(
        args.lambda_min * 1e-3,
        args.w_max,
        &crate::physics::taylor::HeightStats::of(&hf),
        gain,
        acc.tolerance,
        acc.order,
    )?;
    let (lo, hi) = hf.range();
    outln!("patch: {}×{} pixels of {:.4}×{:.4} µm = {:.3}×{:.3} µm", hf.nx, hf.ny, hf.dx_um, hf.dy_um, lx, ly);
    outln!("heights: {lo:.4}..{hi:.4} µm, mean {:.4} µm, max |h − mean| {:.4} µm", hf.mean(), hf.max_deviation());
    outln!(
        "window: σ = {:.4}×{:.4} bins (coherence {} µm), weight sum up to {gain:.3}",
        window.sigma_x,
        window.sigma_y,
        acc.coherence_um
    );
    let (gx, gy, spacing) = crate::material::dominant_grating(&hf);
    if spacing > 0.0 {
        outln!("dominant spacing: {spacing:.4} µm along ({gx:.3}, {gy:.3}) (what the gem approach uses)");
    }
    outln!("{}", plan.describe());
    let mib = (plan.order + 1) as f64 * (hf.nx * hf.ny) as f64 * 8.0 / (1 << 20) as f64;
    outln!("GPU texture: {} RG32F layers, {mib:.1} MiB", plan.order + 1);
    if args.compute {
        let start = std::time::Instant::now();
        crate::physics::taylor::TaylorTerms::compute(&hf, plan.order, None)?;
        outln!("precomputed {} terms in {:.1} ms", plan.order + 1, start.elapsed().as_secs_f64() * 1e3);
    }
    // The table `view` and rendered sequences use: any light and view, as fine as the lobes within 256 MiB.
    let request = crate::material::Reach::ANY.table_request();
    let table = crate::physics::baked::TablePlan::new(&hf, acc.coherence_um, &request, acc.table_tolerance)?;
    outln!("any light and view: {}", table.describe());
    if args.compute {
        let start = std::time::Instant::now();
        let (built, cached) = crate::physics::baked::load_or_build(&hf, &table, None)?;
        let how = if cached { "loaded from the cache" } else { "built" };
        outln!(
            "{how} the baked table in {:.1} ms: {}",
            start.elapsed().as_secs_f64() * 1e3,
            built.certificate.describe()
        );
        crate::physics::baked::check_certificate(&built, acc.strict_table)?;
    }
    Ok(())
}
