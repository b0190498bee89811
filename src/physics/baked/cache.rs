//! Baked tables and their estimates on disk, as verified entries of `crate::io::cache`: each names the plan it was
//! computed for (the patch's hash, the illuminant's, the coherence, the tolerance, the nodes, the grid), so a second run with the
//! same patch and views loads in milliseconds, and a damaged, edited or foreign file is rebuilt, never used.

use std::path::Path;

use crate::io::cache::{KeyHash, PlanBytes, Reader, Stamp};
use crate::physics::baked::{
    BakedTable, Certificate, Estimate, Grid, TableLevel, TablePlan, LAYER_CHANNELS, MAX_TERMS,
};
use crate::physics::heightfield::HeightField;

/// Bumped whenever the build's definition changes: tables of other versions are rebuilt.
const VERSION: u64 = 4;
/// Bytes of a table's payload besides its texels: the grid, the certificate, the report (at most this long).
const TABLE_OVERHEAD: u64 = 4096;
const MAX_REPORT: usize = 1024;

/// Everything the estimate of `plan` depends on (the grid is not sized yet: the domain stands for it).
fn estimate_plan(hf: &HeightField, plan: &TablePlan) -> PlanBytes {
    let mut h = KeyHash::default();
    hf.hash_into(&mut h);
    let mut light = KeyHash::default();
    plan.illuminant.hash_into(&mut light);
    let mut p = PlanBytes::default();
    p.u64(h.finish())
        .u64(light.finish())
        .f64(plan.coherence_um)
        .f64(plan.tolerance)
        .u64(plan.nodes.count as u64)
        .u64(u64::from(plan.lattice));
    let d = plan.domain;
    for v in [d.u.0, d.u.1, d.v.0, d.v.1, d.w.0, d.w.1] {
        p.f64(v);
    }
    p
}

/// The bytes that identify the table of `plan` (what its cache entry is keyed by): for results computed from it.
pub fn table_identity(hf: &HeightField, plan: &TablePlan) -> Vec<u8> {
    let mut p = PlanBytes(table_stamp(hf, plan).plan);
    p.u64(VERSION);
    p.0
}

/// Everything the table of `plan` depends on.
fn table_stamp(hf: &HeightField, plan: &TablePlan) -> Stamp {
    let mut p = estimate_plan(hf, plan);
    p.u64(plan.terms as u64).u64(u64::from(plan.point));
    let g = &plan.grid;
    for v in [g.u0, g.v0, g.texel, g.w.0, g.w.1] {
        p.f64(v);
    }
    p.u64(g.nu as u64).u64(g.nv as u64);
    // (Only where it is not the default, so that the default tables keep their keys.)
    if plan.lambda_step_nm != crate::physics::baked::TABLE_LAMBDA_STEP_NM {
        p.f64(plan.lambda_step_nm);
    }
    if plan.mass_only {
        p.u64(1);
    }
    if g.segments > 1 {
        p.u64(g.segments as u64);
        for s in &plan.segments {
            p.u64(s.nodes.count as u64).u64(s.estimate.terms as u64);
        }
    }
    Stamp { kind: "baked", what: "baked table", version: VERSION, plan: p.0 }
}

/// The estimate for a plan whose grid is still unsized, from the default cache folder; computed with `measure`
/// and stored there when missing.
pub fn estimate(hf: &HeightField, plan: &TablePlan, measure: impl FnOnce() -> Estimate) -> Estimate {
    let stamp = Stamp {
        kind: "estimate",
        what: "estimate of a baked table",
        version: VERSION,
        plan: estimate_plan(hf, plan).0,
    };
    let dir = crate::io::cache::default_dir();
    let cached = dir.as_deref().and_then(|d| crate::io::cache::load(d, &stamp, 32)).and_then(|bytes| {
        let mut r = Reader::new(&bytes);
        let terms = usize::try_from(r.u64()?).ok().filter(|&t| (1..=plan.nodes.count).contains(&t))?;
        let points = usize::try_from(r.u64()?).ok()?;
        let every_lobe = r.u64()? != 0;
        let tail = r.f64().filter(|t| t.is_finite() && *t >= 0.0)?;
        r.finished().then_some(Estimate { terms, points, every_lobe, tail })
    });
    cached.unwrap_or_else(|| {
        let e = measure();
        if let Some(d) = &dir {
            let mut bytes = Vec::with_capacity(32);
            for v in [e.terms as u64, e.points as u64, u64::from(e.every_lobe), e.tail.to_bits()] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
            // A cache that cannot be written costs time, not correctness.
            let _ = crate::io::cache::store(d, &stamp, &bytes);
        }
        e
    })
}

/// Stores `table`, built for `plan`, under `dir`.
pub fn write(dir: &Path, hf: &HeightField, plan: &TablePlan, table: &BakedTable) -> std::io::Result<()> {
    let mut bytes = Vec::with_capacity(table.bytes() as usize + TABLE_OVERHEAD as usize);
    let c = &table.certificate;
    let needed = c.needed.map_or(u64::MAX, |n| n as u64);
    for v in [c.terms as u64, needed, c.nodes as u64, c.unseen.to_bits(), c.tail.to_bits(), c.tolerance.to_bits()] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes.extend_from_slice(&(table.levels.len() as u64).to_le_bytes());
    let report = &table.report.as_bytes()[..table.report.len().min(MAX_REPORT)];
    bytes.extend_from_slice(&(report.len() as u64).to_le_bytes());
    bytes.extend_from_slice(report);
    for level in &table.levels {
        bytes.extend_from_slice(&(level.width as u64).to_le_bytes());
        bytes.extend_from_slice(&(level.height as u64).to_le_bytes());
        bytes.extend_from_slice(bytemuck::cast_slice(&level.texels));
    }
    crate::io::cache::store(dir, &table_stamp(hf, plan), &bytes)
}

/// The table cached under `dir` for `plan`, or None (missing, or not checking out: it is then rebuilt). The
/// grid is the plan's (it is part of the entry's plan), the terms within the nodes, every texel finite.
pub fn read(dir: &Path, hf: &HeightField, plan: &TablePlan) -> Option<BakedTable> {
    let grid: Grid = plan.grid;
    let most = grid.bytes(MAX_TERMS.min(plan.nodes.count)) + TABLE_OVERHEAD;
    let stamp = table_stamp(hf, plan);
    let bytes = crate::io::cache::load(dir, &stamp, most)?;
    let table = parse(&bytes, plan);
    if table.is_none() {
        log::info!(
            "the cached baked table {} checks out but does not hold a table for its plan; building it again",
            stamp.file(dir).display()
        );
    }
    table
}

fn parse(bytes: &[u8], plan: &TablePlan) -> Option<BakedTable> {
    let grid = plan.grid;
    let mut r = Reader::new(bytes);
    let mut count = || r.u64().and_then(|v| usize::try_from(v).ok());
    let (terms, needed, nodes) = (count()?, count()?, count()?);
    let (unseen, tail, tolerance) = (r.f64()?, r.f64()?, r.f64()?);
    let levels = usize::try_from(r.u64()?).ok()?;
    let plausible = (1..=MAX_TERMS.min(nodes)).contains(&terms)
        && nodes == plan.nodes.count
        && tolerance == plan.tolerance
        && [unseen, tail].iter().all(|v| v.is_finite() && *v >= 0.0)
        && levels == grid.level_sizes().len();
    if !plausible {
        return None;
    }
    let needed = (needed != usize::MAX).then_some(needed);
    let certificate = Certificate { terms, needed, nodes, unseen, tail, tolerance };
    let report = r.string()?;
    let layers = crate::physics::baked::layers_for(terms) * grid.segments;
    let mut out = Vec::with_capacity(levels);
    for &(w, h) in &grid.level_sizes() {
        let (width, height) = (usize::try_from(r.u64()?).ok()?, usize::try_from(r.u64()?).ok()?);
        if (width, height) != (w, h) {
            return None;
        }
        let raw = r.take(layers * w * h * LAYER_CHANNELS * 4)?;
        let texels: Vec<f32> = bytemuck::pod_collect_to_vec(raw);
        if !texels.iter().all(|t| t.is_finite()) {
            return None;
        }
        out.push(TableLevel { width, height, texels });
    }
    r.finished().then_some(BakedTable { grid, terms, levels: out, certificate, report })
}
