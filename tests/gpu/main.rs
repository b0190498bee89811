//! All GPU tests, in one binary, on the test device (lavapipe unless `DIFFRACT_TEST_DEVICE` says otherwise) with
//! validation (see `harness`).

mod capture;
mod diffraction;
mod env_map;
mod environment;
mod golden;
mod harness;
mod lamps;
mod maps;
mod scenes;
mod shadow;
mod surface;
mod visibility;

use diffract::gpu::vk::DeviceSelector;
use diffract::render::preview::{render_offscreen, PreviewScene};
use harness::gpu_test;

#[test]
fn the_test_device_is_listed() {
    let (devices, _) = diffract::gpu::vk::list_devices(false).expect("list devices");
    let chosen = diffract::gpu::vk::choose_device(&devices, &DeviceSelector::parse(&harness::place::test_device()));
    assert!(chosen.is_ok(), "{devices:?}");
}

#[test]
fn validation_canary_counts_a_deliberate_error() {
    // The harness is only worth something if a real validation error is seen: provoke one on purpose.
    let ctx = harness::open();
    let log = ctx.validation();
    assert_eq!(log.count(), 0);
    ctx.provoke_validation_error();
    assert!(log.count() >= 1, "the validation layer's message was not counted");
    assert!(log.messages().iter().any(|m| m.contains("size")), "{:?}", log.messages());
}

#[test]
fn preview_scene_matches_golden_image() {
    let frame = gpu_test(|ctx| {
        render_offscreen(ctx, &PreviewScene::lit_sphere(), 128, 128, ash::vk::SampleCountFlags::TYPE_1).unwrap()
    });
    assert!(frame.gpu_ms().is_some(), "lavapipe has timestamps");
    golden::check("preview_128", frame.width, frame.height, frame.rgba8().expect("RGBA8"));
}

#[test]
fn odd_sized_frames_render() {
    let frame = gpu_test(|ctx| {
        render_offscreen(ctx, &PreviewScene::lit_sphere(), 33, 7, ash::vk::SampleCountFlags::TYPE_1).unwrap()
    });
    assert_eq!(frame.rgba8().expect("RGBA8").len(), 33 * 7 * 4);
}
