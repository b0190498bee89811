//! The `diffract` binary as a user meets it: its outputs, and one clear line and a non-zero exit for every
//! mistake a user can make, never a panic.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{assert_one_line_error, diffract, place};

fn scratch(name: &str) -> PathBuf {
    common::scratch("cli", name)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn devices_lists_the_test_device() {
    let o = diffract(&["devices"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    if place::on_lavapipe() {
        assert!(out.contains("llvmpipe") && out.contains("CPU") && out.contains("1.3"), "{out}");
    } else {
        // A row of the table: index, name, type, then the Vulkan version (`1.4.312`).
        let versioned = |row: &str| row.split_whitespace().any(|w| w.starts_with("1.") && w.matches('.').count() == 2);
        assert!(out.lines().skip(1).any(versioned), "{out}");
    }
}

/// `diffract render` of a `size`² frame into `out` on the test device, with `extra` arguments.
fn render(out: &Path, size: &str, extra: &[&str]) -> Output {
    let device = place::test_device();
    let mut args = vec!["render", "--out", out.to_str().unwrap(), "--width", size, "--height", size];
    args.extend(["--device", device.as_str()]);
    args.extend(extra);
    diffract(&args)
}

#[test]
fn render_writes_a_nonblank_png_without_validation_messages() {
    let path = scratch("render.png");
    let _ = std::fs::remove_file(&path);
    let o = render(&path, "128", &["--validation"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("validation"), "{}", stderr(&o));
    let img = image::open(&path).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (128, 128));
    let first = img.get_pixel(0, 0);
    assert!(img.pixels().any(|p| p != first), "the image is blank");
}

/// What the help and the docs accept is accepted: `auto` where the help shows `[default: auto]`, the daylight
/// series' ends, an exposure at the scene files' limit.
#[test]
fn the_documented_values_are_accepted() {
    let accepted = ["--table-segments", "auto", "--order", "auto", "--illuminant", "D250", "--exposure", "100"];
    let o = render(&scratch("accepted.png"), "16", &accepted);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A flat `[render] background` under the sky is in the frame's units (the sun's radiance is 1): one far from
/// the sky's own light is named in a warning, one near it is not.
#[test]
fn a_background_far_from_the_skys_light_is_named() {
    let dir = scratch("background");
    std::fs::create_dir_all(&dir).unwrap();
    for (colour, warned) in [("[0.5, 0.7, 1.0]", true), ("[4e-6, 5e-6, 6e-6]", false)] {
        let scene = dir.join("bg.toml");
        std::fs::write(
            &scene,
            format!(
                "[camera]\nposition = [0.0, 0.5, 3.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 30.0\n\n[light]\n\
                 direction = [0.3, 1.0, 0.5]\nenvironment = \"sky\"\n\n[[object]]\nshape = \"sphere\"\n\
                 material = \"m\"\n\n[material.m]\ngenerate = \"flat\"\nsize_um = 2.0\napproach = \"gem\"\n\n\
                 [render]\nbackground = {colour}\n"
            ),
        )
        .unwrap();
        let o = render(&dir.join("bg.png"), "16", &[scene.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(stderr(&o).contains("is in the frame's units"), warned, "{colour}: {}", stderr(&o));
    }
}

#[test]
fn unknown_device_is_one_line() {
    assert_one_line_error(
        &diffract(&["render", "--device", "no-such-gpu", "--out", scratch("x.png").to_str().unwrap()]),
        "no-such-gpu",
    );
    assert_one_line_error(&diffract(&["render", "--device", "99", "--out", scratch("x.png").to_str().unwrap()]), "99");
}

#[test]
fn missing_driver_points_at_mesa() {
    let o = Command::new(place::diffract_bin())
        .args(["devices"])
        .env("VK_ICD_FILENAMES", "/nonexistent.json")
        .env("VK_DRIVER_FILES", "/nonexistent.json")
        .output()
        .unwrap();
    assert_one_line_error(&o, "mesa-vulkan-drivers");
}

#[test]
fn unwritable_output_is_one_line() {
    assert_one_line_error(&diffract(&["render", "--out", "/nonexistent-dir/x.png"]), "does not exist");
    assert_one_line_error(&diffract(&["render", "--out", scratch("x.jpg").to_str().unwrap()]), ".png");
}

#[test]
fn a_map_shader_asked_of_a_scene_and_a_frame_target_asked_of_a_map_are_refused_before_any_work() {
    let o = diffract(&["profile", "--width", "32", "--frames", "1", "--no-reference", "--sweep", "shader=compute"]);
    assert_one_line_error(&o, "for BRDF maps");
    let patch = place::assets().join("patches/blazed-1.6um.gsf");
    let args = ["profile", "--heightfield", patch.to_str().unwrap(), "--width", "32", "--frames", "1"];
    let o = diffract(&[&args[..], &["--no-reference", "--sweep", "target=display"]].concat());
    assert_one_line_error(&o, "is for scenes");
}

#[test]
fn bad_sizes_are_refused_by_the_parser() {
    let o = diffract(&["render", "--out", scratch("x.png").to_str().unwrap(), "--width", "0"]);
    assert!(!o.status.success());
    assert!(!stderr(&o).contains("panicked"));
}

#[test]
fn help_shows_examples() {
    let o = diffract(&["--help"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("Examples:"));
}

#[test]
fn the_places_a_test_needs_are_found() {
    let assets = place::assets();
    assert!(assets.join("afm/elaphe-100px.png").is_file(), "{}", assets.display());
    assert!(place::diffract_bin().is_file(), "{}", place::diffract_bin().display());
    // Set by the copy below: the copied binary must find what was carried beside it.
    if let Some(expected) = std::env::var_os("DIFFRACT_EXPECT_ASSETS") {
        assert_eq!(assets, PathBuf::from(expected));
    }
}

#[test]
fn a_test_binary_copied_elsewhere_finds_the_binary_and_assets_carried_with_it() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch("carried");
    let _ = std::fs::remove_dir_all(&dir);
    let deps = dir.join("target/release/deps");
    std::fs::create_dir_all(dir.join("assets/afm")).unwrap();
    std::fs::create_dir_all(&deps).unwrap();
    std::fs::copy(place::afm("elaphe-100px.png"), dir.join("assets/afm/elaphe-100px.png")).unwrap();
    let copy = deps.join("cli-copy");
    std::fs::copy(std::env::current_exe().unwrap(), &copy).unwrap();
    // The carried `diffract` leaves a mark, then runs the real one.
    let bin = dir.join("target/release/diffract");
    let real = place::diffract_bin();
    let script = format!("#!/bin/sh\ntouch \"$(dirname \"$0\")/used\"\nexec '{}' \"$@\"\n", real.display());
    std::fs::write(&bin, script).unwrap();
    std::fs::set_permissions(&bin, std::fs::Permissions::from_mode(0o755)).unwrap();
    let o = Command::new(&copy)
        .args(["--exact", "devices_lists_the_test_device", "the_places_a_test_needs_are_found"])
        .env_remove("DIFFRACT_BIN")
        .env_remove("DIFFRACT_ASSETS")
        .env("DIFFRACT_EXPECT_ASSETS", dir.join("assets"))
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && out.contains("2 passed"), "{out}{}", stderr(&o));
    assert!(dir.join("target/release/used").is_file(), "the copy ran the diffract carried beside it");
}

/// `gen sky` writes the clear sky as a 2:1 OpenEXR of finite, non-negative radiance with the sun's disc the
/// brightest texel, near the asked-for direction; its mistakes are one line each.
#[test]
fn gen_sky_writes_an_equirectangular_sky_and_refuses_what_the_model_cannot_do() {
    let out = scratch("sky.exr");
    let args = ["gen", "sky", "--out", out.to_str().unwrap(), "--width", "256", "--sun-elevation-deg", "30"];
    let o = diffract(&[&args[..], &["--sun-azimuth-deg", "91"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("klx from the sky"));
    let image = image::open(&out).unwrap().into_rgb32f();
    assert_eq!(image.dimensions(), (256, 128));
    assert!(image.pixels().all(|p| p.0.iter().all(|c| c.is_finite() && *c >= 0.0)));
    let (at, _) =
        image.enumerate_pixels().map(|(x, y, p)| ((x, y), p.0[1])).fold(
            ((0, 0), 0.0),
            |a, b| {
                if b.1 > a.1 {
                    b
                } else {
                    a
                }
            },
        );
    // Azimuth 91° is just past three quarters across (x = 192.7); 30° high is a third of the way down to the
    // horizon (y = 42.7).
    assert_eq!(at, (192, 42), "the sun's texel");
    // The sun on the horizon works, and neither model writes a negative texel there.
    for model in ["hosek-wilkie", "preetham"] {
        let low = ["--sun-elevation-deg", "0", "--turbidity", "2", "--sky-model", model];
        let o = diffract(&[&args[..6], &low[..]].concat());
        assert!(o.status.success(), "{model}: {}", stderr(&o));
        let image = image::open(&out).unwrap().into_rgb32f();
        assert!(image.pixels().all(|p| p.0.iter().all(|c| c.is_finite() && *c >= 0.0)), "{model}");
    }
    for (flags, needle) in [
        (vec!["--turbidity", "0.5"], "turbidity"),
        (vec!["--turbidity", "1.5", "--sky-model", "preetham"], "Preetham"),
        (vec!["--sky-model", "prague"], "hosek-wilkie"),
        (vec!["--sun-elevation-deg", "-5"], "elevation"),
        (vec!["--sun-elevation-deg", "-0.1"], "elevation"),
        (vec!["--width", "7"], "width"),
        (vec!["--ground-albedo", "2"], "albedo"),
        (vec!["--exposure", "3"], "--exposure"),
    ] {
        let o = diffract(&[&["gen", "sky", "--out", out.to_str().unwrap()][..], &flags].concat());
        assert_one_line_error(&o, needle);
    }
    assert_one_line_error(&diffract(&["gen", "sky", "--out", scratch("sky.jpg").to_str().unwrap()]), ".exr");
}

#[test]
fn map_under_an_environment_writes_radiance_and_checks_itself_against_the_exact_reference() {
    let (sky, patch, png, exr) =
        (scratch("map-sky.exr"), scratch("map-sine.gsf"), scratch("map-env.png"), scratch("map-env.exr"));
    let path = |p: &PathBuf| p.to_str().unwrap().to_string();
    let o = diffract(&["gen", "sky", "--out", &path(&sky), "--width", "128", "--sun-elevation-deg", "60"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let args = ["gen", "patch", "sinusoidal", "--period-um", "1.6", "--height-um", "0.1", "--size-um", "16"];
    let o = diffract(&[&args[..], &["--out", &path(&patch)]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = diffract(&[
        "map",
        "--heightfield",
        &path(&patch),
        "--environment",
        &path(&sky),
        "--size",
        "24",
        "--env-samples",
        "256",
        "--env-reference",
        "6",
        "--out",
        &path(&png),
        "--exr",
        &path(&exr),
        "--validation",
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success(), "{}{stdout}", stderr(&o));
    assert!(!stderr(&o).contains("VALIDATION"), "{}", stderr(&o));
    assert!(
        stdout.contains("256 samples per pixel") && stdout.contains("exact reference at 6 random pixels"),
        "{stdout}"
    );
    // The map is radiance in the sky's cd/m²: somewhere between the sky's and the sun's, and finite.
    let image = image::open(&exr).unwrap().into_rgb32f();
    assert_eq!(image.dimensions(), (24, 24));
    let brightest = image.pixels().map(|p| p.0[1]).fold(0.0f32, f32::max);
    assert!(image.pixels().all(|p| p.0.iter().all(|c| c.is_finite() && *c >= 0.0)));
    assert!(brightest > 100.0 && brightest < 1e9, "brightest {brightest} cd/m²");
}

/// `map` under a lamp (issue 59): a lamp 1 cm in radius at 0.5 m subtends atan(0.02) = 1.1458°, which sets the
/// coherence as --light-radius-deg does (model.md §1.13: 65 µm × 0.267°/1.1458° = 15.12 µm), so the two maps are
/// the same pixels, and differ from the map under the material's own coherence; a lamp without its distance, of
/// no size, or beside --coherence-um is one line.
#[test]
fn a_map_under_a_lamp_takes_its_coherence_from_its_size() {
    let patch = place::assets().join("patches/blazed-1.6um.gsf");
    let run = |name: &str, extra: &[&str]| {
        let exr = scratch(name);
        let (p, e, png) = (patch.to_str().unwrap(), exr.to_str().unwrap(), scratch(&format!("{name}.png")));
        let args = ["map", "--heightfield", p, "--light-theta", "30", "--size", "32", "--exposure", "4"];
        let o = diffract(&[&args[..], extra, &["--out", png.to_str().unwrap(), "--exr", e]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        (stderr(&o), std::fs::read(&exr).unwrap())
    };
    let (note, lamp) = run("lamp.exr", &["--lamp-radius-m", "0.01", "--lamp-distance-m", "0.5"]);
    assert!(note.contains("note: a light 1.1458° in radius: coherence length 15.1224 µm"), "{note}");
    let degrees = 0.02f64.atan().to_degrees().to_string();
    let (_, by_angle) = run("angle.exr", &["--light-radius-deg", &degrees]);
    let (_, own) = run("own.exr", &[]);
    assert!(lamp == by_angle, "a lamp's map differs from the map under its angular radius");
    assert!(lamp != own, "the lamp's size changed nothing");
    let p = patch.to_str().unwrap();
    for (extra, says) in [
        (&["--lamp-radius-m", "0.01"][..], "--lamp-distance-m"),
        (&["--lamp-radius-m", "0", "--lamp-distance-m", "1"][..], "must be above 0"),
        (&["--light-radius-deg", "1", "--coherence-um", "30"][..], "not both"),
    ] {
        let o = diffract(
            &[&["map", "--heightfield", p, "--light-theta", "30", "--out", "/tmp/never.png"][..], extra].concat(),
        );
        assert_one_line_error(&o, says);
    }
}
