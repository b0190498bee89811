//! A patch prepared for the GPU under a material's settings (`settings.rs` holds the settings and the approaches;
//! model.md §3): what views it must serve ([`Reach`]) and the prepared [`Material`] — Taylor terms or the baked
//! table, plan, window, wavelength sampling, the environment's moments and the uniform block `DiffractionParams`
//! of `glsl/include/params.glsl`. The thesis's four approaches are specialization constants of one shader (term
//! count, wavelength count, window radius, approach), the baked table a second build of the same shaders (`BAKED`):
//! [`Material::spec_constants`].

use std::time::Instant;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::gpu::interface::DiffractionParams;
use crate::io::progress::Progress;
use crate::light::prefilter::{Moments, Quadrature};
use crate::material::{Approach, Settings, MAX_WINDOW_RADIUS};
use crate::physics::baked;
use crate::physics::baked::{BakedTable, Domain, TablePlan, TableRequest};
use crate::physics::coherence::CoherenceWindow;
use crate::physics::exact::window_gain;
use crate::physics::heightfield::HeightField;
use crate::physics::spectrum;
use crate::physics::spectrum::Sampling;
use crate::physics::taylor::{HeightStats, TaylorPlan, TaylorTerms};

/// The views a material must serve: what sizes its Taylor plan (the largest |w|) and its baked table (the box of
/// (u, v, w) and the smallest pixel footprint).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reach {
    /// Light and views anywhere above the surface, by pixels whose footprint in (u, v) is at least `footprint`
    /// (0: as fine as the lobes).
    Hemisphere { footprint: f64 },
    /// A BRDF map of `size` pixels across the hemisphere of views, under `light` (unit, patch frame); `filtered`:
    /// each pixel is averaged over its footprint (else it reads its centre's value).
    Map { light: DVec3, size: u32, filtered: bool },
    /// What a frame shows: the box of its (u, v, w) and its smallest footprint.
    Seen { domain: Domain, footprint: f64 },
}

impl Reach {
    /// Any light and view, at any footprint down to the lobes' width.
    pub const ANY: Reach = Reach::Hemisphere { footprint: 0.0 };

    /// The largest |w| the views reach.
    pub fn w_max(&self) -> f64 {
        match self {
            Reach::Hemisphere { .. } => 2.0,
            Reach::Map { light, .. } => 1.0 + light.z,
            Reach::Seen { domain, .. } => -domain.w.0,
        }
    }

    /// What a baked table for these views must cover.
    pub fn table_request(&self) -> TableRequest {
        match *self {
            Reach::Hemisphere { footprint } => TableRequest {
                domain: Domain::HEMISPHERE,
                footprint,
                aligned: false,
                centres_only: false,
                segments: None,
                mass_only: false,
            },
            Reach::Map { light, size, filtered } => TableRequest {
                domain: Domain::map(light),
                footprint: 2.0 / f64::from(size.max(1)),
                aligned: true,
                centres_only: !filtered,
                segments: None,
                mass_only: false,
            },
            Reach::Seen { domain, footprint } => TableRequest {
                domain,
                footprint,
                aligned: false,
                centres_only: false,
                segments: None,
                mass_only: false,
            },
        }
    }
}

/// The window weight at which the default render window stops (the first tap left out weighs less).
pub(crate) const RENDER_WINDOW_CUTOFF: f64 = 1e-3;
/// Most wavelengths one pixel may sample (a 1 nm step over 380–780 nm is 401).
pub const MAX_LAMBDA_COUNT: usize = 4001;
/// The widest coherence window (σ in DFT bins) under which NMM, PQ and gem stay approximations of a few ΔE00: they
/// assume light coherent across the patch (one wavelength per bin crossed, an exact periodic tiling, sharp orders).
/// Measured on the Elaphe scan's 24² map against the exact reference: at σ = 1 bin mean ΔE00 1.0 (NMM), 4.0 (PQ),
/// 4.6 (gem); at σ = 4 bins (1 µm coherence) 9, 28 and 22 (`tests/extremes.rs`).
pub const APPROXIMATION_MAX_SIGMA_BINS: f64 = 1.0;
/// Efficiency of each non-zero order in Stam's analytic grating (his GPU Gems shader scales orders by 0.1).
pub const GEM_ORDER_EFFICIENCY: f32 = 0.1;

/// A patch prepared for one approach and its settings.
pub struct Material {
    pub settings: Settings,
    pub nx: usize,
    pub ny: usize,
    /// The Taylor plan (None for gem).
    pub plan: Option<TaylorPlan>,
    pub window: CoherenceWindow,
    pub sampling: Sampling,
    /// F_0..=F_N as interleaved f32 (re, im), layer after layer; one zero layer for gem.
    pub texels: Vec<f32>,
    pub layers: u32,
    pub params: DiffractionParams,
    /// The baked approach's table, its plan, and how long it took to build or load (ms; from the cache?).
    pub table: Option<BakedTable>,
    pub table_plan: Option<TablePlan>,
    pub table_ms: f64,
    pub table_cached: bool,
    /// The BRDF's moments against the environment's light (`light::prefilter`): where a scene's environment
    /// diffracts (set by [`Material::prepare_moments`]).
    pub moments: Option<Moments>,
}

impl Material {
    /// Precomputes what `settings.approach` needs of `hf` for the views of `reach`.
    pub fn prepare(hf: &HeightField, settings: Settings, reach: &Reach) -> Result<Self> {
        let s = settings;
        let sampling = checked_sampling(&s)?;
        let window = render_window(hf, &s)?;
        let (plan, texels, mut layers) = if s.approach.uses_terms() {
            let (plan, texels) = taylor_texels(hf, &s, &window, reach.w_max())?;
            (Some(plan), texels, plan.order as u32 + 1)
        } else if s.approach == Approach::Baked {
            (None, Vec::new(), 0)
        } else {
            (None, vec![0.0; hf.nx * hf.ny * 2], 1)
        };
        let baked = if s.approach == Approach::Baked { Some(Baked::prepare(hf, &s, reach)?) } else { None };
        if let Some(b) = &baked {
            layers = b.table.layers() as u32;
        }
        let (lx, ly) = hf.size_um();
        let sigma_s = s.coherence_um / 4.0;
        let sigma_f = 1.0 / (2.0 * std::f64::consts::PI * sigma_s);
        let (gx, gy, spacing) = if s.approach == Approach::Gem { dominant_grating(hf) } else { (1.0, 0.0, 0.0) };
        let params = DiffractionParams {
            // (w: the baked table's segments of w.)
            patch_px: [
                hf.nx as i32,
                hf.ny as i32,
                layers as i32,
                baked.as_ref().map_or(1, |b| b.table.grid.segments as i32),
            ],
            patch_um: [lx as f32, ly as f32, hf.dx_um as f32, hf.dy_um as f32],
            window: [
                window.sigma_x as f32,
                window.sigma_y as f32,
                sigma_f as f32,
                if crate::light::lamp::follows_light(s.coherence_um) { s.coherence_um as f32 } else { 0.0 },
            ],
            spectral: [
                sampling.lambda_min_nm as f32,
                sampling.step_nm as f32,
                sampling.y_norm() as f32,
                spectrum::y_norm_continuous(s.illuminant) as f32,
            ],
            light: [0.0, 0.0, 1.0, 0.0],
            pq: [(s.coherence_um / lx).ceil().max(1.0) as f32, (s.coherence_um / ly).ceil().max(1.0) as f32, 0.0, 0.0],
            gem: [gx as f32, gy as f32, spacing as f32, GEM_ORDER_EFFICIENCY],
            // The exposure a window applies (0 EV here; the viewer sets its own).
            display: [1.0, 0.0, 0.0, 0.0],
            table_uv: baked.as_ref().map_or([0.0; 4], |b| b.uv),
            table_w: baked.as_ref().map_or([0.0; 4], |b| b.w),
            // The pigment's white, and (w) the diffraction's gain: 1 in relative units, the physical factor under a
            // physical light (`spectrum::diffraction_gain`).
            light_white: spectrum::white_rgb(s.illuminant)
                .as_vec3()
                .extend(spectrum::diffraction_gain(&sampling, s.coherence_um) as f32)
                .to_array(),
        };
        let (table, table_plan, table_ms, table_cached) = match baked {
            Some(b) => (Some(b.table), Some(b.plan), b.ms, b.cached),
            None => (None, None, 0.0, false),
        };
        let material = Self {
            settings,
            nx: hf.nx,
            ny: hf.ny,
            plan,
            window,
            sampling,
            texels,
            layers,
            params,
            table,
            table_plan,
            table_ms,
            table_cached,
            moments: None,
        };
        if let Some(caveat) = material.caveat() {
            log::warn!("{caveat}");
        }
        Ok(material)
    }

    /// Tabulates the moments of `hf`'s BRDF under these settings (`light::prefilter::Moments`), from a table for every
    /// pair of directions with texels of `light::prefilter::MOMENT_TEXEL` (built or read from the cache like any
    /// other). The light must be in physical units.
    pub fn prepare_moments(&mut self, hf: &HeightField) -> Result<()> {
        self.moments = Some(moments_of(hf, &self.settings)?);
        Ok(())
    }

    /// Where the approach's own assumption fails for this patch and coherence length (so that its colours are off
    /// by more than its usual error), or its baked table misses its tolerance, the reason in one line; None where
    /// it holds. FLSS and baked model partial coherence and carry no caveat of the first kind.
    pub fn caveat(&self) -> Option<String> {
        if let Some(m) = self.table.as_ref().and_then(baked::shortfall) {
            return Some(format!("{m}; {}", baked::TABLE_SHORTFALL_HINT));
        }
        let approach = self.settings.approach;
        if !matches!(approach, Approach::Nmm | Approach::Pq | Approach::Gem) {
            return None;
        }
        let sigma = self.window.sigma_x.max(self.window.sigma_y);
        (sigma > APPROXIMATION_MAX_SIGMA_BINS).then(|| {
            format!(
                "{} assumes light coherent across the patch, but a coherence length of {} µm blurs its spectrum over \
                 σ = {sigma:.1} DFT bins (its assumption holds to about {APPROXIMATION_MAX_SIGMA_BINS}): expect colour \
                 errors of several ΔE00 (up to ~25 at σ = 4); flss and baked model partial coherence",
                approach.name(),
                crate::error::number(self.settings.coherence_um)
            )
        })
    }

    /// Specialization constants: TERMS (Taylor layers, or the baked table's Chebyshev terms), WINDOW_RADIUS,
    /// LAMBDA_COUNT, APPROACH, DISPLAY_OUTPUT.
    pub fn spec_constants(&self, display_output: bool) -> crate::gpu::vk::SpecConstants {
        let terms = self.table.as_ref().map_or(self.layers, |t| t.terms as u32);
        use crate::gpu::interface::{
            SPEC_APPROACH, SPEC_DISPLAY_OUTPUT, SPEC_LAMBDA_COUNT, SPEC_TERMS, SPEC_WINDOW_RADIUS,
        };
        crate::gpu::vk::SpecConstants::default()
            .u32(SPEC_TERMS, terms)
            .i32(SPEC_WINDOW_RADIUS, self.window.radius_x.max(self.window.radius_y) as i32)
            .u32(SPEC_LAMBDA_COUNT, self.sampling.count as u32)
            .u32(SPEC_APPROACH, self.settings.approach.id())
            .u32(SPEC_DISPLAY_OUTPUT, u32::from(display_output))
    }

    /// Sets the exposure and the tone curve a shader that writes display values applies (a window's; 0 EV and
    /// clip as prepared).
    pub fn set_display(&mut self, exposure_ev: f64, tone: crate::display::Tone) {
        self.params.display = crate::display::tone::display_uniform(exposure_ev, tone);
    }

    /// One line on the baked table (its plan, and how long it took), for the commands' reports.
    pub fn table_line(&self) -> Option<String> {
        let (plan, table) = (self.table_plan.as_ref()?, self.table.as_ref()?);
        let how = if self.table_cached { "loaded from the cache" } else { "built" };
        Some(format!(
            "{}; {how} in {:.0} ms ({}; {})",
            plan.describe(),
            self.table_ms,
            table.report,
            table.certificate.describe()
        ))
    }
}

/// The moments of `hf`'s BRDF under `settings`' coherence length and table tolerance (their light is the basis',
/// whatever `settings` names): from a baked table per band of the basis, for every pair of directions with texels
/// of `MOMENT_TEXEL` (built, or read from the cache), on a `MOMENT_GRID`² grid, by the fast quadrature
/// (`light::prefilter::Quadrature::FAST`).
pub fn moments_of(hf: &HeightField, settings: &Settings) -> Result<Moments> {
    moments_by(hf, settings, &crate::light::prefilter::Quadrature::FAST)
}

/// [`moments_of`] integrated by `quadrature` (the fast one, or the careful one to measure it against).
pub fn moments_by(hf: &HeightField, settings: &Settings, quadrature: &Quadrature) -> Result<Moments> {
    use crate::light::prefilter::{basis, key_tail, MOMENTS_VERSION, MOMENT_GRID, MOMENT_TEXEL};
    use crate::physics::baked::load_or_build_bands;
    // Texels of MOMENT_TEXEL (a table's texel is a footprint over √3: `TablePlan::size_grid`).
    // One segment of w: the moments read every texel once, so fewer layers a read would save nothing.
    let request = TableRequest {
        segments: Some(1),
        mass_only: quadrature.mass_only,
        ..Reach::Hemisphere { footprint: MOMENT_TEXEL * 3f64.sqrt() }.table_request()
    };
    // The first band's plan (its estimate of the terms in w, a second or so) serves the others, under their light.
    let lights = basis();
    let mut first = TablePlan::new_under(hf, settings.coherence_um, &request, settings.table_tolerance, lights[0])?;
    first.lambda_step_nm = quadrature.lambda_step_nm;
    let mut plans = Vec::new();
    let mut gains = Vec::new();
    for illuminant in lights {
        plans.push(if illuminant == first.illuminant { first.clone() } else { first.for_light(hf, illuminant)? });
        // Binned weights are normalised as the 1 nm tables' (`Sampling::binned_weights`): so is the gain.
        let step = if quadrature.mass_only { 1.0 } else { quadrature.lambda_step_nm };
        let sampling = Sampling::visible_under(step, illuminant);
        gains.push(crate::light::sampling::env_gain(&sampling, settings.coherence_um)?);
    }
    // The bands share their nodes in w (the most any needs), so that one pass builds the three tables.
    let most = plans.iter().map(|plan| plan.nodes.count).max().unwrap_or(2);
    for plan in &mut plans {
        *plan = plan.with_nodes_at_least(hf, most)?;
    }
    // Cached beside the tables: keyed by their plans and everything below.
    let mut p = crate::io::cache::PlanBytes::default();
    for (plan, gain) in plans.iter().zip(&gains) {
        p.0.extend(crate::physics::baked::cache::table_identity(hf, plan));
        p.f64(*gain);
    }
    key_tail(&mut p, quadrature);
    let stamp =
        crate::io::cache::Stamp { kind: "moments", what: "environment moments", version: MOMENTS_VERSION, plan: p.0 };
    let dir = crate::io::cache::default_dir();
    let cached = dir.as_deref().and_then(|dir| {
        let bytes = crate::io::cache::load(dir, &stamp, (MOMENT_GRID * MOMENT_GRID * 90 * 8 + 8) as u64)?;
        Moments::from_bytes(&bytes).filter(|m| m.grid == MOMENT_GRID)
    });
    if let Some(moments) = cached {
        return Ok(moments);
    }
    let bar = crate::io::progress::Progress::new("the environment's moments", 2);
    bar.detail("baking the spectral bands in one pass");
    let start = std::time::Instant::now();
    let tables: Vec<_> = load_or_build_bands(hf, &plans)?.into_iter().zip(gains).collect();
    bar.step();
    let baked = start.elapsed();
    bar.detail(format!("integrating over {MOMENT_GRID}² views"));
    let moments = Moments::new(
        &[(&tables[0].0, tables[0].1), (&tables[1].0, tables[1].1), (&tables[2].0, tables[2].1)],
        MOMENT_GRID,
        quadrature.blocks,
    );
    bar.step();
    bar.finish();
    // A timed line whether or not the bar was drawn (a log gets no bar): the step is seconds long.
    log::info!(
        target: crate::io::LOG_PLAIN,
        "the environment's moments: {} band tables in {:.1} s, {MOMENT_GRID}² views in {:.1} s{}",
        tables.len(),
        baked.as_secs_f64(),
        (start.elapsed() - baked).as_secs_f64(),
        if dir.is_some() { " (cached for later runs)" } else { " (no cache: computed again next run)" }
    );
    if let Some(dir) = dir.as_deref() {
        // A cache that cannot be written costs time, not correctness.
        if let Err(e) =
            std::fs::create_dir_all(dir).and_then(|()| crate::io::cache::store(dir, &stamp, &moments.to_bytes()))
        {
            log::warn!("could not cache the environment moments in {}: {e}", dir.display());
        }
    }
    Ok(moments)
}

/// The wavelengths of `s`'s step, refused when the step or the window radius is out of range.
fn checked_sampling(s: &Settings) -> Result<Sampling> {
    if !(s.lambda_step_nm.is_finite() && s.lambda_step_nm > 0.0) {
        return Err(Error::setting(
            "lambda_step_nm",
            format!("the wavelength step must be positive, got {} nm", crate::error::number(s.lambda_step_nm)),
        ));
    }
    let sampling = Sampling::visible_under(s.lambda_step_nm, s.illuminant);
    if sampling.count > MAX_LAMBDA_COUNT {
        return Err(Error::setting(
            "lambda_step_nm",
            format!("a {} nm step gives {} wavelengths (at most {MAX_LAMBDA_COUNT})", s.lambda_step_nm, sampling.count),
        ));
    }
    if s.window_radius.is_some_and(|r| r > MAX_WINDOW_RADIUS) {
        return Err(Error::setting("window_radius", format!("the window radius is at most {MAX_WINDOW_RADIUS}")));
    }
    Ok(sampling)
}

/// The coherence window the shaders sum over: `s`'s radius, or the smallest that keeps the taps left out below
/// [`RENDER_WINDOW_CUTOFF`].
fn render_window(hf: &HeightField, s: &Settings) -> Result<CoherenceWindow> {
    let (lx, ly) = hf.size_um();
    let full = CoherenceWindow::new(lx, ly, s.coherence_um, None)?;
    let radius = s.window_radius.unwrap_or_else(|| {
        let r = |sigma: f64| ((-2.0 * RENDER_WINDOW_CUTOFF.ln()).sqrt() * sigma - 0.5).ceil().max(0.0) as u32;
        r(full.sigma_x).max(r(full.sigma_y)).min(MAX_WINDOW_RADIUS)
    });
    CoherenceWindow::new(lx, ly, s.coherence_um, Some(radius))
}

/// The Taylor plan for views up to `w_max` and its terms as f32 texels; refused where the GPU's f32 sums cannot
/// reach the tolerance, unless `s` accepts it.
fn taylor_texels(
    hf: &HeightField,
    s: &Settings,
    window: &CoherenceWindow,
    w_max: f64,
) -> Result<(TaylorPlan, Vec<f32>)> {
    let gain = window_gain(window, hf);
    let plan = TaylorPlan::new(VISIBLE_MIN_UM, w_max, &HeightStats::of(hf), gain, s.tolerance, s.order)?;
    if !plan.f32_suffices() && !s.accept_f32_error {
        return Err(Error::Precision(format!(
            "the GPU's f32 sums cannot reach the tolerance for this patch ({}); raise --tolerance, lower the heights, \
             or pass --accept-f32-error",
            plan.describe()
        )));
    }
    let terms = TaylorTerms::compute(hf, plan.order, None)?;
    Ok((plan, terms.to_f32_texels(plan.order)))
}

/// The baked approach's table (built, or read from the cache) and the parameters the shader reads it by.
struct Baked {
    table: BakedTable,
    plan: TablePlan,
    ms: f64,
    cached: bool,
    /// The table's (u0, v0, width, height) in direction space.
    uv: [f32; 4],
    /// The lower end of its w range, its segments per unit of w (`baked.glsl`'s `table_segment`), the texel size
    /// and the top mip level.
    w: [f32; 4],
}

impl Baked {
    fn prepare(hf: &HeightField, s: &Settings, reach: &Reach) -> Result<Self> {
        let request = TableRequest { segments: s.table_segments, ..reach.table_request() };
        let plan = TablePlan::new_under(hf, s.coherence_um, &request, s.table_tolerance, s.illuminant)?;
        let start = Instant::now();
        let bar = Progress::new("baking the colour table", 0);
        let (table, cached) = baked::load_or_build(hf, &plan, Some(&|done, total| bar.set(done, total)))?;
        bar.finish();
        // Refused here when strict; otherwise the material's caveat warns.
        if s.strict_table {
            baked::check_certificate(&table, true)?;
        }
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let g = table.grid;
        let length = g.w.1 - g.w.0;
        let uv = [g.u0 as f32, g.v0 as f32, (g.nu as f64 * g.texel) as f32, (g.nv as f64 * g.texel) as f32];
        let w = [
            g.w.0 as f32,
            if length > 0.0 { (g.segments as f64 / length) as f32 } else { 0.0 },
            g.texel as f32,
            (table.levels.len() - 1) as f32,
        ];
        Ok(Self { table, plan, ms, cached, uv, w })
    }
}

const VISIBLE_MIN_UM: f64 = spectrum::VISIBLE_MIN_NM * 1e-3;

/// The strongest non-DC frequency of the heights (largest |DFT(h)| bin): gem's grating direction (unit) and
/// spacing in µm. A flat patch has none (spacing 0).
pub fn dominant_grating(hf: &HeightField) -> (f64, f64, f64) {
    // A tiling's spectrum is its cell's on every T-th bin: the same frequencies, for the cost of one tile.
    let hf = &*hf.tiling_cell();
    let Ok(terms) = TaylorTerms::compute(hf, 1, None) else { return (1.0, 0.0, 0.0) };
    let f1 = &terms.layers[1];
    let (hx, hy) = ((hf.nx / 2) as i64, (hf.ny / 2) as i64);
    let (lx, ly) = hf.size_um();
    let mut best = (0.0, 0i64, 0i64);
    for (i, c) in f1.iter().enumerate() {
        let (jx, jy) = ((i % hf.nx) as i64 - hx, (i / hf.nx) as i64 - hy);
        // Half the spectrum: h is real, so bin −j mirrors bin j.
        if (jy, jx) <= (0, 0) {
            continue;
        }
        if c.norm() > best.0 {
            best = (c.norm(), jx, jy);
        }
    }
    if best.0 < 1e-12 {
        return (1.0, 0.0, 0.0);
    }
    let (fx, fy) = (best.1 as f64 / lx, best.2 as f64 / ly);
    let f = (fx * fx + fy * fy).sqrt();
    (fx / f, fy / f, 1.0 / f)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEMISPHERE: Reach = Reach::Hemisphere { footprint: 0.0 };

    #[test]
    fn gem_finds_the_period_and_direction_of_a_grating() {
        let (nx, ny, period) = (64, 8, 16);
        let h = (0..nx * ny)
            .map(|i| ((i / nx) as f64 * 0.0 + (std::f64::consts::TAU * (i % nx) as f64 / period as f64).cos()) * 0.1)
            .collect();
        let hf = HeightField::new(nx, ny, 0.1, 0.1, h).unwrap();
        let (gx, gy, d) = dominant_grating(&hf);
        assert!((gx.abs() - 1.0).abs() < 1e-12 && gy.abs() < 1e-12);
        assert!((d - 1.6).abs() < 1e-9, "{d}");
    }

    #[test]
    fn default_window_radius_follows_the_cutoff() {
        let hf = HeightField::new(650, 650, 0.1, 0.1, vec![0.0; 650 * 650]).unwrap();
        let m = Material::prepare(&hf, Settings::default(), &HEMISPHERE).unwrap();
        assert_eq!(m.window.radius_x, 2, "σ = 2/π bins needs ±2 taps for a 1e-3 cutoff");
        assert_eq!(m.layers, 1, "a flat patch needs one term");
        assert_eq!(m.sampling.count, 81);
    }

    #[test]
    fn f32_trouble_is_refused_unless_accepted() {
        let h: Vec<f64> = (0..64 * 64).map(|i| if (i % 64) < 32 { 0.0 } else { 1.5 }).collect();
        let hf = HeightField::new(64, 64, 0.1, 0.1, h).unwrap();
        let e = Material::prepare(&hf, Settings::default(), &HEMISPHERE).err().expect("refused");
        assert!(e.to_string().contains("f32"), "{e}");
        let accepted = Settings { accept_f32_error: true, ..Settings::default() };
        assert!(Material::prepare(&hf, accepted, &HEMISPHERE).is_ok());
    }
}
