//! The baked colour table: the spectrally integrated colour of a patch over (u, v), its dependence on w a Chebyshev
//! series, prefiltered into mip levels — the `baked` approach's few filtered fetches per pixel in place of FLSS's
//! tens of thousands. model.md §3.5 says what it stores, how it is built and how its degree in w is certified.
//!
//! This module plans a table ([`TablePlan`]: the (u, v, w) box the views produce, the smallest pixel footprint, the
//! degree the tolerance needs, at most [`MAX_TABLE_BYTES`], the segments of w) and holds it ([`BakedTable`], its
//! [`Grid`]); [`build`] builds it exactly in f64, [`degree`] estimates and certifies its degree, `sample` reads it
//! as the shaders do (their twin), `cache` keeps it verified on disk.

pub mod build;
pub mod cache;
pub mod degree;
mod lobes;
pub mod sample;

pub use degree::{Certificate, Estimate, Nodes};

pub use sample::FOOTPRINT_LOD_BIAS;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::physics::coherence::CoherenceWindow;
use crate::physics::heightfield::HeightField;
use crate::physics::illuminant::Illuminant;

/// GPU memory one material's table may take, with its mip levels.
pub const MAX_TABLE_BYTES: u64 = 256 << 20;
/// Default tolerance on the Chebyshev tail in w, relative to each texel's brightest value over w.
pub const DEFAULT_TABLE_TOLERANCE: f64 = 1e-4;
/// Colour below which nothing is seen (XYZ relative to a D65 mirror; at the +8 EV the AFM maps are shown with it
/// is 2.6·10⁻⁷): the tolerance's absolute floor and the weakest lobe the build keeps.
pub const INVISIBLE: f64 = 1e-10;
/// The wavelength step of the build, nm (the reference's).
pub const TABLE_LAMBDA_STEP_NM: f64 = 1.0;
/// Most Chebyshev terms in w (a structure needing more is far deeper than the wavelengths it is lit with).
pub const MAX_TERMS: usize = 64;
/// The wavelength step of the estimate of the degree, nm (the degree in w hardly depends on the spectral
/// sampling; the build's certificate is made at the table's own 1 nm).
pub(crate) const PROBE_LAMBDA_STEP_NM: f64 = 5.0;
/// Most sub-samples per texel axis on the coherent path.
pub const MAX_SUBSAMPLES: usize = 8;
/// Coefficients per texel of an RGBA32F layer.
pub(crate) const LAYER_CHANNELS: usize = 4;

/// The (u, v, w) a table covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain {
    pub u: (f64, f64),
    pub v: (f64, f64),
    pub w: (f64, f64),
}

impl Domain {
    /// Every pair of directions above the surface: |u|, |v| ≤ 2, −2 ≤ w ≤ 0.
    pub const HEMISPHERE: Domain = Domain { u: (-2.0, 2.0), v: (-2.0, 2.0), w: (-2.0, 0.0) };

    /// A BRDF map's views (the unit disk of ω_r.xy) under the light `light` (unit, patch frame).
    pub fn map(light: DVec3) -> Self {
        Self { u: (-light.x - 1.0, -light.x + 1.0), v: (-light.y - 1.0, -light.y + 1.0), w: (-light.z - 1.0, -light.z) }
    }

    /// A tiny box at normal reflection (the table of a material nothing shows).
    pub const POINT: Domain = Domain { u: (-0.01, 0.01), v: (-0.01, 0.01), w: (-2.0, -1.98) };

    /// The box widened by `margin` on every side, clipped to the hemisphere's.
    pub fn widened(&self, margin: f64) -> Self {
        let h = Self::HEMISPHERE;
        let grow = |(a, b): (f64, f64), (ha, hb): (f64, f64)| ((a - margin).max(ha), (b + margin).min(hb));
        Self { u: grow(self.u, h.u), v: grow(self.v, h.v), w: grow(self.w, h.w) }
    }

    /// The smallest box holding both.
    pub fn union(&self, other: &Self) -> Self {
        let join = |(a, b): (f64, f64), (c, d): (f64, f64)| (a.min(c), b.max(d));
        Self { u: join(self.u, other.u), v: join(self.v, other.v), w: join(self.w, other.w) }
    }

    /// The box of a set of (u, v, w) points, clipped to the hemisphere's; None for no points.
    pub fn bounding(points: impl IntoIterator<Item = DVec3>) -> Option<Self> {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in points.into_iter().filter(|p| p.is_finite()) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        if lo.x > hi.x {
            return None;
        }
        let h = Self::HEMISPHERE;
        let clip = |(a, b): (f64, f64), (ha, hb): (f64, f64)| (a.max(ha), b.min(hb).max(a.max(ha)));
        Some(Self { u: clip((lo.x, hi.x), h.u), v: clip((lo.y, hi.y), h.v), w: clip((lo.z, hi.z), h.w) })
    }
}

/// What a table must serve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableRequest {
    pub domain: Domain,
    /// The smallest pixel footprint the table will be sampled with, in (u, v) units (0: as fine as the lobes).
    pub footprint: f64,
    /// Pixel centres lie on a grid of this spacing starting half a pixel inside the domain (a BRDF map): the
    /// texels are then an odd fraction of a pixel, so that every pixel centre is a texel centre.
    pub aligned: bool,
    /// Aligned, and every read is a pixel centre's value (a map that is not filtered over each pixel's
    /// footprint): one texel per pixel holds it exactly, and finer texels would only be memory.
    pub centres_only: bool,
    /// Equal segments of w, each with its own series ([`Grid::segments`]); None: chosen by the plan
    /// ([`TablePlan::new`]: two where w spans more than 1.5 and they need fewer layers a read, within twice the
    /// memory of one).
    pub segments: Option<usize>,
    /// The table is only integrated further, against factors that change slowly across a texel (the
    /// environment's moments): its texels need hold only the mass of their light ([`TablePlan::mass_only`]), and
    /// the grid is the footprint's whatever the degree in w, so no estimate of the degree is made (the build
    /// certifies the degree it keeps, as always).
    pub mass_only: bool,
}

/// The texel grid: texel (a, b) covers u ∈ [u0 + a·texel, u0 + (a + 1)·texel) and likewise v; `w` is cut into
/// `segments` equal intervals, each mapped to t ∈ [−1, 1] and expanded in its own Chebyshev series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub u0: f64,
    pub v0: f64,
    pub texel: f64,
    pub nu: usize,
    pub nv: usize,
    pub w: (f64, f64),
    /// Equal intervals of `w`, each with its own series: segment s holds the table's layers s·L .. (s + 1)·L
    /// (L = the RGBA layers of its terms), so a read fetches L layers however many segments there are. A
    /// series over half the interval needs fewer terms (its coefficients fall like J_d(Ω·ρ), ρ the half-width:
    /// [`degree`]), at the price of the memory of every segment.
    pub segments: usize,
}

impl Grid {
    pub fn u_centre(&self, a: usize) -> f64 {
        self.u0 + (a as f64 + 0.5) * self.texel
    }

    pub fn v_centre(&self, b: usize) -> f64 {
        self.v0 + (b as f64 + 0.5) * self.texel
    }

    /// The segment of w and t ∈ [−1, 1] within it (clamped: the series is never extrapolated); the shader's
    /// `table_segment` does the same in f32.
    pub fn segment_of(&self, w: f64) -> (usize, f64) {
        let (w0, w1) = self.w;
        let n = self.segments.max(1);
        if w1 <= w0 {
            return (0, 0.0);
        }
        let x = ((w - w0) / (w1 - w0) * n as f64).clamp(0.0, n as f64);
        let segment = (x.floor() as usize).min(n - 1);
        (segment, (2.0 * (x - segment as f64) - 1.0).clamp(-1.0, 1.0))
    }

    /// The w-interval of `segment`.
    pub fn segment_w(&self, segment: usize) -> (f64, f64) {
        let (w0, w1) = self.w;
        let n = self.segments.max(1) as f64;
        let at = |i: usize| if i >= self.segments { w1 } else { w0 + (w1 - w0) * i as f64 / n };
        (at(segment), at(segment + 1))
    }

    /// w at t of a one-segment grid.
    pub fn w_of(&self, t: f64) -> f64 {
        debug_assert_eq!(self.segments, 1, "w_of maps one segment");
        let (w0, w1) = self.w;
        0.5 * (w0 + w1) + 0.5 * (w1 - w0) * t
    }

    /// Mip level sizes, level 0 first, down to 1×1 (Vulkan's rule: each level halves, rounding down).
    pub fn level_sizes(&self) -> Vec<(usize, usize)> {
        let mut sizes = vec![(self.nu, self.nv)];
        while let Some(&(w, h)) = sizes.last().filter(|&&(w, h)| w > 1 || h > 1) {
            sizes.push(((w / 2).max(1), (h / 2).max(1)));
        }
        sizes
    }

    /// Bytes of `terms` coefficients per channel and segment in RGBA32F layers, over every mip level.
    pub fn bytes(&self, terms: usize) -> u64 {
        let texels: u64 = self.level_sizes().iter().map(|&(w, h)| (w * h) as u64).sum();
        texels * (layers_for(terms) * self.segments) as u64 * (LAYER_CHANNELS * 4) as u64
    }
}

/// RGBA layers holding `terms` coefficients of X, Y and Z: coefficient d of channel c is scalar 3d + c.
pub(crate) fn layers_for(terms: usize) -> usize {
    (3 * terms).div_ceil(LAYER_CHANNELS)
}

/// How a table will be built, decided before the table's own work: the grid, the nodes in w the build samples,
/// and the degree estimated at every lobe centre (cached like the tables). The build certifies the degree it
/// keeps ([`BakedTable::certificate`]).
#[derive(Clone, Debug, PartialEq)]
pub struct TablePlan {
    /// The (u, v, w) the table must serve, and its grid.
    pub domain: Domain,
    pub grid: Grid,
    /// Chebyshev terms in w the grid is sized for: the estimate's (the most any segment's needs).
    pub terms: usize,
    pub estimate: Estimate,
    /// The nodes in w the build samples, and the bound on what they cannot see (over several segments: their
    /// count summed, the largest bound).
    pub nodes: Nodes,
    /// Each segment of w (`grid.segments` of them): its interval, nodes and estimate.
    pub segments: Vec<Segment>,
    pub tolerance: f64,
    /// Standard deviation in u of the intensity lobes at λ = 380 nm and 780 nm.
    pub lobe_width: (f64, f64),
    /// Pixels of the tiling cell, and whether the lobes are independent (tiling stride ≥ 10.5 window widths).
    pub cell: (usize, usize),
    pub lattice: bool,
    /// Texel-centre values (a map whose pixel centres are texel centres) instead of texel averages.
    pub point: bool,
    /// The texel the footprint asked for, when memory made the table coarser.
    pub coarsened_from: Option<f64>,
    /// The window (full: taps down to 10⁻¹⁷) in bins of the whole patch.
    pub window: CoherenceWindow,
    pub coherence_um: f64,
    /// The light's spectrum the table integrates under (its colours are XYZ relative to that white mirror).
    pub illuminant: Illuminant,
    /// The wavelength step of the build's spectral sums, nm: [`TABLE_LAMBDA_STEP_NM`] unless a table that is only
    /// integrated further (the environment's moments) asks for a coarser one.
    pub lambda_step_nm: f64,
    /// Whether a texel need only hold the mass of the light in it, not how it lies within (a table that is only
    /// integrated further against smooth factors: the environment's moments): sub-samples [`MASS_SPACING`] lobe
    /// widths apart instead of one.
    pub mass_only: bool,
}

/// The spacing of the sub-samples of a [`TablePlan::mass_only`] table, in lobe widths (standard deviations of
/// the narrowest intensity lobe): the samples of a Gaussian of standard deviation σ at spacing h sum to its
/// integral within 2·exp(−2π²σ²/h²) (Poisson's summation formula), 2·10⁻⁶ at h = 1.2σ. A lobe's light is then
/// counted whole, split between the texels it straddles in proportions a sub-sample or so off.
pub const MASS_SPACING: f64 = 1.2;

/// One segment of a table's w-interval ([`Grid::segments`]), planned like a table of its own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub w: (f64, f64),
    pub nodes: Nodes,
    pub estimate: Estimate,
}

/// Most segments of w a table may be cut into.
pub const MAX_SEGMENTS: usize = 8;
/// How much more memory than one segment's table the plan accepts for fewer layers a read when it chooses the
/// segments itself.
const SEGMENT_MEMORY_RATIO: f64 = 2.0;

/// The shortest w-interval `auto` tries to cut in two: three quarters of every view's (the any-view tables').
const SEGMENT_MIN_W: f64 = 1.5;

/// Tiling strides (in window widths σ) beyond which neighbouring lobes no longer interfere: their cross term
/// carries exp(−(T/σ)²/4) ≤ 10⁻¹².
pub(crate) const INDEPENDENT_STRIDE: f64 = 10.5;

/// A request and a tolerance a plan can be made for: the tolerance in (0, 1), each range an interval, the smallest
/// footprint non-negative (positive for an aligned table's).
fn check_request(request: &TableRequest, tolerance: f64) -> Result<()> {
    if !(tolerance.is_finite() && tolerance > 0.0 && tolerance < 1.0) {
        return Err(Error::setting(
            "table_tolerance",
            format!("the table tolerance must lie in (0, 1), got {tolerance}"),
        ));
    }
    let d = request.domain;
    for (name, (a, b)) in [("u", d.u), ("v", d.v), ("w", d.w)] {
        if !(a.is_finite() && b.is_finite() && a <= b) {
            return Err(Error::Invalid(format!("the table's {name} range [{a}, {b}] is not an interval")));
        }
    }
    let footprint = request.footprint;
    if !(footprint.is_finite() && footprint >= 0.0) || (request.aligned && footprint == 0.0) {
        return Err(Error::Invalid(format!("the smallest pixel footprint must be positive, got {footprint}")));
    }
    Ok(())
}

impl TablePlan {
    pub fn new(hf: &HeightField, coherence_um: f64, request: &TableRequest, tolerance: f64) -> Result<Self> {
        Self::new_under(hf, coherence_um, request, tolerance, Illuminant::d65())
    }

    /// [`Self::new`] for light of `illuminant`'s spectrum.
    pub fn new_under(
        hf: &HeightField,
        coherence_um: f64,
        request: &TableRequest,
        tolerance: f64,
        illuminant: Illuminant,
    ) -> Result<Self> {
        check_request(request, tolerance)?;
        let d = request.domain;
        let (lx, ly) = hf.size_um();
        let window = CoherenceWindow::new(lx, ly, coherence_um, None)?;
        // A lobe's intensity |A|²·exp(−d²/σ²) has the standard deviation σ/√2 bins, λ/L in u per bin.
        let lobe = |nm: f64| (window.sigma_x / lx).min(window.sigma_y / ly) * nm * 1e-3 / std::f64::consts::SQRT_2;
        let lobe_width =
            (lobe(crate::physics::spectrum::VISIBLE_MIN_NM), lobe(crate::physics::spectrum::VISIBLE_MAX_NM));
        let cell = hf.period_cell();
        let (tx, ty) = ((hf.nx / cell.0) as f64, (hf.ny / cell.1) as f64);
        let lattice = tx / window.sigma_x >= INDEPENDENT_STRIDE && ty / window.sigma_y >= INDEPENDENT_STRIDE;
        let nodes = degree::nodes_for(hf, &window, cell, d.w, &illuminant, 2)?;
        let blank = Estimate { terms: 1, points: 0, every_lobe: true, tail: 0.0 };
        let mut plan = Self {
            domain: d,
            // Unsized until the estimate is in; the estimate reads only its w-interval, the domain's.
            grid: Self::grid(d, 1.0, true, 1),
            terms: 1,
            estimate: blank,
            nodes,
            segments: vec![Segment { w: d.w, nodes, estimate: blank }],
            tolerance,
            lobe_width,
            cell,
            lattice,
            point: request.aligned,
            coarsened_from: None,
            window,
            coherence_um,
            illuminant,
            lambda_step_nm: TABLE_LAMBDA_STEP_NM,
            mass_only: request.mass_only,
        };
        // (Without an estimate, the grid is sized for as many terms as the nodes can certify.)
        plan.estimate = if request.mass_only {
            Estimate { terms: nodes.count, ..blank }
        } else {
            cache::estimate(hf, &plan, || degree::estimate(hf, &plan))
        };
        plan.terms = plan.estimate.terms;
        plan.segments[0].estimate = plan.estimate;
        plan.size_grid(request);
        plan.segmented_as_asked(hf, request)
    }

    /// This one-segment plan, or its w-interval cut into the segments `request` asks for (texels sized again for
    /// their memory), or into two where `auto` finds they read fewer layers.
    fn segmented_as_asked(self, hf: &HeightField, request: &TableRequest) -> Result<Self> {
        let d = self.domain;
        let segments = match request.segments {
            Some(n) if !(1..=MAX_SEGMENTS).contains(&n) => {
                return Err(Error::setting(
                    "table_segments",
                    format!("a table has 1 to {MAX_SEGMENTS} segments of w, not {n}"),
                ))
            }
            Some(1) => return Ok(self),
            Some(n) => self.segmented(hf, n)?,
            // Two segments where they read fewer layers (a series over half the interval needs fewer terms)
            // within SEGMENT_MEMORY_RATIO of one's memory on the same grid, never a coarser one. The layers are
            // compared at a term more than each estimate: the certificate, made on every texel at 1 nm steps,
            // has kept one more than the estimate in the shipped scenes' tables (docs/performance.md). Tried only
            // on w-intervals longer than SEGMENT_MIN_W (the two segments' estimates cost time): a map's spans 1,
            // the shipped scenes' frames about 1, and none of those read fewer layers in two.
            None if self.terms > 1 && d.w.1 - d.w.0 > SEGMENT_MIN_W => {
                let two = self.segmented(hf, 2)?;
                let (bytes, one) = (two.grid.bytes(two.terms + 1), self.grid.bytes(self.terms + 1));
                let fewer = layers_for(two.terms + 1) < layers_for(self.terms + 1);
                // On the same texels as the one segment's plan, which were sized (and coarsened) for fewer bytes.
                let keep = fewer && bytes <= MAX_TABLE_BYTES && bytes as f64 <= SEGMENT_MEMORY_RATIO * one as f64;
                return Ok(if keep { two } else { self });
            }
            None => return Ok(self),
        };
        // Segments the user asked for: texels sized again for their memory.
        let mut plan = segments;
        plan.coarsened_from = None;
        plan.size_grid(request);
        Ok(plan)
    }

    /// This plan with its w-interval cut into `n` equal segments, each with its own nodes and estimate, the
    /// grid's texels unchanged (the caller sizes it again where the memory calls for it).
    fn segmented(&self, hf: &HeightField, n: usize) -> Result<Self> {
        let grid = Grid { segments: n, ..self.grid };
        let cell = self.cell;
        let mut segments = Vec::with_capacity(n);
        for s in 0..n {
            let w = grid.segment_w(s);
            let nodes = degree::nodes_for(hf, &self.window, cell, w, &self.illuminant, 2)?;
            let mut one = Segment { w, nodes, estimate: self.estimate };
            let probe = self.with_segment(&one);
            one.estimate = cache::estimate(hf, &probe, || degree::estimate(hf, &probe));
            segments.push(one);
        }
        let estimate = Estimate {
            terms: segments.iter().map(|s| s.estimate.terms).max().unwrap_or(1),
            points: segments.iter().map(|s| s.estimate.points).sum(),
            every_lobe: segments.iter().all(|s| s.estimate.every_lobe),
            tail: segments.iter().map(|s| s.estimate.tail).fold(0.0, f64::max),
        };
        let nodes = Nodes {
            count: segments.iter().map(|s| s.nodes.count).sum(),
            unseen: std::array::from_fn(|c| segments.iter().map(|s| s.nodes.unseen[c]).fold(0.0, f64::max)),
        };
        Ok(Self { grid, terms: estimate.terms, estimate, nodes, segments, ..self.clone() })
    }

    /// The one-segment plan of `segment` (its w-interval, nodes and estimate on this plan's texels): what the
    /// estimate and the build of that segment read.
    /// This plan under another light (one of the environment's spectral bands after the first): the same domain,
    /// grid and estimate of the terms in w — the estimate sizes the grid, and each table's own certificate decides
    /// its degree — with the nodes in w that light needs (at least this plan's, so that one pass builds both).
    pub fn for_light(&self, hf: &HeightField, illuminant: Illuminant) -> Result<Self> {
        let mut plan = Self { illuminant, ..self.clone() };
        if plan.segments.len() == 1 {
            let nodes = degree::nodes_for(hf, &plan.window, plan.cell, plan.grid.w, &illuminant, self.nodes.count)?;
            plan.nodes = nodes;
            plan.segments[0].nodes = nodes;
        }
        Ok(plan)
    }

    /// This plan sampling w at `count` nodes or more (a single segment's plan; a plan of several is returned as
    /// it is): the spectral bands of one material share their nodes, so that one pass builds them all
    /// ([`build::build_bands`]).
    pub fn with_nodes_at_least(&self, hf: &HeightField, count: usize) -> Result<Self> {
        if self.segments.len() != 1 || self.nodes.count >= count {
            return Ok(self.clone());
        }
        let nodes = degree::nodes_for(hf, &self.window, self.cell, self.grid.w, &self.illuminant, count)?;
        let segments = vec![Segment { nodes, ..self.segments[0] }];
        Ok(Self { nodes, segments, ..self.clone() })
    }

    pub fn with_segment(&self, segment: &Segment) -> Self {
        let domain = Domain { w: segment.w, ..self.domain };
        Self {
            domain,
            grid: Grid { w: segment.w, segments: 1, ..self.grid },
            terms: segment.estimate.terms,
            estimate: segment.estimate,
            nodes: segment.nodes,
            segments: vec![*segment],
            ..self.clone()
        }
    }

    /// Sub-samples per texel axis whose mean is a texel's value: on the coherent path, enough that their spacing is
    /// at most the lobe width (sub-sample i of texel a sits at u0 + (a + (i + ½)/s)·texel), or [`MASS_SPACING`]
    /// lobe widths for a [`Self::mass_only`] table; 1 for point tables and on the lattice path, whose texel averages
    /// are exact.
    pub fn subsamples(&self) -> usize {
        if self.point || self.lattice {
            1
        } else {
            let spacing = if self.mass_only { MASS_SPACING * self.lobe_width.0 } else { self.lobe_width.0 };
            ((self.grid.texel / spacing).ceil() as usize).clamp(1, MAX_SUBSAMPLES)
        }
    }

    /// The finest grid the request can use within [`MAX_TABLE_BYTES`]. Texels finer than the narrowest lobe
    /// gain nothing (a texel one standard deviation wide averages a lobe's peak down by 4 %); texels wider than
    /// F/√3 would blur what a pixel of footprint F resolves (the level it reads is that much finer than F,
    /// [`FOOTPRINT_LOD_BIAS`]). A map's texels are an odd fraction of its pixels, so that its pixel centres are
    /// texel centres.
    fn size_grid(&mut self, request: &TableRequest) {
        let (d, finest) = (request.domain, self.lobe_width.0);
        let footprint = if request.aligned { request.footprint } else { request.footprint / 3f64.sqrt() };
        let fits = |g: &Grid| g.bytes(self.terms) <= MAX_TABLE_BYTES;
        let segments = self.grid.segments;
        let mut grid;
        if request.aligned {
            let mut k = if request.centres_only { 1 } else { ((footprint / finest).ceil() as usize).max(1) | 1 };
            grid = Self::grid(d, footprint / k as f64, true, segments);
            while !fits(&grid) && k > 1 {
                self.coarsened_from.get_or_insert(grid.texel);
                k -= 2;
                grid = Self::grid(d, footprint / k as f64, true, segments);
            }
        } else {
            grid = Self::grid(d, footprint.max(finest), false, segments);
        }
        let mut scale = 1.0;
        while !fits(&grid) {
            self.coarsened_from.get_or_insert(grid.texel);
            scale *= 2f64.powf(0.25);
            let texel = footprint.max(if request.aligned { 0.0 } else { finest }) * scale;
            grid = Self::grid(d, texel, request.aligned, segments);
        }
        self.grid = grid;
    }

    /// The grid of `texel` over `d`: aligned to d's lower corner (maps), else widened by a texel and snapped to
    /// multiples of the texel (so that nearby views give the same table).
    fn grid(d: Domain, texel: f64, aligned: bool, segments: usize) -> Grid {
        let (u0, v0, u1, v1) = if aligned {
            (d.u.0, d.v.0, d.u.1, d.v.1)
        } else {
            let lo = |x: f64| ((x / texel).floor() - 1.0) * texel;
            let hi = |x: f64| ((x / texel).ceil() + 1.0) * texel;
            (lo(d.u.0), lo(d.v.0), hi(d.u.1), hi(d.v.1))
        };
        let n = |a: f64, b: f64| (((b - a) / texel).round() as usize).max(1);
        Grid { u0, v0, texel, nu: n(u0, u1), nv: n(v0, v1), w: d.w, segments }
    }

    /// One line for users: grid, lobes, degree, memory.
    pub fn describe(&self) -> String {
        let g = &self.grid;
        let resolved = if g.texel <= self.lobe_width.0 * 1.0001 {
            "resolves every lobe".to_string()
        } else if self.point {
            // Texel-centre values: a pixel centre reads its own exact value, whatever lies between centres.
            format!(
                "one texel per pixel centre; lobes of {:.4}–{:.4} between centres are not stored",
                self.lobe_width.0, self.lobe_width.1
            )
        } else {
            format!(
                "lobes of {:.4}–{:.4} narrower than a texel are averaged over it",
                self.lobe_width.0, self.lobe_width.1
            )
        };
        format!(
            "baked table: u ∈ [{:.3}, {:.3}], v ∈ [{:.3}, {:.3}], w ∈ [{:.3}, {:.3}]{}; {}×{} texels of {:.5} ({}{}); \
             {} path, {}; about {} terms in w{} (estimated at {}, tail {:.1e} there; the build certifies the degree \
             against a tolerance of {:.0e} of each texel's brightest value + 1e-10 from {} nodes in w); {:.1} MiB",
            g.u0,
            g.u0 + g.nu as f64 * g.texel,
            g.v0,
            g.v0 + g.nv as f64 * g.texel,
            g.w.0,
            g.w.1,
            if g.segments > 1 { format!(" in {} segments", g.segments) } else { String::new() },
            g.nu,
            g.nv,
            g.texel,
            resolved,
            self.coarsened_from
                .map(|t| format!("; coarsened from {t:.5} to fit {} MiB", MAX_TABLE_BYTES >> 20))
                .unwrap_or_default(),
            if self.lattice { "lattice" } else { "coherent" },
            if self.point { "texel-centre values" } else { "texel averages" },
            self.terms,
            if g.segments > 1 { " each" } else { "" },
            if self.estimate.every_lobe {
                format!("{} lobe centres{}", self.estimate.points, if self.lattice { "" } else { " and midpoints" })
            } else {
                format!("{} points of a regular grid", self.estimate.points)
            },
            self.estimate.tail,
            self.tolerance,
            self.nodes.count,
            g.bytes(self.terms) as f64 / (1u64 << 20) as f64
        )
    }
}

/// The table `plan` describes: from the cache folder (`$DIFFRACT_CACHE`, else the user's) when an earlier run
/// built it, else built (and stored there). Returns the table and whether it came from the cache.
pub fn load_or_build(
    hf: &HeightField,
    plan: &TablePlan,
    progress: Option<build::Progress<'_>>,
) -> Result<(BakedTable, bool)> {
    let dir = crate::io::cache::default_dir();
    if let Some(table) = dir.as_deref().and_then(|d| cache::read(d, hf, plan)) {
        return Ok((table, true));
    }
    let table = build::build(hf, plan, progress)?;
    if let Some(d) = &dir {
        if let Err(e) = cache::write(d, hf, plan, &table) {
            log::warn!("could not cache the baked table in {}: {e}", d.display());
        }
    }
    Ok((table, false))
}

/// [`load_or_build`] for plans that differ only in their light (the environment's spectral bands): from the cache
/// where every one is there, else all built in one pass ([`build::build_bands`]) and cached.
pub fn load_or_build_bands(hf: &HeightField, plans: &[TablePlan]) -> Result<Vec<BakedTable>> {
    let dir = crate::io::cache::default_dir();
    let cached: Option<Vec<BakedTable>> =
        plans.iter().map(|plan| dir.as_deref().and_then(|d| cache::read(d, hf, plan))).collect();
    if let Some(tables) = cached {
        return Ok(tables);
    }
    let tables = build::build_bands(hf, plans)?;
    if let Some(d) = &dir {
        for (plan, table) in plans.iter().zip(&tables) {
            if let Err(e) = cache::write(d, hf, plan, table) {
                log::warn!("could not cache the baked table in {}: {e}", d.display());
            }
        }
    }
    Ok(tables)
}

/// Where `table`'s certificate misses its tolerance (memory or [`MAX_TERMS`] kept fewer terms than it needs, or
/// the nodes could not reach it), what it keeps and why, in words naming the tail and the tolerance.
pub(crate) fn shortfall(table: &BakedTable) -> Option<String> {
    let c = &table.certificate;
    if c.meets_tolerance() {
        return None;
    }
    let why = match c.needed {
        Some(n) if n > MAX_TERMS => format!("it needs {n} terms, more than the {MAX_TERMS} a table holds"),
        Some(n) => format!("the {n} terms it needs do not fit in {} MiB", MAX_TABLE_BYTES >> 20),
        None => format!("{} nodes in w cannot reach it", c.nodes),
    };
    Some(format!(
        "the baked table keeps {} terms in w, whose tail is up to {:.1e} of a texel's brightest value, above its \
         tolerance {:.0e} ({why})",
        c.terms, c.tail, c.tolerance
    ))
}

/// A warning where `table` misses its tolerance (`shortfall`), or, when `strict`, a refusal.
pub fn check_certificate(table: &BakedTable, strict: bool) -> Result<()> {
    match shortfall(table) {
        None => Ok(()),
        Some(m) if strict => Err(Error::Precision(format!(
            "{m}; refused (--strict-table, or the scene's table_tolerance): raise the tolerance or narrow the views"
        ))),
        Some(m) => {
            log::warn!("{m}; {TABLE_SHORTFALL_HINT}");
            Ok(())
        }
    }
}

/// What a warning about a table that misses its tolerance adds.
pub(crate) const TABLE_SHORTFALL_HINT: &str = "colours may be off by that much (--strict-table refuses such a table)";

/// One mip level: RGBA32F texels, layer after layer, rows top (v0) first.
#[derive(Clone, Debug, PartialEq)]
pub struct TableLevel {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<f32>,
}

/// A built table: the grid, the Chebyshev terms kept, every mip level, and what the build proved about them.
#[derive(Clone, Debug, PartialEq)]
pub struct BakedTable {
    pub grid: Grid,
    pub terms: usize,
    pub levels: Vec<TableLevel>,
    pub certificate: Certificate,
    /// How it was built, in a few words (path, texel values or averages).
    pub report: String,
}

impl BakedTable {
    /// Layers of the texture array: every segment's.
    pub fn layers(&self) -> usize {
        self.layers_per_read() * self.grid.segments
    }

    /// Layers one read fetches: one segment's.
    pub fn layers_per_read(&self) -> usize {
        layers_for(self.terms)
    }

    /// Bytes of every level (what the GPU holds).
    pub fn bytes(&self) -> u64 {
        self.levels.iter().map(|l| l.texels.len() as u64 * 4).sum()
    }

    /// Packs level 0 from f64 coefficients, texel after texel: coefficient d of channel c of texel t (rows
    /// top first) is `coef[t·stride + 3d + c]`, of which the certificate's terms are kept; then averages the mip
    /// levels.
    pub fn from_coefficients(
        grid: Grid,
        coef: &[f64],
        stride: usize,
        certificate: Certificate,
        report: String,
    ) -> Self {
        let (nu, nv, terms) = (grid.nu, grid.nv, certificate.terms);
        let layers = layers_for(terms);
        let mut level0 = vec![0f32; layers * nu * nv * LAYER_CHANNELS];
        for (t, texel) in coef.chunks_exact(stride).take(nu * nv).enumerate() {
            for (scalar, v) in texel[..3 * terms].iter().enumerate() {
                let (layer, channel) = (scalar / LAYER_CHANNELS, scalar % LAYER_CHANNELS);
                level0[(layer * nu * nv + t) * LAYER_CHANNELS + channel] = *v as f32;
            }
        }
        let mut levels = vec![TableLevel { width: nu, height: nv, texels: level0 }];
        for &(w, h) in &grid.level_sizes()[1..] {
            let next = downsample(levels.last().expect("level 0"), w, h, layers);
            levels.push(next);
        }
        Self { grid, terms, levels, certificate, report }
    }

    /// One table of `grid`'s segments from a table per segment (each built on the same texels over its own
    /// w-interval), in order: segment s's layers follow segment s − 1's, each padded with zero coefficients to the
    /// most terms any keeps. The certificate holds for every segment: the most terms, the largest tail and bound,
    /// the nodes summed.
    pub fn from_segments(grid: Grid, parts: Vec<BakedTable>, report: String) -> Self {
        assert_eq!(parts.len(), grid.segments, "one table per segment");
        let terms = parts.iter().map(|p| p.terms).max().unwrap_or(1);
        let layers = layers_for(terms);
        let c: Vec<Certificate> = parts.iter().map(|p| p.certificate).collect();
        let certificate = Certificate {
            terms,
            needed: c.iter().map(|c| c.needed).collect::<Option<Vec<_>>>().and_then(|n| n.into_iter().max()),
            nodes: c.iter().map(|c| c.nodes).sum(),
            unseen: c.iter().map(|c| c.unseen).fold(0.0, f64::max),
            tail: c.iter().map(|c| c.tail).fold(0.0, f64::max),
            tolerance: c[0].tolerance,
        };
        let levels = grid
            .level_sizes()
            .iter()
            .enumerate()
            .map(|(l, &(width, height))| {
                let per_layer = width * height * LAYER_CHANNELS;
                let mut texels = vec![0f32; grid.segments * layers * per_layer];
                for (s, part) in parts.iter().enumerate() {
                    let own = &part.levels[l].texels;
                    texels[s * layers * per_layer..][..own.len()].copy_from_slice(own);
                }
                TableLevel { width, height, texels }
            })
            .collect();
        Self { grid, terms, levels, certificate, report }
    }
}

/// A coarser level by box resampling: texel i of the `w`-wide level covers [i·r, (i + 1)·r) texels of the finer
/// one (r = fine/coarse width), each weighted by its overlap, so every level keeps the mean (and the texel
/// centres line up in normalised coordinates, as the sampler reads them).
fn downsample(fine: &TableLevel, w: usize, h: usize, layers: usize) -> TableLevel {
    let weights = |n_fine: usize, n: usize| -> Vec<Vec<(usize, f64)>> {
        let r = n_fine as f64 / n as f64;
        (0..n)
            .map(|i| {
                let (a, b) = (i as f64 * r, (i + 1) as f64 * r);
                (a.floor() as usize..(b.ceil() as usize).min(n_fine))
                    .map(|j| (j, ((j + 1) as f64).min(b) - (j as f64).max(a)))
                    .filter(|&(_, o)| o > 0.0)
                    .map(|(j, o)| (j, o / r))
                    .collect()
            })
            .collect()
    };
    let (wx, wy) = (weights(fine.width, w), weights(fine.height, h));
    let mut texels = vec![0f32; layers * w * h * LAYER_CHANNELS];
    for layer in 0..layers {
        let src = &fine.texels[layer * fine.width * fine.height * LAYER_CHANNELS..];
        for (y, ry) in wy.iter().enumerate() {
            for (x, rx) in wx.iter().enumerate() {
                let mut acc = [0f64; LAYER_CHANNELS];
                for &(sy, fy) in ry {
                    for &(sx, fx) in rx {
                        let t = &src[(sy * fine.width + sx) * LAYER_CHANNELS..][..LAYER_CHANNELS];
                        for (a, v) in acc.iter_mut().zip(t) {
                            *a += fy * fx * f64::from(*v);
                        }
                    }
                }
                let out = &mut texels[((layer * h + y) * w + x) * LAYER_CHANNELS..][..LAYER_CHANNELS];
                for (o, a) in out.iter_mut().zip(acc) {
                    *o = a as f32;
                }
            }
        }
    }
    TableLevel { width: w, height: h, texels }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_levels_keep_the_mean_and_end_in_one_texel() {
        let grid = Grid { u0: -1.0, v0: -1.0, texel: 0.1, nu: 7, nv: 5, w: (-2.0, -1.0), segments: 1 };
        assert_eq!(grid.level_sizes(), vec![(7, 5), (3, 2), (1, 1)]);
        let terms = 2;
        let coef: Vec<f64> = (0..3 * terms * 35).map(|i| ((i * 37) % 11) as f64).collect();
        let certificate =
            Certificate { terms, needed: Some(terms), nodes: terms, unseen: 0.0, tail: 0.0, tolerance: 1e-4 };
        let table = BakedTable::from_coefficients(grid, &coef, 3 * terms, certificate, String::new());
        assert_eq!(table.layers(), 2);
        for scalar in 0..3 * terms {
            let mean = (0..35).map(|t| coef[t * 3 * terms + scalar]).sum::<f64>() / 35.0;
            let (layer, ch) = (scalar / 4, scalar % 4);
            for level in &table.levels {
                let n = level.width * level.height;
                let sum: f64 = (0..n).map(|i| f64::from(level.texels[(layer * n + i) * 4 + ch])).sum();
                assert!((sum / n as f64 - mean).abs() < 1e-5, "scalar {scalar}: {} vs {mean}", sum / n as f64);
            }
        }
        assert_eq!(table.bytes(), grid.bytes(terms));
    }

    #[test]
    fn a_table_that_misses_its_tolerance_warns_or_is_refused_when_strict() {
        let grid = Grid { u0: 0.0, v0: 0.0, texel: 0.1, nu: 2, nv: 2, w: (-2.0, -1.0), segments: 1 };
        let table = |terms, needed, tail| {
            let certificate = Certificate { terms, needed, nodes: 24, unseen: 1e-12, tail, tolerance: 1e-4 };
            BakedTable::from_coefficients(grid, &[0.0; 4 * 192], 192, certificate, String::new())
        };
        let fine = table(8, Some(8), 3e-5);
        assert!(shortfall(&fine).is_none() && check_certificate(&fine, true).is_ok());
        let short = table(3, Some(9), 2.5e-3);
        let m = shortfall(&short).unwrap();
        assert!(m.contains("keeps 3 terms") && m.contains("2.5e-3") && m.contains("1e-4"), "{m}");
        assert!(m.contains("the 9 terms it needs do not fit in 256 MiB"), "{m}");
        assert!(check_certificate(&short, false).is_ok(), "a warning, not a refusal");
        let e = check_certificate(&short, true).unwrap_err().to_string();
        assert!(e.contains("refused") && e.lines().count() == 1, "{e}");
        let capped = table(64, Some(70), 2e-4);
        assert!(shortfall(&capped).unwrap().contains("more than the 64 a table holds"));
    }

    #[test]
    fn a_map_grid_puts_texel_centres_on_pixel_centres() {
        let cell: Vec<f64> = (0..100 * 100).map(|i| ((i * 7919) % 101) as f64 * 1e-3).collect();
        let hf = HeightField::new(100, 100, 0.065, 0.065, cell).unwrap().tiled(10, 10).unwrap();
        let pixel = 2.0 / 64.0;
        let request = TableRequest {
            domain: Domain::map(DVec3::new(0.0, 0.0, 1.0)),
            footprint: pixel,
            aligned: true,
            centres_only: false,
            segments: None,
            mass_only: false,
        };
        let plan = TablePlan::new(&hf, 65.0, &request, DEFAULT_TABLE_TOLERANCE).unwrap();
        assert!(plan.point && plan.terms >= 1 && plan.estimate.every_lobe && plan.estimate.points > 0);
        let k = (pixel / plan.grid.texel).round();
        assert!((pixel / plan.grid.texel - k).abs() < 1e-9 && k as usize % 2 == 1, "{plan:?}");
        assert!(plan.grid.texel <= plan.lobe_width.0 * 1.0001, "{}", plan.describe());
        // Pixel 10's centre is texel (10 k + (k − 1)/2)'s centre.
        let px = -1.0 + (10.0 + 0.5) * pixel;
        let a = 10 * k as usize + (k as usize - 1) / 2;
        assert!((plan.grid.u_centre(a) - px).abs() < 1e-12);
        assert!(plan.lattice && plan.cell == (100, 100));
    }
}

#[cfg(test)]
mod band_tests {
    use super::*;

    /// The environment's spectral bands built in one pass are the tables each band's own build gives, to rounding
    /// (the same sums in the same order, weighted per band), on both paths: a random-height patch (coherent) and a
    /// tiled one (lattice); and a plan that cannot share a pass is built on its own.
    #[test]
    fn bands_built_in_one_pass_are_each_bands_own_table() {
        let cell: Vec<f64> = (0..16 * 16).map(|i| ((i * 7919) % 23) as f64 * 4e-3).collect();
        let random = HeightField::new(16, 16, 0.25, 0.25, cell.clone()).unwrap();
        let tiled = HeightField::new(16, 16, 0.25, 0.25, cell).unwrap().tiled(20, 20).unwrap();
        let request =
            TableRequest { segments: Some(1), ..crate::material::Reach::Hemisphere { footprint: 0.1 }.table_request() };
        let lights = [0, 1, 2].map(|k| Illuminant::d65_band(k).physical());
        for (name, hf, coherence) in [("coherent", &random, 4.0), ("lattice", &tiled, 65.0)] {
            let first = TablePlan::new_under(hf, coherence, &request, 1e-4, lights[0]).unwrap();
            let mut plans: Vec<TablePlan> = lights.iter().map(|&l| first.for_light(hf, l).unwrap()).collect();
            let most = plans.iter().map(|p| p.nodes.count).max().unwrap();
            for p in &mut plans {
                *p = p.with_nodes_at_least(hf, most).unwrap();
            }
            assert_eq!(plans[0].lattice, name == "lattice", "{name}");
            let together = build::build_bands(hf, &plans).unwrap();
            assert!(together[0].report.contains("one pass"), "{name}: {}", together[0].report);
            for (plan, table) in plans.iter().zip(&together) {
                let alone = build::build(hf, plan, None).unwrap();
                assert_eq!(alone.certificate.terms, table.certificate.terms, "{name}");
                let level = &table.levels[0];
                let mut worst = 0.0f64;
                let mut largest = 0.0f64;
                for b in (0..level.height).step_by(3) {
                    for a in (0..level.width).step_by(3) {
                        for w in [-1.9, -1.3, -0.6] {
                            let (p, q) = (table.level_xyz(0, a, b, w), alone.level_xyz(0, a, b, w));
                            worst = worst.max((p - q).abs().max_element());
                            largest = largest.max(q.abs().max_element());
                        }
                    }
                }
                assert!(largest > 0.0 && worst <= 1e-6 * largest, "{name}: {worst:e} of {largest:e}");
            }
        }
    }
}
