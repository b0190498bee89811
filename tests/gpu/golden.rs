//! Golden-image comparison with a tolerance. On a mismatch the actual image and a difference image (absolute
//! difference, amplified ×8) are written under `target/golden-failures/`. Re-blessing is explicit:
//! `DIFFRACT_BLESS=1 cargo test` overwrites the golden files with the actual images.
//!
//! The golden images were blessed on lavapipe. On another device (`DIFFRACT_TEST_DEVICE`) the same channel
//! tolerance holds but more pixels may exceed it: another rasteriser covers edge pixels differently (on an
//! NVIDIA H100, 0.11 % of an 800² frame's pixels, all on edges, differed by more than 3/255).

use std::path::PathBuf;

/// Largest per-channel difference (of 255) a pixel may have before it counts as different. Lavapipe is
/// deterministic on one machine, but LLVM versions may round transcendental functions differently.
pub const CHANNEL_TOLERANCE: u8 = 3;
/// Fraction of pixels that may exceed the channel tolerance (edge pixels under rasterisation changes).
pub const MAX_DIFFERENT_FRACTION: f64 = 0.002;
/// The same on a device other than the one the images were blessed on (the small test images are mostly edge).
pub const MAX_DIFFERENT_FRACTION_ELSEWHERE: f64 = 0.02;

/// The fraction of pixels allowed past the channel tolerance on the test device.
fn allowed_fraction() -> f64 {
    if crate::harness::place::on_lavapipe() {
        MAX_DIFFERENT_FRACTION
    } else {
        MAX_DIFFERENT_FRACTION_ELSEWHERE
    }
}

fn root() -> PathBuf {
    crate::harness::place::root()
}

/// Compares `actual` (RGBA8) with `tests/golden/<name>.png`.
pub fn check(name: &str, width: u32, height: u32, actual: &[u8]) {
    let golden_path = root().join("tests/golden").join(format!("{name}.png"));
    let actual_img = image::RgbaImage::from_raw(width, height, actual.to_vec()).expect("size matches");
    if std::env::var("DIFFRACT_BLESS").is_ok_and(|v| v == "1") {
        assert!(crate::harness::place::on_lavapipe(), "the golden images are blessed on lavapipe, the default device");
        actual_img.save(&golden_path).expect("write golden image");
        eprintln!("blessed {}", golden_path.display());
        return;
    }
    let failures = root().join("target/golden-failures");
    let golden = match image::open(&golden_path) {
        Ok(g) => g.to_rgba8(),
        Err(e) => {
            std::fs::create_dir_all(&failures).unwrap();
            actual_img.save(failures.join(format!("{name}.actual.png"))).unwrap();
            panic!("no golden image {} ({e}); run with DIFFRACT_BLESS=1 to create it", golden_path.display());
        }
    };
    assert_eq!((golden.width(), golden.height()), (width, height), "golden image {name} has another size");
    let mut diff = image::RgbaImage::new(width, height);
    let mut different = 0usize;
    for (i, (a, g)) in actual.chunks(4).zip(golden.as_raw().chunks(4)).enumerate() {
        let d: Vec<u8> = a.iter().zip(g).map(|(x, y)| x.abs_diff(*y)).collect();
        if d.iter().any(|&c| c > CHANNEL_TOLERANCE) {
            different += 1;
        }
        let px = image::Rgba([d[0].saturating_mul(8), d[1].saturating_mul(8), d[2].saturating_mul(8), 255]);
        diff.put_pixel(i as u32 % width, i as u32 / width, px);
    }
    let fraction = different as f64 / (width * height) as f64;
    if fraction > allowed_fraction() {
        std::fs::create_dir_all(&failures).unwrap();
        actual_img.save(failures.join(format!("{name}.actual.png"))).unwrap();
        diff.save(failures.join(format!("{name}.diff.png"))).unwrap();
        panic!(
            "{name}: {different} pixels ({:.3} %) differ by more than {CHANNEL_TOLERANCE}/255; actual and difference \
             images are in {}; if the change is intended, re-bless with DIFFRACT_BLESS=1",
            fraction * 100.0,
            failures.display()
        );
    }
}
