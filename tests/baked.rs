//! The baked table against the exact CPU evaluation (no GPU): its values at texel centres on both build paths,
//! its texel averages and its coarsest mip level against means computed directly, its degree in w, its cache.
//! "Exact" is `Reference` with `Method::Exact` (the DFT of exp(i·k·w·h) itself at the window's bins, no Taylor
//! series, no FFT) or, where a patch is too large for that, the f64 Taylor sum to 10⁻¹⁰; both at 1 nm steps.

use diffract::physics::baked::sample::{MipFilter, TableMips};
use diffract::physics::baked::{
    build, cache, Domain, Grid, TablePlan, TableRequest, DEFAULT_TABLE_TOLERANCE, FOOTPRINT_LOD_BIAS,
};
use diffract::physics::coherence::CoherenceWindow;
use diffract::physics::exact::{Method, Query, Reference};
use diffract::physics::heightfield::HeightField;
use diffract::physics::spectrum::Sampling;
use glam::DVec3;

#[path = "common/place.rs"]
mod place;

/// Heights from a small deterministic generator, `amplitude` µm peak to peak.
fn noise(n: usize, seed: u64, amplitude: f64) -> Vec<f64> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            amplitude * (s >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

/// A random 8×8 cell of 0.1 µm pixels tiled 8×: a 6.4 µm patch whose spectrum lives on every 8th bin. Under a
/// 6.4 µm coherence the window is 0.64 bins wide, so lobes 8 bins apart do not interfere (the lattice path).
fn tiled() -> HeightField {
    HeightField::new(8, 8, 0.1, 0.1, noise(64, 7, 0.25)).unwrap().tiled(8, 8).unwrap()
}

/// A random 24×24 patch of 0.1 µm pixels, no tiling (the coherent path).
fn dense() -> HeightField {
    HeightField::new(24, 24, 0.1, 0.1, noise(576, 11, 0.25)).unwrap()
}

fn reference(hf: &HeightField, coherence_um: f64, method: Method) -> Reference {
    let (lx, ly) = hf.size_um();
    let window = CoherenceWindow::new(lx, ly, coherence_um, None).unwrap();
    let plan = match method {
        Method::Exact => None,
        _ => {
            let q = [Query { lambda_nm: 380.0, theta_i: 0.0, phi_i: 0.0, theta_r: 0.0, phi_r: 0.0 }];
            Some(Reference::plan_for(hf, &window, &q, 1e-10, None).unwrap())
        }
    };
    Reference::new(hf, window, method, plan).unwrap()
}

fn close(table: DVec3, exact: DVec3, rel: f64, what: &str) {
    let err = (table - exact).abs().max_element();
    assert!(err <= rel * exact.max_element() + 1e-9, "{what}: table {table} vs exact {exact} (error {err:.2e})");
}

/// A BRDF map's table (texel-centre values) at normal incidence for a map of `size` pixels.
fn map_table(hf: &HeightField, coherence_um: f64, size: u32) -> (TablePlan, diffract::physics::baked::BakedTable) {
    let light = DVec3::Z;
    let request = TableRequest {
        domain: Domain::map(light),
        footprint: 2.0 / f64::from(size),
        aligned: true,
        centres_only: false,
        segments: None,
        mass_only: false,
    };
    let plan = TablePlan::new(hf, coherence_um, &request, DEFAULT_TABLE_TOLERANCE).unwrap();
    let table = build::build(hf, &plan, None).unwrap();
    (plan, table)
}

#[test]
fn table_values_at_texel_centres_equal_the_exact_evaluation() {
    let sampling = Sampling::visible(1.0);
    for (name, hf, lattice) in [("tiled", tiled(), true), ("dense", dense(), false)] {
        let (lx, _) = hf.size_um();
        let (plan, table) = map_table(&hf, lx, 8);
        assert_eq!(plan.lattice, lattice, "{name}: {}", plan.describe());
        assert!(plan.point && table.terms >= 2, "{}", plan.describe());
        let exact = reference(&hf, lx, Method::Exact);
        let g = plan.grid;
        // Texels across the specular peak, the first orders and the dark between them, at both ends of the w
        // interval and inside it.
        let at = |fu: f64, fv: f64| ((fu * g.nu as f64) as usize, (fv * g.nv as f64) as usize);
        for (a, b) in [at(0.5, 0.5), at(0.52, 0.5), at(0.6, 0.45), at(0.2, 0.7), at(0.05, 0.1), at(0.97, 0.5)] {
            for t in [-0.95, 0.1, 0.9] {
                let w = g.w_of(t);
                let uvw = DVec3::new(g.u_centre(a), g.v_centre(b), w);
                close(
                    table.texel_xyz(a, b, w),
                    exact.spectral_xyz(uvw, &sampling),
                    2e-3,
                    &format!("{name} ({a}, {b}) w {w:.3}"),
                );
                // The filtered read at level 0 lands on the same value (texel centres are sample points).
                close(table.xyz(uvw, 0.0), exact.spectral_xyz(uvw, &sampling), 2e-3, name);
            }
        }
    }
}

#[test]
fn texel_averages_and_the_coarsest_level_equal_means_computed_directly() {
    // A scene's table (texel averages) over a small box of views of the tiled patch, texels wider than the lobes.
    let hf = tiled();
    let (lx, _) = hf.size_um();
    let domain = Domain { u: (-0.15, 0.15), v: (-0.15, 0.15), w: (-1.9, -1.7) };
    let request =
        TableRequest { domain, footprint: 0.12, aligned: false, centres_only: false, segments: None, mass_only: false };
    let plan = TablePlan::new(&hf, lx, &request, DEFAULT_TABLE_TOLERANCE).unwrap();
    assert!(plan.lattice && !plan.point && plan.grid.texel > plan.lobe_width.1, "{}", plan.describe());
    let table = build::build(&hf, &plan, None).unwrap();
    let exact = reference(&hf, lx, Method::Taylor);
    let sampling = Sampling::visible(1.0);
    let g: Grid = plan.grid;
    let w = -1.8;
    // The mean of B over `n`×`n` texels from (a0, b0): composite 6-point Gauss–Legendre on every texel (exact for
    // polynomials of degree 11 on each; the lobes are at least 0.4 texels wide).
    const NODES: [(f64, f64); 6] = [
        (-0.932_469_514_203_152, 0.171_324_492_379_170),
        (-0.661_209_386_466_265, 0.360_761_573_048_139),
        (-0.238_619_186_083_197, 0.467_913_934_572_691),
        (0.238_619_186_083_197, 0.467_913_934_572_691),
        (0.661_209_386_466_265, 0.360_761_573_048_139),
        (0.932_469_514_203_152, 0.171_324_492_379_170),
    ];
    let mean = |a0: usize, b0: usize, n: usize| {
        let mut sum = DVec3::ZERO;
        for b in b0..b0 + n {
            for a in a0..a0 + n {
                for &(y, wy) in &NODES {
                    for &(x, wx) in &NODES {
                        let u = g.u0 + (a as f64 + 0.5 + 0.5 * x) * g.texel;
                        let v = g.v0 + (b as f64 + 0.5 + 0.5 * y) * g.texel;
                        sum += exact.spectral_xyz(DVec3::new(u, v, w), &sampling) * (0.25 * wx * wy);
                    }
                }
            }
        }
        sum / (n * n) as f64
    };
    for (a, b) in [(g.nu / 2, g.nv / 2), (g.nu / 2 + 2, g.nv / 2 - 1), (1, g.nv - 2)] {
        close(table.texel_xyz(a, b, w), mean(a, b, 1), 2e-3, &format!("texel ({a}, {b})"));
    }
    // The coarsest level is one texel: the mean over the whole (square) table.
    assert_eq!(g.nu, g.nv);
    let coarsest = table.levels.len() - 1;
    assert_eq!((table.levels[coarsest].width, table.levels[coarsest].height), (1, 1));
    close(table.xyz(DVec3::new(0.0, 0.0, w), coarsest as f64), mean(0, 0, g.nu), 2e-3, "coarsest level");
}

#[test]
fn a_pixel_footprint_picks_the_level_a_third_of_its_variance_finer() {
    let hf = dense();
    let (_, table) = map_table(&hf, 2.4, 8);
    let t = table.grid.texel;
    assert_eq!(table.lod(0.5 * t), 0.0, "a footprint within a texel reads level 0");
    assert_eq!(table.lod(f64::NAN), 0.0);
    assert!((table.lod(8.0 * t) - (3.0 - FOOTPRINT_LOD_BIAS)).abs() < 1e-12);
    assert_eq!(table.lod(1e9 * t), (table.levels.len() - 1) as f64, "clamped to the coarsest level");
}

#[test]
fn the_nearest_mip_filter_reads_the_level_nearest_the_lod_and_auto_takes_it_on_a_cpu_device() {
    let hf = dense();
    let (_, table) = map_table(&hf, 2.4, 8);
    assert!(table.levels.len() >= 3, "{} levels", table.levels.len());
    let g = &table.grid;
    let w = 0.5 * (g.w.0 + g.w.1);
    // Points between texel centres, where a level's bilinear read differs from its neighbours'.
    for (fu, fv) in [(0.37, 0.61), (0.52, 0.23), (0.81, 0.77)] {
        let uvw = DVec3::new(g.u0 + fu * g.nu as f64 * g.texel, g.v0 + fv * g.nv as f64 * g.texel, w);
        for (lod, level) in [(0.3, 0.0), (0.7, 1.0), (1.2, 1.0), (1.6, 2.0)] {
            assert_eq!(table.xyz_filtered(uvw, lod, MipFilter::Nearest), table.xyz(uvw, level), "lod {lod}");
        }
        // Trilinear blends the two levels: at lod 1.25 it is a quarter of the way from level 1 to level 2.
        let (one, two) = (table.xyz(uvw, 1.0), table.xyz(uvw, 2.0));
        assert!((one - two).abs().max_element() > 1e-9 * one.abs().max_element(), "the levels differ here");
        let blended = table.xyz_filtered(uvw, 1.25, MipFilter::Linear);
        assert!((blended - (one + 0.25 * (two - one))).abs().max_element() <= 1e-12 + 1e-9 * one.max_element());
    }
    assert_eq!(TableMips::Auto.filter(true), MipFilter::Nearest);
    assert_eq!(TableMips::Auto.filter(false), MipFilter::Linear);
    for cpu in [false, true] {
        assert_eq!(TableMips::Linear.filter(cpu), MipFilter::Linear);
        assert_eq!(TableMips::Nearest.filter(cpu), MipFilter::Nearest);
    }
    assert_eq!([MipFilter::Linear, MipFilter::Nearest].map(MipFilter::texels_per_read), [8, 4]);
}

#[test]
fn deeper_structures_need_more_terms_in_w() {
    let shallow = HeightField::new(8, 8, 0.1, 0.1, noise(64, 3, 0.1)).unwrap().tiled(8, 8).unwrap();
    let deep = HeightField::new(8, 8, 0.1, 0.1, noise(64, 3, 0.8)).unwrap().tiled(8, 8).unwrap();
    // One series over the whole interval (segments would each need fewer terms).
    let request = TableRequest {
        domain: Domain::HEMISPHERE,
        footprint: 0.05,
        aligned: false,
        centres_only: false,
        segments: Some(1),
        mass_only: false,
    };
    let plan = |hf: &HeightField| TablePlan::new(hf, 6.4, &request, DEFAULT_TABLE_TOLERANCE).unwrap();
    let (a, b) = (plan(&shallow), plan(&deep));
    assert!(b.terms > a.terms + 4, "{} vs {}", a.describe(), b.describe());
    assert!(b.nodes.count > a.nodes.count, "the build samples w more densely for the deeper structure");
    for p in [&a, &b] {
        assert!(p.estimate.tail <= DEFAULT_TABLE_TOLERANCE && p.estimate.every_lobe, "{}", p.describe());
        assert!(p.nodes.unseen.iter().all(|&u| u <= 0.25e-10), "{:?}", p.nodes);
    }
}

#[test]
fn a_cached_table_reads_back_as_built_and_only_for_its_plan() {
    let hf = dense();
    let (plan, table) = map_table(&hf, 2.4, 8);
    let dir = place::scratch_root().join("baked-cache");
    let _ = std::fs::remove_dir_all(&dir);
    cache::write(&dir, &hf, &plan, &table).unwrap();
    assert_eq!(cache::read(&dir, &hf, &plan).as_ref(), Some(&table));
    let entries = || std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect::<Vec<_>>();
    let files = entries();
    assert_eq!(files.len(), 1, "{files:?}");
    let (other, _) = map_table(&hf, 2.4, 16);
    assert_eq!(cache::read(&dir, &hf, &other), None, "a file is read only for the grid it was built for");
    // A changed byte anywhere, a truncated file and an appended one are refused, not misread.
    let bytes = std::fs::read(&files[0]).unwrap();
    for at in [9, bytes.len() / 2, bytes.len() - 1] {
        let mut changed = bytes.clone();
        changed[at] ^= 0x40;
        std::fs::write(&files[0], &changed).unwrap();
        assert_eq!(cache::read(&dir, &hf, &plan), None, "byte {at} changed");
    }
    std::fs::write(&files[0], &bytes[..bytes.len() - 4]).unwrap();
    assert_eq!(cache::read(&dir, &hf, &plan), None);
    std::fs::write(&files[0], [bytes.as_slice(), &[0; 4]].concat()).unwrap();
    assert_eq!(cache::read(&dir, &hf, &plan), None);
    std::fs::write(&files[0], &bytes).unwrap();
    assert_eq!(cache::read(&dir, &hf, &plan).as_ref(), Some(&table), "restored, it reads back");
}

#[test]
fn between_texel_centres_the_table_interpolates_within_a_colour_difference_of_one() {
    // A map table read where pixel centres fall half a texel off every node (the worst case for bilinear
    // interpolation), against the exact colour there: the table resolves the lobes, so the colour holds.
    let hf = tiled();
    let (lx, _) = hf.size_um();
    let (plan, table) = map_table(&hf, lx, 32);
    let exact = reference(&hf, lx, Method::Taylor);
    let sampling = Sampling::visible(1.0);
    let g = plan.grid;
    let w = -1.8;
    let mut des = Vec::new();
    for b in (2..g.nv - 2).step_by(g.nv / 12) {
        for a in (2..g.nu - 2).step_by(g.nu / 24) {
            let uvw = DVec3::new(g.u_centre(a) + 0.5 * g.texel, g.v_centre(b) + 0.5 * g.texel, w);
            let de =
                diffract::reference::exact_image::delta_e(table.xyz(uvw, 0.0), exact.spectral_xyz(uvw, &sampling), 4.0);
            des.push(de);
        }
    }
    let mean = des.iter().sum::<f64>() / des.len() as f64;
    let worst = des.iter().copied().fold(0.0, f64::max);
    eprintln!("between nodes: mean ΔE00 {mean:.3}, worst {worst:.3} over {} points", des.len());
    assert!(mean < 1.0 && worst < 5.0, "mean {mean}, worst {worst}");
}

/// A map read at its pixel centres only (no footprint filter) gets one texel per pixel, each the exact colour of
/// its pixel's centre; a filtered map keeps the finer texels its lobes need.
#[test]
fn a_map_read_at_pixel_centres_has_one_texel_per_pixel() {
    let hf = dense();
    let (lx, _) = hf.size_um();
    let size = 24;
    let request = |centres_only| TableRequest {
        domain: Domain::map(DVec3::Z),
        footprint: 2.0 / f64::from(size),
        aligned: true,
        centres_only,
        segments: None,
        mass_only: false,
    };
    let point = TablePlan::new(&hf, lx, &request(true), DEFAULT_TABLE_TOLERANCE).unwrap();
    let filtered = TablePlan::new(&hf, lx, &request(false), DEFAULT_TABLE_TOLERANCE).unwrap();
    assert_eq!((point.grid.nu, point.grid.nv), (size as usize, size as usize), "{}", point.describe());
    assert!(filtered.grid.nu > point.grid.nu, "the lobes ask for finer texels: {}", filtered.describe());
    let table = build::build(&hf, &point, None).unwrap();
    let exact = reference(&hf, lx, Method::Exact);
    let sampling = Sampling::visible(1.0);
    let g = point.grid;
    // A map's pixel centres lie at −1 + (i + ½)·2/size in u and in v (glsl/map.frag.glsl): each is a texel's centre.
    for (x, y) in [(12, 12), (13, 12), (5, 17), (20, 3)] {
        let (u, v) =
            (-1.0 + (f64::from(x) + 0.5) * 2.0 / f64::from(size), -1.0 + (f64::from(y) + 0.5) * 2.0 / f64::from(size));
        assert!((g.u_centre(x as usize) - u).abs() < 1e-12 && (g.v_centre(y as usize) - v).abs() < 1e-12);
        let w = -(1.0 - u * u - v * v).max(0.0).sqrt() - 1.0;
        let uvw = DVec3::new(u, v, w.clamp(g.w.0, g.w.1));
        close(table.xyz(uvw, 0.0), exact.spectral_xyz(uvw, &sampling), 2e-3, &format!("pixel ({x}, {y})"));
    }
}
