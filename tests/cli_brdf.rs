//! `diffract brdf` and `diffract terms` as a user runs them: PNG and GSF input give the Bessel orders of a
//! sinusoidal grating, and hostile files end in one line and a non-zero exit.

mod common;

use std::path::PathBuf;
use std::process::Output;

use common::{assert_one_line_error, diffract};
use diffract::physics::formats::gsf;
use diffract::physics::heightfield::HeightField;

fn scratch(name: &str) -> PathBuf {
    common::scratch("cli_brdf", name)
}

fn bessel_j(m: i32, x: f64) -> f64 {
    const STEPS: usize = 512;
    (0..STEPS)
        .map(|i| {
            (m as f64 * i as f64 / STEPS as f64 * std::f64::consts::TAU
                - x * (i as f64 / STEPS as f64 * std::f64::consts::TAU).sin())
            .cos()
        })
        .sum::<f64>()
        / STEPS as f64
}

/// Parses the CSV into rows of (header → value).
fn csv(o: &Output) -> Vec<std::collections::HashMap<String, f64>> {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    assert_eq!(
        header.join(","),
        "lambda_nm,theta_i_deg,phi_i_deg,theta_r_deg,phi_r_deg,u,v,w,power,reflectance,brdf_sr"
    );
    lines.map(|l| header.iter().cloned().zip(l.split(',').map(|v| v.parse::<f64>().unwrap())).collect()).collect()
}

const A_UM: f64 = 0.1;
const PERIOD_PX: usize = 32;
const DX_UM: f64 = 0.05;

/// The grating as GSF and as a 16-bit PNG (grey g ↦ h = H·g/65535 with H = 2a, so h = a·(1 + cos)).
fn grating_files() -> (PathBuf, PathBuf) {
    let n = PERIOD_PX * 20;
    let phase = |x: usize| (std::f64::consts::TAU * x as f64 / PERIOD_PX as f64).cos();
    let gsf_path = scratch("sine.gsf");
    let hf = HeightField::new(n, 2, DX_UM, DX_UM, (0..2 * n).map(|i| A_UM * phase(i % n)).collect()).unwrap();
    gsf::write(&gsf_path, &hf, "sinusoidal grating").unwrap();
    let png_path = scratch("sine.png");
    let img = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_fn(n as u32, 2, |x, _| {
        image::Luma([(32767.5 * (1.0 + phase(x as usize))).round() as u16])
    });
    img.save(&png_path).unwrap();
    (gsf_path, png_path)
}

#[test]
fn both_inputs_and_both_methods_give_bessel_orders() {
    let (gsf_path, png_path) = grating_files();
    let d_um = PERIOD_PX as f64 * DX_UM;
    let lambda = 550.0;
    let views: Vec<String> =
        (0..=2).map(|m| format!("{},180", (m as f64 * lambda * 1e-3 / d_um).asin().to_degrees())).collect();
    for (file, extra) in [(&gsf_path, vec![]), (&png_path, vec!["--pixel-size-um", "0.05", "--height-um", "0.2"])] {
        for method in ["exact", "taylor"] {
            let mut args =
                vec!["brdf", "--heightfield", file.to_str().unwrap(), "--light-theta", "0", "--lambda", "550"];
            args.extend(extra.iter().copied());
            args.extend(["--method", method]);
            for v in &views {
                args.extend(["--view", v.as_str()]);
            }
            let rows = csv(&diffract(&args));
            assert_eq!(rows.len(), 3);
            for (m, row) in rows.iter().enumerate() {
                let k = std::f64::consts::TAU / (lambda * 1e-3);
                let expected = bessel_j(m as i32, k * row["w"] * A_UM).powi(2);
                let rel = (row["power"] - expected).abs() / expected;
                assert!(rel < 5e-3, "{} {method} m={m}: {} vs {expected}", file.display(), row["power"]);
            }
        }
    }
}

#[test]
fn flat_png_is_a_mirror() {
    let path = scratch("flat.png");
    image::GrayImage::from_pixel(16, 16, image::Luma([128])).save(&path).unwrap();
    let o = diffract(&[
        "brdf",
        "--heightfield",
        path.to_str().unwrap(),
        "--pixel-size-um",
        "0.1",
        "--height-um",
        "0.3",
        "--light-theta",
        "0",
        "--view",
        "0,0",
        "--view",
        "10,0",
        "--lambda",
        "400:700:100",
    ]);
    let rows = csv(&o);
    assert_eq!(rows.len(), 8, "4 wavelengths × 2 views, wavelength-major");
    for pair in rows.chunks(2) {
        assert_eq!(pair[0]["power"], 1.0);
        assert!((pair[0]["reflectance"] - 1.0).abs() < 1e-12);
        // In sr⁻¹: R₀·(k σ_s)²/π at the mirror (n = 1.5: R₀ = 0.04; σ_s = 65 µm / 4).
        let k_sigma = std::f64::consts::TAU / (pair[0]["lambda_nm"] * 1e-3) * 65.0 / 4.0;
        let peak = 0.04 * k_sigma * k_sigma / std::f64::consts::PI;
        assert!((pair[0]["brdf_sr"] / peak - 1.0).abs() < 1e-9, "{} vs {peak}", pair[0]["brdf_sr"]);
        assert!(pair[1]["power"] < 1e-12);
    }
}

/// The first order's width in direction cosines (the power's standard deviation along u) of a blazed grating (2.5 µm
/// period, 40 µm wide) at 550 nm under a light `radius_deg` in angular radius, from a `brdf` cut through it.
fn blazed_first_order_width(file: &str, radius_deg: &str) -> f64 {
    let o = diffract(&[
        "brdf",
        "--heightfield",
        file,
        "--light-theta",
        "0",
        "--light-radius-deg",
        radius_deg,
        "--view-theta",
        "8:17.5:0.01",
        "--view-phi",
        "180",
        "--lambda",
        "550",
    ]);
    let rows = csv(&o);
    let (mut m0, mut m1, mut m2) = (0.0, 0.0, 0.0);
    for pair in rows.windows(2) {
        let du = (pair[1]["u"] - pair[0]["u"]).abs();
        let (p, u) = ((pair[0]["power"] + pair[1]["power"]) / 2.0, (pair[0]["u"] + pair[1]["u"]) / 2.0);
        (m0, m1, m2) = (m0 + p * du, m1 + p * u * du, m2 + p * u * u * du);
    }
    let mean = m1 / m0;
    assert!((mean.abs() - 0.22).abs() < 1e-3, "the first order lies at |u| = λ/d = 0.22, not {mean}");
    (m2 / m0 - mean * mean).sqrt()
}

#[test]
fn a_lamps_first_order_is_wider_than_the_suns_by_the_ratio_of_their_radii() {
    let (n, period, dx) = (800, 50, 0.05);
    let path = scratch("blazed.gsf");
    let heights = (0..2 * n).map(|i| 0.25 * ((i % n) % period) as f64 / period as f64).collect();
    gsf::write(&path, &HeightField::new(n, 2, dx, dx, heights).unwrap(), "blazed grating").unwrap();
    let file = path.to_str().unwrap();
    let sun_deg = diffract::physics::sky::sun_angular_radius().to_degrees();
    let sun = blazed_first_order_width(file, &sun_deg.to_string());
    let lamp = blazed_first_order_width(file, "1");
    // model.md §1.13: the coherence length scales as 1/α, so the lobe (a single line under the window) as α.
    let (ratio, predicted) = (lamp / sun, 1.0 / sun_deg);
    eprintln!("first order σ_u: sun {sun:.5}, 1° lamp {lamp:.5}: ratio {ratio:.3} (predicted {predicted:.3})");
    assert!((ratio / predicted - 1.0).abs() < 0.1, "ratio {ratio} against {predicted}");
    let at_normal = |extra: &[&str]| {
        let args = ["brdf", "--heightfield", file, "--light-theta", "0", "--view", "0,0", "--lambda", "550"];
        diffract(&[&args[..], extra].concat())
    };
    assert_one_line_error(&at_normal(&["--light-radius-deg", "1", "--coherence-um", "30"]), "not both");
    let huge = at_normal(&["--light-radius-deg", "40"]);
    assert_one_line_error(&huge, "--light-radius-deg: a light 40° in angular radius");
}

fn brdf_on(file: &str, extra: &[&str]) -> Output {
    let mut args = vec!["brdf", "--heightfield", file, "--light-theta", "0", "--view", "0,0", "--lambda", "500"];
    args.extend_from_slice(extra);
    diffract(&args)
}

#[test]
fn the_taylor_order_is_forced_by_its_name_or_its_first_one() {
    let afm = common::place::afm("elaphe-100px.png");
    let afm = afm.to_str().unwrap();
    let png = ["--pixel-size-um", "0.065", "--height-um", "0.375", "--method", "taylor", "--accept-f32-error"];
    let by = |flag| brdf_on(afm, &[&[flag, "3"][..], &png].concat());
    let (order, terms) = (by("--order"), by("--terms"));
    assert!(order.status.success(), "{}", String::from_utf8_lossy(&order.stderr));
    assert_eq!(order.stdout, terms.stdout);
    assert!(String::from_utf8_lossy(&order.stderr).contains("N = 3"), "{}", String::from_utf8_lossy(&order.stderr));
}

#[test]
fn hostile_input_is_refused_in_one_line() {
    let png = ["--pixel-size-um", "0.1", "--height-um", "0.3"];
    assert_one_line_error(&brdf_on("/no/such/file.gsf", &[]), "cannot open");
    let colour = scratch("colour.png");
    image::RgbImage::from_pixel(4, 4, image::Rgb([10, 200, 30])).save(&colour).unwrap();
    assert_one_line_error(&brdf_on(colour.to_str().unwrap(), &png), "real colour");
    let grey_rgb = scratch("grey-rgb.png");
    image::RgbaImage::from_pixel(4, 4, image::Rgba([90, 90, 90, 255])).save(&grey_rgb).unwrap();
    assert!(brdf_on(grey_rgb.to_str().unwrap(), &png).status.success(), "grey stored as RGBA is grey");
    let truncated = scratch("truncated.png");
    let bytes = std::fs::read(&colour).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    assert_one_line_error(&brdf_on(truncated.to_str().unwrap(), &png), "truncated.png");
    let garbage = scratch("garbage.gsf");
    std::fs::write(&garbage, b"\x89PNG not really").unwrap();
    assert_one_line_error(&brdf_on(garbage.to_str().unwrap(), &[]), "not a Gwyddion");
    assert_one_line_error(&brdf_on(grey_rgb.to_str().unwrap(), &[]), "--pixel-size-um");
    assert_one_line_error(
        &brdf_on(grey_rgb.to_str().unwrap(), &["--pixel-size-um", "0", "--height-um", "0.3"]),
        "positive",
    );
    assert_one_line_error(
        &brdf_on(grey_rgb.to_str().unwrap(), &["--pixel-size-um", "-1", "--height-um", "0.3"]),
        "positive",
    );
    // A PNG header that claims a huge image is refused before decoding.
    let huge = scratch("huge.png");
    let mut header = bytes[..33].to_vec();
    header[16..20].copy_from_slice(&100_000u32.to_be_bytes());
    header[20..24].copy_from_slice(&100_000u32.to_be_bytes());
    std::fs::write(&huge, &header).unwrap();
    let o = brdf_on(huge.to_str().unwrap(), &png);
    assert!(!o.status.success() && !String::from_utf8_lossy(&o.stderr).contains("panicked"));
}

#[test]
fn invalid_parameters_are_errors_not_zeros() {
    let (gsf_path, _) = grating_files();
    let f = gsf_path.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["brdf", "--heightfield", f];
        args.extend_from_slice(extra);
        diffract(&args)
    };
    assert_one_line_error(&run(&["--light-theta", "0", "--view", "90,0", "--lambda", "500"]), "horizon");
    assert_one_line_error(&run(&["--light-theta", "95", "--view", "10,0", "--lambda", "500"]), "horizon");
    assert_one_line_error(&run(&["--light-theta", "0", "--view", "10,0", "--lambda", "0"]), "λ");
    assert_one_line_error(&run(&["--light-theta", "0", "--view-theta", "10:0:1", "--lambda", "500"]), "TO is below");
    assert_one_line_error(&run(&["--light-theta", "0", "--lambda", "500"]), "--view");
    assert_one_line_error(
        &run(&["--light-theta", "0", "--view", "10,0", "--lambda", "500", "--coherence-um", "-3"]),
        "coherence",
    );
    assert_one_line_error(
        &run(&["--light-theta", "0", "--view", "10,0", "--lambda", "500", "--method", "taylor", "--terms", "999"]),
        "limit",
    );
}

#[test]
fn grazing_rows_are_finite() {
    let (gsf_path, _) = grating_files();
    let rows = csv(&diffract(&[
        "brdf",
        "--heightfield",
        gsf_path.to_str().unwrap(),
        "--light-theta",
        "89.99",
        "--view-theta",
        "89.9,89.99",
        "--view-phi",
        "180",
        "--lambda",
        "500",
        "--method",
        "taylor",
    ]));
    for r in rows {
        assert!(r["power"].is_finite() && r["reflectance"].is_finite(), "{r:?}");
    }
}

#[test]
fn terms_reports_the_plan_for_the_afm_patch() {
    let afm = common::place::afm("elaphe-100px.png");
    let afm = afm.to_str().unwrap();
    let o =
        diffract(&["terms", "--heightfield", afm, "--pixel-size-um", "0.065", "--height-um", "0.375", "--tile", "3"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("300×300 pixels") && out.contains("Taylor order N ="), "{out}");
}

#[test]
fn map_renders_every_approach_validation_clean_with_exr() {
    let patch = scratch("map-blazed.gsf");
    let o = diffract(&[
        "gen",
        "patch",
        "blazed",
        "--size-um",
        "13",
        "--pixel-um",
        "0.05",
        "--out",
        patch.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for approach in ["flss", "nmm", "pq", "gem"] {
        let png = scratch(&format!("map-{approach}.png"));
        let exr = scratch(&format!("map-{approach}.exr"));
        let o = diffract(&[
            "map",
            "--heightfield",
            patch.to_str().unwrap(),
            "--light-theta",
            "0",
            "--light-phi",
            "-90",
            "--size",
            "33",
            "--approach",
            approach,
            "--lambda-step",
            "20",
            "--exposure",
            "4",
            "--out",
            png.to_str().unwrap(),
            "--exr",
            exr.to_str().unwrap(),
            "--validation",
            "--device",
            &common::place::test_device(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success() && !err.contains("validation"), "{approach}: {err}");
        let img = image::open(&png).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (33, 33));
        assert!(img.pixels().any(|p| p.0 != [0, 0, 0]), "{approach}: blank map");
        let linear = image::open(&exr).unwrap();
        assert!(
            matches!(linear, image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_)),
            "{approach}: EXR holds floats"
        );
        let max = linear.to_rgb32f().pixels().flat_map(|p| p.0).fold(0.0f32, f32::max);
        assert!(max > 0.1, "{approach}: the specular reflection is in the linear EXR ({max})");
    }
}

#[test]
fn map_refuses_bad_input_in_one_line() {
    let patch = scratch("map-flat.gsf");
    assert!(diffract(&["gen", "patch", "flat", "--size-um", "2", "--out", patch.to_str().unwrap()]).status.success());
    let p = patch.to_str().unwrap();
    let out = scratch("never.png");
    let o = out.to_str().unwrap();
    assert_one_line_error(&diffract(&["map", "--heightfield", p, "--light-theta", "90", "--out", o]), "horizon");
    assert_one_line_error(
        &diffract(&["map", "--heightfield", p, "--light-theta", "0", "--out", "/nope/x.png"]),
        "does not exist",
    );
    assert_one_line_error(
        &diffract(&["map", "--heightfield", p, "--light-theta", "0", "--out", o, "--exr", "x.tiff"]),
        ".exr",
    );
    assert_one_line_error(
        &diffract(&["map", "--heightfield", p, "--light-theta", "0", "--out", o, "--lambda-step", "0"]),
        "step",
    );
    assert_one_line_error(
        &diffract(&["map", "--heightfield", p, "--light-theta", "0", "--out", o, "--device", "nope"]),
        "nope",
    );
    let tall = scratch("map-tall.gsf");
    assert!(diffract(&[
        "gen",
        "patch",
        "blazed",
        "--size-um",
        "13",
        "--height-um",
        "3",
        "--out",
        tall.to_str().unwrap()
    ])
    .status
    .success());
    assert_one_line_error(
        &diffract(&["map", "--heightfield", tall.to_str().unwrap(), "--light-theta", "0", "--out", o]),
        "f32",
    );
}

#[test]
fn brdf_gpu_prints_the_same_csv_as_the_cpu() {
    let (gsf_path, _) = grating_files();
    let args = [
        "brdf",
        "--heightfield",
        gsf_path.to_str().unwrap(),
        "--light-theta",
        "0",
        "--view-theta",
        "0:40:5",
        "--view-phi",
        "180",
        "--lambda",
        "500,600",
    ];
    let cpu = csv(&diffract(&[&args[..], &["--method", "taylor"]].concat()));
    let gpu =
        csv(&diffract(&[&args[..], &["--gpu", "--validation", "--device", &common::place::test_device()]].concat()));
    assert_eq!(cpu.len(), gpu.len());
    for (c, g) in cpu.iter().zip(&gpu) {
        for key in ["lambda_nm", "theta_r_deg", "u", "v", "w"] {
            assert_eq!(c[key], g[key]);
        }
        if c["power"] > 1e-4 {
            assert!((c["power"] - g["power"]).abs() / c["power"] < 1e-3, "{c:?} vs {g:?}");
        }
    }
    let o = diffract(&[&args[..], &["--gpu", "--method", "exact"]].concat());
    assert_one_line_error(&o, "--gpu evaluates the Taylor sum");
}

/// The material settings are one declaration (src/material/settings.rs): every command takes the same flags, old names
/// still work, and a command that does not read a setting says so instead of ignoring it.
#[test]
fn settings_flags_are_shared_and_old_names_still_work() {
    let patch = scratch("settings-flat.gsf");
    assert!(diffract(&["gen", "patch", "flat", "--size-um", "2", "--out", patch.to_str().unwrap()]).status.success());
    let p = patch.to_str().unwrap();
    let terms = |extra: &[&str]| {
        let mut args = vec!["terms", "--heightfield", p];
        args.extend_from_slice(extra);
        diffract(&args)
    };
    // `--terms` is the Taylor order's first name, `--strict` the strict table's.
    for (new, old) in [
        (["--order", "3"], ["--terms", "3"]),
        (["--strict-table", "--window-radius=2"], ["--strict", "--window-radius=2"]),
    ] {
        let (a, b) = (terms(&new), terms(&old));
        assert!(a.status.success() && b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
        assert_eq!(a.stdout, b.stdout, "{new:?} and {old:?} are one setting");
    }
    assert!(String::from_utf8_lossy(&terms(&["--order", "3"]).stdout).contains("N = 3"));
    // A setting `terms` does not read is refused, and hidden from its help.
    assert_one_line_error(&terms(&["--approach", "gem"]), "--approach has no effect on `diffract terms`");
    assert_one_line_error(&terms(&["--lambda-step", "10"]), "--lambda-step-nm has no effect");
    assert_one_line_error(&terms(&["--window-radius", "17"]), "0 to 16");
    let help = String::from_utf8_lossy(&diffract(&["terms", "--help"]).stdout).to_string();
    assert!(help.contains("--coherence-um") && !help.contains("--approach"), "{help}");
    let help = String::from_utf8_lossy(&diffract(&["render", "--help"]).stdout).to_string();
    for flag in ["--approach", "--order", "--lambda-step-nm", "--coherence-um", "--table-tolerance", "--strict-table"] {
        assert!(help.contains(flag), "render --help lacks {flag}");
    }
}
