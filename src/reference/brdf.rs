//! The BRDF at chosen wavelengths and pairs of directions by any of the four ways diffract evaluates P, and the
//! refusals they share, so that `diffract brdf` and the extremes grid (`tests/extremes.rs`) take the same path:
//! - [`Method::Exact`]: the DFT of exp(i·k·w·h) itself, in f64 (no series): defined everywhere;
//! - [`Method::Taylor`]: the precomputed Taylor terms summed in f64; refused where its own rounding exceeds the
//!   tolerance (model.md §2.3);
//! - [`Method::TaylorF32`] and [`Evaluator::Gpu`]: the same sum in f32 (CPU emulation, or the shaders' code on the
//!   device); refused where f32 cannot reach the tolerance unless the caller accepts that error, and the GPU also
//!   where the full window has more taps than the shaders take.
//!
//! Every evaluation ends in finite values or in an error naming why it was refused.

use crate::error::{number, Error, Result};
use crate::material::Settings;
use crate::physics::coherence::{CoherenceWindow, Lookup};
use crate::physics::exact::{Method, Query, Reference, Sample};
use crate::physics::heightfield::HeightField;
use crate::physics::taylor::TaylorPlan;
use crate::physics::taylor::F64_UNIT_ROUNDOFF;

/// Where and how P is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Evaluator {
    /// On the CPU, by a [`Method`].
    Cpu(Method),
    /// The Taylor sum in f32 by the compute shader (`glsl/brdf_eval.comp.glsl`).
    Gpu,
}

impl Evaluator {
    /// Every evaluator, the reference first.
    pub const ALL: [Evaluator; 4] = [
        Evaluator::Cpu(Method::Exact),
        Evaluator::Cpu(Method::Taylor),
        Evaluator::Cpu(Method::TaylorF32),
        Evaluator::Gpu,
    ];

    /// The name users type (`--method …`, or `--gpu`).
    pub fn name(self) -> &'static str {
        match self {
            Evaluator::Cpu(Method::Exact) => "exact",
            Evaluator::Cpu(Method::Taylor) => "taylor",
            Evaluator::Cpu(Method::TaylorF32) => "taylor-f32",
            Evaluator::Gpu => "gpu",
        }
    }
}

/// The values, and what the evaluation used (for the user's notes).
pub struct Evaluation {
    pub samples: Vec<Sample>,
    /// The Taylor plan (None for exact).
    pub plan: Option<TaylorPlan>,
}

/// Evaluates `queries` on `hf` with `evaluator`; `gpu` is the device for [`Evaluator::Gpu`].
pub fn evaluate(
    hf: &HeightField,
    queries: &[Query],
    evaluator: Evaluator,
    accuracy: &Settings,
    gpu: Option<&crate::gpu::vk::Context>,
) -> Result<Evaluation> {
    prepare(hf, queries, evaluator, accuracy)?.run(gpu)
}

/// An evaluation that passed every check: what [`Prepared::run`] needs, nothing computed yet.
pub struct Prepared<'a> {
    hf: &'a HeightField,
    queries: &'a [Query],
    evaluator: Evaluator,
    accuracy: Settings,
    window: CoherenceWindow,
    /// The Taylor plan (None for exact).
    plan: Option<TaylorPlan>,
}

/// Checks an evaluation before any work (or device) is spent on it: the queries, the window, and for the Taylor
/// evaluators the plan and its refusals (f64 or f32 rounding; the GPU's window limit).
pub fn prepare<'a>(
    hf: &'a HeightField,
    queries: &'a [Query],
    evaluator: Evaluator,
    accuracy: &Settings,
) -> Result<Prepared<'a>> {
    for q in queries {
        q.check()?;
    }
    let (lx, ly) = hf.size_um();
    let window = CoherenceWindow::new(lx, ly, accuracy.coherence_um, accuracy.window_radius)?;
    let plan = match evaluator {
        Evaluator::Cpu(Method::Exact) => None,
        _ => Some(Reference::plan_for(hf, &window, queries, accuracy.tolerance, accuracy.order)?),
    };
    match (evaluator, &plan) {
        (Evaluator::Cpu(Method::Taylor), Some(plan)) => refuse_unless_f64_suffices(plan)?,
        (Evaluator::Cpu(Method::TaylorF32) | Evaluator::Gpu, Some(plan)) => {
            refuse_unless_f32_suffices(plan, accuracy.accept_f32_error)?
        }
        _ => {}
    }
    let radius = window.radius_x.max(window.radius_y);
    let limit = crate::material::MAX_WINDOW_RADIUS;
    if evaluator == Evaluator::Gpu && radius > i64::from(limit) {
        return Err(Error::setting(
            "window_radius",
            format!(
            "--gpu: this patch's full window has {radius} taps either side of the nearest bin and the shaders take \
             at most {limit}; pass --window-radius R (R ≤ {limit}) to evaluate a truncated window"
        ),
        ));
    }
    Ok(Prepared { hf, queries, evaluator, accuracy: *accuracy, window, plan })
}

impl Prepared<'_> {
    /// Evaluates; `gpu` is the device for [`Evaluator::Gpu`]. Non-finite values are refused.
    pub fn run(self, gpu: Option<&crate::gpu::vk::Context>) -> Result<Evaluation> {
        let samples = match self.evaluator {
            Evaluator::Cpu(method) => {
                Reference::new(self.hf, self.window, method, self.plan)?.evaluate(self.queries)?
            }
            Evaluator::Gpu => {
                let ctx = gpu.ok_or_else(|| Error::Invalid("the GPU evaluation needs a Vulkan device".into()))?;
                self.run_gpu(ctx)?
            }
        };
        refuse_non_finite(&samples)?;
        Ok(Evaluation { samples, plan: self.plan })
    }

    /// The compute shader's Taylor sum, with the window the CPU methods use.
    fn run_gpu(&self, ctx: &crate::gpu::vk::Context) -> Result<Vec<Sample>> {
        let (hf, accuracy) = (self.hf, &self.accuracy);
        let plan = self.plan.ok_or_else(|| Error::Invalid("the GPU evaluation needs a Taylor plan".into()))?;
        let settings = Settings {
            order: Some(plan.order),
            window_radius: Some(self.window.radius_x.max(self.window.radius_y) as u32),
            accept_f32_error: true,
            ..*accuracy
        };
        let material =
            crate::material::Material::prepare(hf, settings, &crate::material::Reach::Hemisphere { footprint: 0.0 })?;
        let values = crate::render::diffraction::evaluate_brdf(ctx, &material, self.queries)?;
        let (lx, ly) = hf.size_um();
        Ok(self
            .queries
            .iter()
            .zip(values)
            .map(|(q, (power, reflectance))| {
                let uvw = q.uvw();
                let in_band = Lookup::new(uvw.x, uvw.y, q.lambda_nm * 1e-3, lx, ly).in_band(hf.nx, hf.ny);
                Sample::new(*q, power, reflectance, in_band, &self.window)
            })
            .collect())
    }
}

/// The f64 Taylor method where its own rounding stays below the tolerance; otherwise a refusal that names the
/// method that can (exact: no series, no cancellation).
pub(crate) fn refuse_unless_f64_suffices(plan: &TaylorPlan) -> Result<()> {
    if plan.f64_suffices() {
        return Ok(());
    }
    Err(Error::Precision(format!(
        "the f64 Taylor sum cannot reach the tolerance here: at N = {} for x_max = {:.1} its terms grow to about \
         {:.0e} before they cancel (f64 rounding about {:.0e} > {:.0e}); use --method exact, which sums exp(i·k·w·h) \
         itself",
        plan.order,
        plan.x_max,
        plan.f64_error / (2.0 * F64_UNIT_ROUNDOFF),
        plan.f64_error,
        plan.tolerance
    )))
}

/// The f32 sums (GPU and its CPU emulation) as `map` treats them: refused where f32 cannot reach the tolerance,
/// unless the caller accepts the error.
pub(crate) fn refuse_unless_f32_suffices(plan: &TaylorPlan, accept: bool) -> Result<()> {
    if plan.f32_suffices() || accept {
        return Ok(());
    }
    Err(Error::Precision(format!(
        "f32 sums cannot reach the tolerance for this patch (N = {} for x_max = {:.1}: f32 rounding about {:.1e} > \
         {:.0e}); use --method exact or taylor (f64), raise --tolerance, or pass --accept-f32-error",
        plan.order, plan.x_max, plan.f32_error, plan.tolerance
    )))
}

/// Non-finite values are refused as a whole: nothing is printed from an overflowed sum.
fn refuse_non_finite(samples: &[Sample]) -> Result<()> {
    let finite = |s: &&Sample| s.power.is_finite() && s.reflectance.is_finite() && s.brdf_sr.is_finite();
    match samples.iter().find(|s| !finite(s)) {
        None => Ok(()),
        Some(s) => Err(Error::Precision(format!(
            "{} of {} values are not finite numbers (an f32 sum overflowed; the first at λ = {} nm, θ_r = {}°); \
             nothing was printed — use --method exact",
            samples.iter().filter(|s| !finite(s)).count(),
            samples.len(),
            number(s.query.lambda_nm),
            number(s.query.theta_r)
        ))),
    }
}
