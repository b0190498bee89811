//! The extremes grid: the measured scans at 1× to 16× their heights, patches from 2² to 4096² pixels, coherence
//! lengths from 1 µm to 1 m, lights and views up to 89.99°, wavelengths from 360 to 830 nm — through every
//! evaluator of P (`exact`, `taylor`, `taylor-f32`, the GPU's compute shader) and a BRDF map per approach.
//!
//! Every evaluation must end in one of two ways:
//! - **pass**: every value finite, and within the tolerance of `exact` — for P, the amplitude difference
//!   | |P| − |P_exact| | ≤ 2·tolerance (the plan's truncation bound and its rounding estimate are each held to
//!   the tolerance); for a map, every pixel finite and its mean CIEDE2000 against the exact reference image
//!   within the approach's stated accuracy ([`map_bound`]);
//! - **refused**, with the reason, in the same words a user reads.
//!
//! Anything else — a non-finite value, a value outside the tolerance, a refusal of `exact`, a panic — fails.
//! `cargo test` runs a coarse grid ([`coarse_grid`]); `scripts/extremes.sh` runs the full one ([`full_grid`],
//! release build) and writes the summary docs/reliability.md quotes to `docs/extremes.md`.

#[path = "gpu/harness.rs"]
mod harness;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::Instant;

use diffract::gpu::vk::Context;
use diffract::material::{Approach, Settings};
use diffract::material::{Material, Reach};
use diffract::physics::exact::{Method, Query, Sample};
use diffract::physics::formats::png::PngScale;
use diffract::physics::heightfield::HeightField;
use diffract::reference::brdf::Evaluator;
use diffract::reference::exact_image::{image_error, ReferenceJob, ReferenceMaterial};
use diffract::render::map;

/// The tolerance on |P − P_N| every evaluation is asked for (the CLI's default).
const TOLERANCE: f64 = 1e-4;

/// A height field of the grid, with the words the summary uses for it.
struct Patch {
    label: String,
    hf: HeightField,
}

/// A measured scan (`assets/afm/<name>-100px.png`, 0.065 µm pixels) with its heights scaled by `scale`.
fn scan(name: &str, height_um: f64, scale: f64) -> HeightField {
    let path = harness::place::afm(&format!("{name}-100px.png"));
    diffract::physics::formats::load(&path, Some(PngScale { pixel_size_um: 0.065, height_um: height_um * scale }))
        .unwrap()
}

fn elaphe(scale: f64) -> HeightField {
    scan("elaphe", 0.375, scale)
}

fn xenopeltis(scale: f64) -> HeightField {
    scan("xenopeltis", 0.44, scale)
}

/// The measured patch at `scale`× height, cut to its top-left `n`² pixels (n ≤ 100) or a 64² cut tiled to `n`².
fn sized(label: &str, hf: HeightField, n: usize) -> Patch {
    let hf = if n <= hf.nx { hf.corner(n, n) } else { hf.corner(64, 64).tiled(n / 64, n / 64).unwrap() };
    Patch { label: format!("{label} {n}²"), hf }
}

/// A block of the grid: patches × coherence lengths × light inclinations × wavelengths, each with every view.
struct Block {
    patches: Vec<Patch>,
    coherences_um: Vec<f64>,
    light_thetas: Vec<f64>,
    lambdas_nm: Vec<f64>,
    view_thetas: Vec<f64>,
    view_phis: Vec<f64>,
}

/// The maps: every approach on each patch, coherence length and light inclination, at one size.
struct Maps {
    patches: Vec<Patch>,
    size: u32,
    light_thetas: Vec<f64>,
    coherences_um: Vec<f64>,
}

/// A grid: blocks of P evaluations (the cost of the exact sum grows with the patch's pixels times its window's
/// taps, so large patches get a block of their own with fewer points) and the maps.
struct Grid {
    blocks: Vec<Block>,
    maps: Vec<Maps>,
}

/// How one evaluation ended.
#[derive(Clone, Debug)]
enum Outcome {
    /// The worst amplitude difference from exact (P), or the mean ΔE00 (maps).
    Pass(f64),
    /// A map of an approximate approach outside its stated domain, evaluated with a warning that says so: its
    /// mean ΔE00 (finite, but not held to the approach's bound).
    Warned(f64),
    Refused(String),
    Fail(String),
}

/// One evaluation of the grid.
struct Record {
    point: String,
    evaluator: String,
    values: usize,
    outcome: Outcome,
}

/// The views of one light: every (θ_r, φ_r) of the grid plus the mirror direction (w → 0 at grazing light).
fn views(block: &Block, theta_i: f64) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> =
        block.view_thetas.iter().flat_map(|&t| block.view_phis.iter().map(move |&p| (t, p))).collect();
    v.push((theta_i, 180.0));
    v
}

fn accuracy(coherence_um: f64) -> Settings {
    Settings { tolerance: TOLERANCE, coherence_um, ..Settings::default() }
}

/// Compares an evaluator's values with exact's.
fn judge(samples: &[Sample], exact: &[Sample]) -> Outcome {
    let mut worst: f64 = 0.0;
    for (s, e) in samples.iter().zip(exact) {
        if !(s.power.is_finite() && s.reflectance.is_finite()) {
            return Outcome::Fail(format!("non-finite value at {:?}", s.query));
        }
        let diff = (s.power.sqrt() - e.power.sqrt()).abs();
        worst = worst.max(diff);
        if diff > 2.0 * TOLERANCE {
            return Outcome::Fail(format!(
                "|P| = {:.6e} against exact {:.6e} (difference {diff:.2e} > 2·{TOLERANCE:e}) at {:?}",
                s.power.sqrt(),
                e.power.sqrt(),
                s.query
            ));
        }
    }
    Outcome::Pass(worst)
}

/// The mean CIEDE2000 a map of `approach` may differ from the exact reference by (at its default settings):
/// FLSS and baked converge to the reference; NMM, PQ and Stam's grating are approximations by design (their
/// documented errors on the measured scans are mean ΔE00 0.3–3), held here to bounds that catch a broken or
/// black map, not to the reference's accuracy.
fn map_bound(approach: Approach) -> f64 {
    match approach {
        Approach::Flss | Approach::Baked => 1.0,
        Approach::Nmm | Approach::Pq => 5.0,
        Approach::Gem => 20.0,
    }
}

/// Every evaluator on one (patch, coherence, light, wavelength) point.
fn brdf_point(
    ctx: &Context,
    patch: &Patch,
    coherence_um: f64,
    theta_i: f64,
    lambda_nm: f64,
    block: &Block,
) -> Vec<Record> {
    let queries: Vec<Query> = views(block, theta_i)
        .into_iter()
        .map(|(theta_r, phi_r)| Query { lambda_nm, theta_i, phi_i: 0.0, theta_r, phi_r })
        .collect();
    let point = format!("{}, L = {coherence_um} µm, θ_i = {theta_i}°, λ = {lambda_nm} nm", patch.label);
    let acc = accuracy(coherence_um);
    let run = |e: Evaluator| diffract::reference::brdf::evaluate(&patch.hf, &queries, e, &acc, Some(ctx));
    let record = |e: Evaluator, outcome: Outcome| Record {
        point: point.clone(),
        evaluator: e.name().to_string(),
        values: queries.len(),
        outcome,
    };
    let exact_evaluator = Evaluator::Cpu(Method::Exact);
    let exact = match run(exact_evaluator) {
        Ok(e) => e.samples,
        Err(e) => return vec![record(exact_evaluator, Outcome::Fail(format!("exact refused: {e}")))],
    };
    let mut out = vec![record(exact_evaluator, judge(&exact, &exact))];
    for e in Evaluator::ALL.into_iter().skip(1) {
        let outcome = match run(e) {
            Ok(ev) => judge(&ev.samples, &exact),
            Err(err) => Outcome::Refused(err.to_string()),
        };
        out.push(record(e, outcome));
    }
    out
}

/// A map of every approach on one (patch, coherence, light) point against the exact reference image.
fn map_point(ctx: &Context, patch: &Patch, coherence_um: f64, theta_i: f64, size: u32) -> Vec<Record> {
    let light = diffract::physics::optics::direction(theta_i, 0.0);
    let point = format!("{}, L = {coherence_um} µm, θ_i = {theta_i}°, {size}² map", patch.label);
    let job = ReferenceJob {
        materials: vec![ReferenceMaterial { heightfield: &patch.hf, coherence_um, illuminant: Default::default() }],
        width: size,
        height: size,
        pixels: ReferenceJob::map_pixels(size, light),
    };
    let pixels = job.pixels.iter().flatten().count();
    let record = |name: &str, outcome: Outcome| Record {
        point: point.clone(),
        evaluator: format!("map {name}"),
        values: pixels,
        outcome,
    };
    let reference = match job.compute(None) {
        Ok(r) => r,
        Err(e) => return vec![record("reference", Outcome::Fail(format!("the exact reference refused: {e}")))],
    };
    Approach::ALL
        .into_iter()
        .map(|approach| {
            let settings = Settings { approach, coherence_um, ..Default::default() };
            let mut warned = false;
            let outcome = Material::prepare(&patch.hf, settings, &Reach::Map { light, size, filtered: false })
                .and_then(|m| {
                    warned = m.caveat().is_some();
                    map::render_map(ctx, &m, size, light, false)
                })
                .map_err(|e| e.to_string())
                .and_then(|map| {
                    if map.non_finite() > 0 {
                        return Err(format!("FAIL: {} non-finite pixels", map.non_finite()));
                    }
                    image_error(&reference, &map.rgba, 0.0).map_err(|e| format!("FAIL: {e}"))
                });
            let outcome = match outcome {
                Ok(err) if warned => Outcome::Warned(err.mean_de),
                Ok(err) if err.mean_de <= map_bound(approach) => Outcome::Pass(err.mean_de),
                Ok(err) => Outcome::Fail(format!(
                    "mean ΔE00 {:.2} (p99 {:.1}) > {}",
                    err.mean_de,
                    err.p99_de,
                    map_bound(approach)
                )),
                Err(e) if e.starts_with("FAIL: ") => Outcome::Fail(e[6..].to_string()),
                Err(e) => Outcome::Refused(e),
            };
            record(approach.name(), outcome)
        })
        .collect()
}

/// Runs the grid on a validated lavapipe context (no message, no live allocation at the end).
fn run(grid: &Grid, progress: bool) -> Vec<Record> {
    harness::gpu_test(|ctx| {
        let mut records = Vec::new();
        let start = Instant::now();
        for block in &grid.blocks {
            for patch in &block.patches {
                for &coherence_um in &block.coherences_um {
                    for &theta_i in &block.light_thetas {
                        for &lambda_nm in &block.lambdas_nm {
                            records.extend(brdf_point(ctx, patch, coherence_um, theta_i, lambda_nm, block));
                        }
                    }
                }
                if progress {
                    eprintln!("{}: done ({:.0} s)", patch.label, start.elapsed().as_secs_f64());
                }
            }
        }
        for maps in &grid.maps {
            for patch in &maps.patches {
                for &coherence_um in &maps.coherences_um {
                    for &theta_i in &maps.light_thetas {
                        records.extend(map_point(ctx, patch, coherence_um, theta_i, maps.size));
                    }
                }
                if progress {
                    eprintln!("maps of {}: done ({:.0} s)", patch.label, start.elapsed().as_secs_f64());
                }
            }
        }
        records
    })
}

/// A refusal's reason in a few words (the class the summary counts).
fn reason(message: &str) -> &'static str {
    const CLASSES: [(&str, &str); 8] = [
        ("Chebyshev nodes over w", "baked table: more than 96 Chebyshev nodes in w"),
        ("f64 Taylor sum cannot reach", "f64 rounding of the Taylor sum above the tolerance"),
        ("f32 sums cannot reach", "f32 rounding above the tolerance"),
        ("GPU's f32 sums cannot reach", "f32 rounding above the tolerance"),
        ("taps either side", "full window wider than the shaders' 16 taps"),
        ("no Taylor order up to", "no Taylor order ≤ 200 reaches the tolerance"),
        ("MiB", "memory limit"),
        ("Out of memory", "device out of memory"),
    ];
    CLASSES.iter().find(|(needle, _)| message.contains(needle)).map_or("other", |c| c.1)
}

/// The summary: per evaluator, evaluations and values passed, refused (by reason) and failed; the worst pass.
fn summary(records: &[Record], seconds: f64) -> String {
    #[derive(Default)]
    struct Tally {
        passed: usize,
        values: usize,
        refused: BTreeMap<&'static str, usize>,
        failed: usize,
        worst: f64,
        warned: usize,
        worst_warned: f64,
    }
    let mut by: BTreeMap<&str, Tally> = BTreeMap::new();
    for r in records {
        let t = by.entry(r.evaluator.as_str()).or_default();
        match &r.outcome {
            Outcome::Pass(x) => {
                t.passed += 1;
                t.values += r.values;
                t.worst = t.worst.max(*x);
            }
            Outcome::Warned(x) => {
                t.warned += 1;
                t.worst_warned = t.worst_warned.max(*x);
            }
            Outcome::Refused(m) => *t.refused.entry(reason(m)).or_default() += 1,
            Outcome::Fail(_) => t.failed += 1,
        }
    }
    let values: usize = records.iter().map(|r| r.values).sum();
    let mut s = format!(
        "{} evaluations ({values} values) in {seconds:.0} s\n\n| evaluator | passed (values) | worst | warned \
         (worst) | refused | failed |\n|---|--:|--:|--:|---|--:|\n",
        records.len()
    );
    for (name, t) in &by {
        let worst = if name.starts_with("map") { format!("ΔE00 {:.3}", t.worst) } else { format!("{:.1e}", t.worst) };
        let refused: Vec<String> = t.refused.iter().map(|(why, n)| format!("{n}: {why}")).collect();
        let refused = if refused.is_empty() { "–".to_string() } else { refused.join("; ") };
        let warned = if t.warned > 0 { format!("{} (ΔE00 {:.1})", t.warned, t.worst_warned) } else { "–".into() };
        let _ = writeln!(s, "| {name} | {} ({}) | {worst} | {warned} | {refused} | {} |", t.passed, t.values, t.failed);
    }
    let mut others: Vec<&str> = records
        .iter()
        .filter_map(|r| match &r.outcome {
            Outcome::Refused(m) if reason(m) == "other" => Some(m.as_str()),
            _ => None,
        })
        .collect();
    others.sort_unstable();
    others.dedup();
    for m in others {
        let _ = writeln!(s, "\nrefused (other): {m}");
    }
    for r in records {
        if let Outcome::Fail(why) = &r.outcome {
            let _ = writeln!(s, "\nFAILED {} on {}: {why}", r.evaluator, r.point);
        }
    }
    s
}

/// What every grid must show: no failure, exact never refused, every evaluator passing somewhere, and the three
/// Taylor evaluators refusing together where f32 cannot reach the tolerance (f32 refusal ⇒ GPU refusal).
fn check(records: &[Record], text: &str) {
    assert!(records.iter().all(|r| !matches!(r.outcome, Outcome::Fail(_))), "{text}");
    // A maps-only run (DIFFRACT_EXTREMES_PART=maps) has no P evaluations to demand passes of.
    let has_p = records.iter().any(|r| r.evaluator == "exact");
    let required: &[&str] = if has_p {
        &["exact", "taylor", "taylor-f32", "gpu", "map flss", "map baked"]
    } else {
        &["map flss", "map baked"]
    };
    for &name in required {
        assert!(
            records.iter().any(|r| r.evaluator == name && matches!(r.outcome, Outcome::Pass(_))),
            "{name} never passed:\n{text}"
        );
    }
    let refused = |point: &str, name: &str| {
        records.iter().any(|r| r.point == point && r.evaluator == name && matches!(r.outcome, Outcome::Refused(_)))
    };
    for r in records.iter().filter(|r| r.evaluator == "taylor-f32") {
        if refused(&r.point, "taylor-f32") {
            assert!(refused(&r.point, "gpu"), "taylor-f32 refused on {} but the GPU evaluated it:\n{text}", r.point);
        }
    }
}

/// The grid `cargo test` runs: Elaphe at 1× and 16× (k·w·h up to ≈ 30), Xenopeltis at 4×, a 2² and a 256²
/// patch; 1 µm, 65 µm and 1 m coherence; lights and views at 0° to 89.99°; 360, 550 and 830 nm; maps of every
/// approach at 1× and 16×, normal and grazing light.
#[test]
fn coarse_grid() {
    let grid = Grid {
        blocks: vec![Block {
            patches: vec![
                sized("Elaphe 1×", elaphe(1.0), 100),
                sized("Elaphe 16×", elaphe(16.0), 100),
                sized("Xenopeltis 4×", xenopeltis(4.0), 100),
                sized("Elaphe 1×", elaphe(1.0), 2),
                sized("Elaphe 1×", elaphe(1.0), 256),
            ],
            coherences_um: vec![1.0, 65.0, 1e6],
            light_thetas: vec![0.0, 60.0, 89.99],
            lambdas_nm: vec![360.0, 550.0, 830.0],
            view_thetas: vec![0.0, 45.0, 89.99],
            view_phis: vec![0.0, 90.0],
        }],
        maps: vec![Maps {
            patches: vec![sized("Elaphe 1×", elaphe(1.0), 100), sized("Elaphe 16×", elaphe(16.0), 100)],
            size: 12,
            light_thetas: vec![0.0, 89.99],
            coherences_um: vec![65.0],
        }],
    };
    let start = Instant::now();
    let records = run(&grid, false);
    let text = summary(&records, start.elapsed().as_secs_f64());
    println!("{text}");
    check(&records, &text);
}

/// NMM, PQ and gem assume light coherent across the patch: where the coherence window spans more than a bin they
/// warn (the full grid measured mean ΔE00 up to 28 at 1 µm); at 65 µm they do not.
#[test]
fn approximations_warn_outside_their_domain() {
    let hf = elaphe(1.0);
    for approach in [Approach::Nmm, Approach::Pq, Approach::Gem, Approach::Flss] {
        let light = diffract::physics::optics::direction(0.0, 0.0);
        let caveat = |coherence_um: f64| {
            let settings = Settings { approach, coherence_um, ..Default::default() };
            Material::prepare(&hf, settings, &Reach::Map { light, size: 8, filtered: false }).unwrap().caveat()
        };
        assert!(caveat(65.0).is_none(), "{approach:?}");
        let narrow = caveat(1.0);
        assert_eq!(narrow.is_some(), approach != Approach::Flss, "{approach:?}: {narrow:?}");
    }
}

/// The full grid (`scripts/extremes.sh`, release build, minutes): heights 1×–16× of both scans, patches 2² to
/// 4096², coherence 1 µm to 1 m, more angles and wavelengths; its summary goes to `$DIFFRACT_EXTREMES_OUT`.
#[test]
#[ignore = "minutes in a release build: scripts/extremes.sh"]
fn full_grid() {
    let scales = [1.0, 2.0, 4.0, 8.0, 16.0];
    let scans = |scale: f64| {
        [
            sized(&format!("Elaphe {scale}×"), elaphe(scale), 100),
            sized(&format!("Xenopeltis {scale}×"), xenopeltis(scale), 100),
        ]
    };
    let grid = Grid {
        blocks: vec![
            Block {
                patches: scales.iter().flat_map(|&s| scans(s)).collect(),
                coherences_um: vec![1.0, 8.0, 65.0, 1000.0, 1e6],
                light_thetas: vec![0.0, 30.0, 60.0, 85.0, 89.99],
                lambdas_nm: vec![360.0, 450.0, 550.0, 700.0, 830.0],
                view_thetas: vec![0.0, 20.0, 45.0, 70.0, 89.0, 89.99],
                view_phis: vec![0.0, 45.0, 90.0, 180.0],
            },
            Block {
                patches: [2, 8, 32].iter().map(|&n| sized("Elaphe 1×", elaphe(1.0), n)).collect(),
                coherences_um: vec![1.0, 65.0, 1e6],
                light_thetas: vec![0.0, 60.0, 89.99],
                lambdas_nm: vec![360.0, 550.0, 830.0],
                view_thetas: vec![0.0, 45.0, 89.99],
                view_phis: vec![0.0, 90.0],
            },
            Block {
                patches: [1024, 4096].iter().map(|&n| sized("Elaphe 1×", elaphe(1.0), n)).collect(),
                coherences_um: vec![65.0, 1e6],
                light_thetas: vec![0.0, 89.99],
                lambdas_nm: vec![360.0, 830.0],
                view_thetas: vec![0.0, 89.99],
                view_phis: vec![0.0],
            },
        ],
        // A 1 µm coherence window spans 73×73 bins of a 6.5 µm patch: its reference image costs tens of minutes
        // at deep heights (the exact sum, or some 60 Taylor terms), so 1 µm maps are taken at 1× only; the
        // P evaluations above cover 1 µm at every height.
        maps: vec![
            Maps {
                patches: [1.0, 4.0, 16.0].iter().flat_map(|&s| scans(s)).collect(),
                size: 24,
                light_thetas: vec![0.0, 60.0, 89.99],
                coherences_um: vec![65.0, 1e6],
            },
            Maps {
                patches: scans(1.0).into(),
                size: 24,
                light_thetas: vec![0.0, 60.0, 89.99],
                coherences_um: vec![1.0],
            },
        ],
    };
    // DIFFRACT_EXTREMES_PART=maps runs the maps alone (the P blocks take most of the time).
    let mut grid = grid;
    if std::env::var("DIFFRACT_EXTREMES_PART").is_ok_and(|p| p == "maps") {
        grid.blocks.clear();
    }
    let start = Instant::now();
    let records = run(&grid, true);
    let text = summary(&records, start.elapsed().as_secs_f64());
    println!("{text}");
    if let Some(out) = std::env::var_os("DIFFRACT_EXTREMES_OUT") {
        std::fs::write(out, &text).unwrap();
    }
    check(&records, &text);
}
