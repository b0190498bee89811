//! Where a test finds what it needs, decided at run time so that a test binary built here also runs elsewhere
//! (copied with the `diffract` binary and the `assets` folder to a machine with another GPU): the Vulkan device,
//! the assets, the binary under test and a scratch folder. Each has an environment variable that overrides it.
//!
//! Shared by every test binary (`#[path]`-included where `common` is not), so each uses a subset of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The device tests run on: `DIFFRACT_TEST_DEVICE` (an index from `diffract devices` or a substring of a
/// device's name), else lavapipe, whose images are reproducible and on which the golden images were blessed.
pub fn test_device() -> String {
    std::env::var("DIFFRACT_TEST_DEVICE").ok().filter(|d| !d.trim().is_empty()).unwrap_or_else(|| LAVAPIPE.into())
}

/// The name (substring) of Mesa's CPU Vulkan driver.
pub const LAVAPIPE: &str = "llvmpipe";

/// Whether the test device is lavapipe (the default; `DIFFRACT_TEST_DEVICE` may name it by index too).
pub fn on_lavapipe() -> bool {
    let selector = diffract::gpu::vk::DeviceSelector::parse(&test_device());
    let chosen =
        diffract::gpu::vk::list_devices(false).and_then(|(all, _)| diffract::gpu::vk::choose_device(&all, &selector));
    chosen.map_or_else(|_| test_device().to_lowercase().contains(LAVAPIPE), |d| d.name.contains(LAVAPIPE))
}

/// The repository's `assets` folder: `DIFFRACT_ASSETS`, else the nearest `assets` folder (with its `afm` scans)
/// beside the test binary or above it (the repository's own, for a binary under `target/`), else the source tree
/// the tests were built from.
pub fn assets() -> PathBuf {
    if let Some(dir) = std::env::var_os("DIFFRACT_ASSETS") {
        return PathBuf::from(dir);
    }
    above_the_binary("assets", |p| p.join("afm").is_dir())
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"))
}

/// The repository's root (where `tests/golden` and `fuzz` lie): the folder above [`assets`].
pub fn root() -> PathBuf {
    let assets = assets();
    assets.parent().map_or(assets.clone(), Path::to_path_buf)
}

/// A file under `assets/afm`.
pub fn afm(name: &str) -> PathBuf {
    assets().join("afm").join(name)
}

/// A shipped scene under `assets/scenes`.
pub fn scene(name: &str) -> PathBuf {
    assets().join("scenes").join(name)
}

/// The `diffract` binary: `DIFFRACT_BIN`, else a `diffract` file beside the test binary or above it (cargo keeps
/// tests in `target/<profile>/deps` and the binary in `target/<profile>`), else the one cargo built.
pub fn diffract_bin() -> PathBuf {
    if let Some(bin) = std::env::var_os("DIFFRACT_BIN") {
        return PathBuf::from(bin);
    }
    above_the_binary("diffract", |p| p.is_file()).unwrap_or_else(|| PathBuf::from(env!("CARGO_BIN_EXE_diffract")))
}

/// A scratch folder for the tests: `DIFFRACT_TEST_TMP`, else cargo's target tmp folder where it exists, else one
/// under the system's temporary folder.
pub fn scratch_root() -> PathBuf {
    if let Some(dir) = std::env::var_os("DIFFRACT_TEST_TMP") {
        return PathBuf::from(dir);
    }
    let built = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    if built.is_dir() {
        return built;
    }
    std::env::temp_dir().join("diffract-tests")
}

/// `name` in the test binary's folder or the nearest folder above it where it is what `fits` asks.
fn above_the_binary(name: &str, fits: impl Fn(&Path) -> bool) -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    exe.ancestors().skip(1).map(|dir| dir.join(name)).find(|p| fits(p))
}
