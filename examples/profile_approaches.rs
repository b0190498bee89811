//! Speed against accuracy: the BRDF map of a blazed grating (the light 20° off the normal) drawn by FLSS, the
//! thesis's full λ-space sampling, and by the baked table, each timed on the Vulkan device (pass by pass) and
//! measured against the exact CPU reference; the profiler's table is printed.
//!
//! Run: `cargo run --release --example profile_approaches`

use diffract::gpu::vk::{Context, ContextDesc, DeviceSelector};
use diffract::material::{Approach, Settings, SettingsPatch};
use diffract::physics::generate::{generate, PatchKind, PatchSpec};
use diffract::physics::optics;
use diffract::reference::profiler;
use diffract::reference::profiler::run::{run, Options, Progress, ReferenceOptions, Subject};
use diffract::reference::profiler::Config;

fn main() -> diffract::Result<()> {
    // A blazed grating of 2.5 µm period, 0.25 µm deep, on a 16 µm square; lit under 16 µm coherence.
    let grating = generate(&PatchSpec::new(PatchKind::Blazed, 16.0, 0.05))?;
    let settings = Settings { coherence_um: 16.0, ..Settings::default() };
    let subject = Subject::Map {
        heightfield: grating,
        light: optics::direction(20.0, 0.0),
        settings,
        name: "blazed grating".into(),
        light_deg: (20.0, 0.0),
    };
    let configs: Vec<Config> = [Approach::Flss, Approach::Baked]
        .map(|approach| Config {
            overrides: SettingsPatch { approach: Some(approach), ..SettingsPatch::default() },
            size: 64,
            samples: None,
            shader: None,
            target: None,
            path: None,
        })
        .to_vec();
    let ctx = Context::new(&ContextDesc::new(DeviceSelector::Auto, false))?;
    let options = Options {
        frames: 5,
        warmup: 1,
        exposure: Some(3.0),
        samples: ctx.sample_count(1, diffract::render::LINEAR_FORMAT)?,
        // One position per pixel, nothing cached: the exact reference of a 64² map takes seconds.
        reference: Some(ReferenceOptions { samples: 1, pixels: None, cache: None }),
        probe: None,
    };
    let report = run(&ctx, &subject, &configs, &options, &|p| {
        if let Progress::Line(line) = p {
            eprintln!("{line}");
        }
    })?;
    println!("{} on {}\n", subject.describe(), ctx.info.name);
    print!("{}", profiler::markdown(&report.rows));
    println!();
    print!("{}", profiler::markdown_passes(&report.rows));
    let (flss, baked) = (&report.rows[0], &report.rows[1]);
    if let (Some(f), Some(b)) = (flss.gpu_ms, baked.gpu_ms) {
        println!("\nbaked is {:.0}× faster than FLSS here", f.median / b.median);
    }
    Ok(())
}
