//! The backend's own tests, on the test device (lavapipe unless `DIFFRACT_TEST_DEVICE` names another, as for
//! `tests/gpu`) with the validation layer: each fails on any message or an allocation live at teardown.

use ash::vk as raw;

use crate::gpu::interface::{
    SelftestPush, BINDING_SELFTEST_IN, BINDING_SELFTEST_OUT, LOCAL_SIZE_X, SPEC_SELFTEST_SCALE,
};
use crate::gpu::shaders;
use crate::gpu::vk::{
    BufferDesc, ComputePipelineDesc, Context, ContextDesc, DescriptorWrite, DeviceSelector, ImageDesc, ImageState,
    MemoryState, SpecConstants,
};

/// Runs `f` on a fresh validated context on the test device and checks the teardown (the library's GPU unit tests
/// all run through it).
pub(crate) fn gpu_test<T>(f: impl FnOnce(&Context) -> T) -> T {
    let device = std::env::var("DIFFRACT_TEST_DEVICE").ok().filter(|d| !d.trim().is_empty());
    let device = device.unwrap_or_else(|| "llvmpipe".into());
    let desc = ContextDesc { device: DeviceSelector::parse(&device), validation: true, window: false };
    let ctx = Context::new(&desc).unwrap_or_else(|e| {
        panic!("the backend's tests need the device {device:?} and the validation layer (scripts/setup-debian.sh): {e}")
    });
    let out = f(&ctx);
    ctx.close_checked().unwrap_or_else(|e| panic!("{e}"));
    out
}

#[test]
fn leak_check_sees_a_live_allocation() {
    gpu_test(|ctx| {
        let b = ctx.create_buffer(BufferDesc::readback(256), "deliberately live").unwrap();
        assert_eq!(ctx.live_allocations(), vec!["deliberately live".to_string()]);
        // SAFETY: unused by the GPU.
        unsafe { b.destroy(ctx) };
        assert!(ctx.live_allocations().is_empty());
    });
}

#[test]
fn a_guard_destroys_what_it_holds_unless_kept() {
    use crate::gpu::vk::Guard;
    gpu_test(|ctx| {
        let failed_build = || -> Result<(), String> {
            let a = Guard::new(ctx, ctx.create_buffer(BufferDesc::readback(256), "a").unwrap());
            let b = Guard::new(ctx, vec![ctx.create_buffer(BufferDesc::readback(64), "b").unwrap()]);
            assert_eq!(ctx.live_allocations().len(), 2);
            let _ = (&a, &b);
            Err("a later step failed".into())
        };
        assert!(failed_build().is_err());
        assert!(ctx.live_allocations().is_empty(), "an early return destroys the guarded objects");
        let kept = Guard::new(ctx, Some(ctx.create_buffer(BufferDesc::readback(256), "kept").unwrap())).keep();
        assert_eq!(ctx.live_allocations(), vec!["kept".to_string()]);
        // SAFETY: unused by the GPU.
        unsafe { crate::gpu::vk::Destroy::destroy(kept, ctx) };
    });
}

#[test]
fn compute_pipeline_with_push_descriptors_and_specialization() {
    gpu_test(|ctx| {
        let n = 1000u32;
        let input: Vec<f32> = (0..n).map(|i| i as f32 * 0.5).collect();
        let src =
            ctx.create_buffer_init(raw::BufferUsageFlags::STORAGE_BUFFER, bytemuck::cast_slice(&input), "in").unwrap();
        let dst = ctx
            .create_buffer(
                BufferDesc::gpu_only(
                    4 * n as u64,
                    raw::BufferUsageFlags::STORAGE_BUFFER | raw::BufferUsageFlags::TRANSFER_SRC,
                ),
                "out",
            )
            .unwrap();
        let pipeline = ctx
            .create_compute_pipeline(&ComputePipelineDesc {
                name: "selftest",
                shader: &shaders::SELFTEST_COMP,
                specialization: SpecConstants::default().f32(SPEC_SELFTEST_SCALE, 3.0),
                push_constant_size: std::mem::size_of::<SelftestPush>() as u32,
            })
            .unwrap();
        let ring = ctx.create_timestamp_ring(2, 2, "selftest timestamps").unwrap().expect("lavapipe has timestamps");
        let push = SelftestPush { offset: 1.5, count: n };
        ctx.one_shot("selftest", |cmd| {
            let laps = ring.begin_frame(ctx, cmd, 7);
            ctx.bind(
                cmd,
                &pipeline,
                &[
                    DescriptorWrite::StorageBuffer(BINDING_SELFTEST_IN, &src),
                    DescriptorWrite::StorageBuffer(BINDING_SELFTEST_OUT, &dst),
                ],
                bytemuck::bytes_of(&push),
            );
            // SAFETY: recording, pipeline bound.
            unsafe { ctx.device().cmd_dispatch(cmd, n.div_ceil(LOCAL_SIZE_X), 1, 1) };
            laps.lap(cmd, "square");
            ctx.barrier_memory(cmd, MemoryState::COMPUTE_WRITE, MemoryState::TRANSFER_READ);
            laps.lap(cmd, "barrier");
            // A third lap does not fit the ring's two: the frame reads as an error, not as wrong times.
        })
        .unwrap();
        let timings = ring.read(ctx, 7).unwrap();
        let names: Vec<&str> = timings.passes.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["square", "barrier"]);
        assert!(timings.passes.iter().all(|p| p.ms >= 0.0 && p.ms < 10_000.0), "{timings:?}");
        ctx.one_shot("selftest (too many laps)", |cmd| {
            let laps = ring.begin_frame(ctx, cmd, 8);
            for name in ["a", "b", "c"] {
                laps.lap(cmd, name);
            }
        })
        .unwrap();
        let e = ring.read(ctx, 8).unwrap_err().to_string();
        assert!(e.contains("more than 2 timed passes"), "{e}");
        let out: Vec<f32> = bytemuck::cast_slice(&ctx.read_buffer(&dst).unwrap()).to_vec();
        for (i, (&x, &y)) in input.iter().zip(&out).enumerate() {
            assert_eq!(y, 3.0 * x * x + 1.5, "element {i}");
        }
        // SAFETY: all work completed.
        unsafe {
            ring.destroy(ctx);
            pipeline.destroy(ctx);
            src.destroy(ctx);
            dst.destroy(ctx);
        }
    });
}

#[test]
fn rg32f_array_texture_round_trips() {
    gpu_test(|ctx| {
        let (w, h, layers) = (17u32, 9u32, 3u32);
        let texels: Vec<f32> = (0..w * h * layers * 2).map(|i| (i as f32).sin() * 1e-3).collect();
        let image = ctx
            .create_image(ImageDesc::texture_array(w, h, layers, raw::Format::R32G32_SFLOAT), "taylor terms")
            .unwrap();
        ctx.upload_image(&image, bytemuck::cast_slice(&texels), ImageState::SHADER_READ).unwrap();
        let back = ctx.read_image(&image, ImageState::SHADER_READ).unwrap();
        assert_eq!(bytemuck::cast_slice::<u8, f32>(&back), &texels[..], "bit-exact round trip");
        // SAFETY: all work completed.
        unsafe { image.destroy(ctx) };
    });
}
