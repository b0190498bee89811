//! The `diffract` binary as a user meets it: its outputs, and one clear line and a non-zero exit for every
//! mistake a user can make, never a panic.

mod common;

use std::path::PathBuf;
use std::process::{Command, Output};

use common::{assert_one_line_error, diffract};

fn scratch(name: &str) -> PathBuf {
    common::scratch("cli", name)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn devices_lists_llvmpipe() {
    let o = diffract(&["devices"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("llvmpipe") && out.contains("CPU") && out.contains("1.3"), "{out}");
}

#[test]
fn render_writes_a_nonblank_png_without_validation_messages() {
    let path = scratch("render.png");
    let _ = std::fs::remove_file(&path);
    let o = diffract(&[
        "render",
        "--out",
        path.to_str().unwrap(),
        "--width",
        "128",
        "--height",
        "128",
        "--validation",
        "--device",
        "llvmpipe",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("validation"), "{}", stderr(&o));
    let img = image::open(&path).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (128, 128));
    let first = img.get_pixel(0, 0);
    assert!(img.pixels().any(|p| p != first), "the image is blank");
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
    let o = Command::new(env!("CARGO_BIN_EXE_diffract"))
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
