//! Baked tables on disk ([`crate::cache`]): named by a hash of everything a table depends on, so a second run
//! with the same patch and views loads in milliseconds.

use std::path::{Path, PathBuf};

use super::{BakedTable, Grid, TableLevel, TablePlan};
use crate::cache::{Fnv, Reader};
use crate::physics::HeightField;

/// Bumped whenever the build's definition changes: tables of other versions are rebuilt.
const VERSION: u64 = 3;
const MAGIC: &[u8; 8] = b"DFRTAB01";

/// The hash of everything `plan`'s table (or, before the grid is sized, its probe) depends on.
fn key(hf: &HeightField, plan: &TablePlan) -> u64 {
    let mut h = Fnv::default();
    h.u64(VERSION);
    hf.hash_into(&mut h);
    h.f64(plan.coherence_um);
    h.f64(plan.tolerance);
    h.u64(plan.probe_terms as u64);
    h.u64(plan.terms as u64);
    h.u64(u64::from(plan.point));
    let g = &plan.grid;
    for v in [g.u0, g.v0, g.texel, g.w.0, g.w.1] {
        h.f64(v);
    }
    h.u64(g.nu as u64);
    h.u64(g.nv as u64);
    h.0
}

/// The file a table for `hf` and `plan` is cached in, under `dir`.
pub fn file(dir: &Path, hf: &HeightField, plan: &TablePlan) -> PathBuf {
    dir.join(format!("baked-{:016x}.bin", key(hf, plan)))
}

/// The probe's measurement (terms, tail) for a plan whose grid is still the probe's, from the default cache
/// folder; computed with `measure` and stored there when missing.
pub fn probe(hf: &HeightField, plan: &TablePlan, measure: impl FnOnce() -> (usize, f64)) -> (usize, f64) {
    let file = crate::cache::default_dir().map(|d| d.join(format!("probe-{:016x}.bin", key(hf, plan))));
    let cached = file.as_deref().and_then(|f| std::fs::read(f).ok()).and_then(|bytes| {
        let mut r = Reader::new(&bytes);
        let terms = usize::try_from(r.u64()?).ok().filter(|&t| (1..=super::MAX_TERMS).contains(&t))?;
        let tail = r.f64()?;
        r.finished().then_some((terms, tail))
    });
    cached.unwrap_or_else(|| {
        let (terms, tail) = measure();
        if let Some(f) = &file {
            let mut bytes = (terms as u64).to_le_bytes().to_vec();
            bytes.extend_from_slice(&tail.to_le_bytes());
            // A cache that cannot be written costs time, not correctness.
            let _ = crate::cache::write_atomic(f, &bytes);
        }
        (terms, tail)
    })
}

pub fn write(file: &Path, table: &BakedTable) -> std::io::Result<()> {
    let mut bytes = Vec::with_capacity(table.bytes() as usize + 256);
    bytes.extend_from_slice(MAGIC);
    let g = &table.grid;
    for v in [g.u0, g.v0, g.texel, g.w.0, g.w.1] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    for v in [g.nu, g.nv, table.terms, table.levels.len()] {
        bytes.extend_from_slice(&(v as u64).to_le_bytes());
    }
    bytes.extend_from_slice(&(table.report.len() as u64).to_le_bytes());
    bytes.extend_from_slice(table.report.as_bytes());
    for level in &table.levels {
        bytes.extend_from_slice(&(level.width as u64).to_le_bytes());
        bytes.extend_from_slice(&(level.height as u64).to_le_bytes());
        bytes.extend_from_slice(bytemuck::cast_slice(&level.texels));
    }
    crate::cache::write_atomic(file, &bytes)
}

/// The cached table for `plan`, or None (missing, unreadable or not matching: it is then rebuilt).
pub fn read(file: &Path, plan: &TablePlan) -> Option<BakedTable> {
    let bytes = std::fs::read(file).ok()?;
    let mut r = Reader::new(&bytes);
    if r.take(8)? != MAGIC {
        return None;
    }
    let (u0, v0, texel, w0, w1) = (r.f64()?, r.f64()?, r.f64()?, r.f64()?, r.f64()?);
    let mut count = || r.u64().and_then(|v| usize::try_from(v).ok());
    let (nu, nv, terms, levels) = (count()?, count()?, count()?, count()?);
    let grid = Grid { u0, v0, texel, nu, nv, w: (w0, w1) };
    if grid != plan.grid || terms == 0 || terms > super::MAX_TERMS || levels != grid.level_sizes().len() {
        return None;
    }
    let report = r.string()?;
    let layers = super::layers_for(terms);
    let mut out = Vec::with_capacity(levels);
    for &(w, h) in &grid.level_sizes() {
        let (width, height) = (usize::try_from(r.u64()?).ok()?, usize::try_from(r.u64()?).ok()?);
        if (width, height) != (w, h) {
            return None;
        }
        let raw = r.take(layers * w * h * super::LAYER_CHANNELS * 4)?;
        out.push(TableLevel { width, height, texels: bytemuck::pod_collect_to_vec(raw) });
    }
    r.finished().then_some(BakedTable { grid, terms, levels: out, report })
}
