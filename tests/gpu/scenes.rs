//! Every scene shipped in assets/scenes renders validation-clean, with colour, as its golden image shows it.

use diffract::material::SettingsPatch;
use diffract::scene::Scene;

use crate::capture::{capture_views, scene_materials};
use crate::golden;
use crate::harness::gpu_test;

#[test]
fn every_asset_scene_renders_in_colour() {
    let dir = crate::harness::place::assets().join("scenes");
    let mut scenes: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    scenes.sort();
    assert!(scenes.len() >= 3, "{scenes:?}");
    for path in scenes.iter().filter(|p| p.extension().is_some_and(|e| e == "toml")) {
        let scene = Scene::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (w, h) = (96, 96);
        let linear = gpu_test(|ctx| {
            let materials = scene_materials(ctx, &scene, (w, h), &SettingsPatch::default());
            let samples = ctx.sample_count(scene.render.samples, diffract::render::LINEAR_FORMAT).unwrap();
            let view = diffract::render::SceneView::of(&scene);
            let frames = capture_views(ctx, &scene, &materials, (w, h), samples, &[view]);
            frames[0].linear().unwrap().to_vec()
        });
        let rgba8 = diffract::display::tone::to_rgba8(
            &linear,
            scene.render.exposure_ev.expect("every shipped scene sets its exposure"),
            diffract::display::Tone::Filmic,
        );
        let coloured =
            rgba8.chunks(4).filter(|p| p[..3].iter().max().unwrap() - p[..3].iter().min().unwrap() > 40).count();
        assert!(coloured > 5, "{}: only {coloured} coloured pixels", path.display());
        // The look, pinned as `render` shows it (the filmic curve): the default snake (head, domed scales,
        // pattern, anti-aliased edges) and the others.
        let stem = path.file_stem().unwrap().to_string_lossy().replace('-', "_");
        golden::check(&format!("scene_{stem}_{w}"), w, h, &rgba8);
    }
}
