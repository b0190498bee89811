//! Helpers shared by the command-line tests.

// Each test binary uses a subset of them.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::{Command, Output};

pub mod place;

/// Runs the `diffract` binary (without DIFFRACT_VALIDATION from the environment; baked tables and references
/// cached under the target folder, not in the user's cache).
pub fn diffract(args: &[&str]) -> Output {
    Command::new(place::diffract_bin())
        .args(args)
        .env_remove("DIFFRACT_VALIDATION")
        .env("DIFFRACT_CACHE", place::scratch_root().join("cache"))
        .output()
        .expect("run diffract")
}

/// A path under the target's scratch folder for the test binary `group`.
pub fn scratch(group: &str, name: &str) -> PathBuf {
    let dir: PathBuf = place::scratch_root().join(group);
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A user error: non-zero exit, exactly one line on stderr that contains `needle`, no panic.
pub fn assert_one_line_error(o: &Output, needle: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "expected a failure, stderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line expected: {err}");
    assert!(err.contains(needle), "expected {needle:?} in {err:?}");
}

/// Generates a small sinusoidal grating (8 µm square, 0.05 µm pixels, 1.6 µm period) at `path`.
pub fn sine_patch(path: &std::path::Path) {
    let o = diffract(&[
        "gen",
        "patch",
        "sinusoidal",
        "--size-um",
        "8",
        "--pixel-um",
        "0.05",
        "--period-um",
        "1.6",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}
