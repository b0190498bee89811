//! Bake and render: the built-in scene (the Elaphe snake), its baked table sized for what this frame's pixels see,
//! drawn offscreen on the Vulkan device and written to a PNG, with each pass's GPU time.
//!
//! Run: `cargo run --release --example render_frame [OUT.png]` (default `frame.png` in the system's temporary
//! folder); `DIFFRACT_VALIDATION=1` turns the Khronos validation layer on.

use diffract::display::AutoExposure;
use diffract::gpu::vk::{Context, ContextDesc, DeviceSelector, Owned};
use diffract::material::SettingsPatch;
use diffract::render::capture::{prepare_materials, scene_reaches, SceneCapture};
use diffract::render::SceneView;
use diffract::scene::Scene;

fn main() -> diffract::Result<()> {
    let out = std::env::args().nth(1).map_or_else(|| std::env::temp_dir().join("frame.png"), Into::into);
    let (width, height) = (256, 256);
    let scene = Scene::default_scene()?;
    let ctx = Context::new(&ContextDesc::new(DeviceSelector::Auto, false))?;
    // A G-buffer of the frame says which (u, v, w) each material's pixels see; each baked table covers just that.
    let reaches = scene_reaches(&ctx, &scene, &[(scene.camera, scene.light_dir)], width, height)?;
    let materials = prepare_materials(&scene, &SettingsPatch::default(), &reaches)?;
    for m in &materials {
        if let Some(line) = m.table_line() {
            println!("{line}");
        }
    }
    let samples = ctx.sample_count(1, diffract::render::LINEAR_FORMAT)?;
    // Owned: its GPU objects are freed when it goes, once the device is idle.
    let mut capture = Owned::new(&ctx, SceneCapture::new(&ctx, &scene, &materials, width, height, samples)?);
    let frame = capture.render(&ctx, &SceneView::of(&scene))?;
    let linear = frame.linear().expect("scene frames are linear");
    // The scene's exposure, else one measured from the frame (its lit pixels' 99.5th percentile shown at 0.9).
    let exposure_ev = scene.render.exposure_ev.or_else(|| AutoExposure::of(linear).map(|a| a.ev)).unwrap_or(0.0);
    let rgba8 = diffract::display::tone::to_rgba8(linear, exposure_ev, diffract::display::Tone::Clip);
    diffract::io::output::write_png_rgba8(&out, width, height, &rgba8)?;
    let passes = frame.times.map_or("no timestamps on this device".into(), |t| t.describe());
    println!("wrote {} ({width}×{height} on {}; GPU {passes})", out.display(), ctx.info.name);
    Ok(())
}
