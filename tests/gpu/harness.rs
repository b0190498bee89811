//! The shared harness of the GPU tests: every test gets a context on lavapipe (so images are reproducible)
//! with the validation layer on, and fails if the layer reported anything or an allocation is still live at
//! teardown.

use diffract::vk::{Context, ContextDesc, DeviceSelector};

/// The device the tests run on: lavapipe, Mesa's CPU Vulkan driver.
pub const TEST_DEVICE: &str = "llvmpipe";

pub fn open() -> Context {
    let desc = ContextDesc { device: DeviceSelector::Name(TEST_DEVICE.into()), validation: true, window: false };
    match Context::new(&desc) {
        Ok(ctx) => ctx,
        Err(e) => panic!("GPU tests need lavapipe and the validation layer (scripts/setup-debian.sh): {e}"),
    }
}

/// Runs `f` on a fresh validated lavapipe context and checks the teardown.
pub fn gpu_test<T>(f: impl FnOnce(&Context) -> T) -> T {
    let ctx = open();
    let log = ctx.validation();
    let out = f(&ctx);
    ctx.wait_idle().expect("device idle");
    let live = ctx.live_allocations();
    drop(ctx);
    assert!(live.is_empty(), "allocations still live at teardown: {live:?}");
    assert_eq!(log.count(), 0, "validation messages:\n{}", log.messages().join("\n"));
    out
}
