//! The shared harness of the GPU tests: every test gets a context on the test device (lavapipe unless
//! `DIFFRACT_TEST_DEVICE` names another, see [`place::test_device`]) with the validation layer on, and fails if
//! the layer reported anything or an allocation is still live at teardown.

use diffract::gpu::vk::{Context, ContextDesc, DeviceSelector};

#[path = "../common/place.rs"]
pub mod place;

pub fn open() -> Context {
    let device = place::test_device();
    let desc = ContextDesc { device: DeviceSelector::parse(&device), validation: true, window: false };
    match Context::new(&desc) {
        Ok(ctx) => ctx,
        Err(e) => panic!(
            "GPU tests need the device {device:?} (DIFFRACT_TEST_DEVICE; default lavapipe) and the validation layer \
             (scripts/setup-debian.sh): {e}"
        ),
    }
}

/// Runs `f` on a fresh validated context on the test device and checks the teardown.
pub fn gpu_test<T>(f: impl FnOnce(&Context) -> T) -> T {
    let ctx = open();
    let out = f(&ctx);
    ctx.close_checked().unwrap_or_else(|e| panic!("{e}"));
    out
}
