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

/// The first picture shows what the project exists for (issue 46's measure): the default scene at 256², as
/// `render` shows it (its samples, the filmic curve at its exposure), shows diffraction's greens, blues or violets
/// (hue 90–300°, saturation > 0.2) in at least 5 % of the snake's pixels, a median value (HSV) of at least 0.3,
/// and at most 2 % of them clipped at white. The snake's pixels: those the view drawn without its background
/// covers at least half.
#[test]
fn the_default_picture_shows_the_iridescence() {
    let scene = Scene::default_scene().unwrap();
    let (w, h) = (256, 256);
    let frames = gpu_test(|ctx| {
        let materials = scene_materials(ctx, &scene, (w, h), &SettingsPatch::default());
        let samples = ctx.sample_count(scene.render.samples, diffract::render::LINEAR_FORMAT).unwrap();
        let view = diffract::render::SceneView::of(&scene);
        let frame = capture_views(ctx, &scene, &materials, (w, h), samples, std::slice::from_ref(&view)).remove(0);
        // The snake's coverage: the snake (the first object) alone, without the soil, drawn without a background.
        let mut snake = scene.clone();
        snake.objects.truncate(1);
        let coverage = capture_views(ctx, &snake, &materials, (w, h), samples, &[view.without_background()]).remove(0);
        [frame, coverage].map(|f| f.linear().unwrap().to_vec())
    });
    let ev = scene.render.exposure_ev.unwrap();
    let shown = diffract::display::tone::to_rgba8(&frames[0], ev, diffract::display::Tone::Filmic);
    let snake: Vec<[f64; 3]> = shown
        .chunks(4)
        .zip(frames[1].chunks(4))
        .filter(|(_, coverage)| coverage[3] >= 0.5)
        .map(|(p, _)| [p[0], p[1], p[2]].map(|c| f64::from(c) / 255.0))
        .collect();
    let n = snake.len() as f64;
    assert!(n > 0.1 * f64::from(w * h), "the snake covers {n} pixels");
    // HSV: value the largest channel, saturation (max − min)/max, hue in degrees.
    let hsv = |[r, g, b]: [f64; 3]| {
        let (max, min) = (r.max(g).max(b), r.min(g).min(b));
        let d = max - min;
        let hue = if d <= 0.0 {
            0.0
        } else if max == r {
            60.0 * ((g - b) / d).rem_euclid(6.0)
        } else if max == g {
            60.0 * ((b - r) / d + 2.0)
        } else {
            60.0 * ((r - g) / d + 4.0)
        };
        (hue, if max > 0.0 { d / max } else { 0.0 }, max)
    };
    let coloured = snake.iter().map(|&p| hsv(p)).filter(|&(h, s, _)| (90.0..=300.0).contains(&h) && s > 0.2).count();
    let mut values: Vec<f64> = snake.iter().map(|&p| hsv(p).2).collect();
    values.sort_by(f64::total_cmp);
    let median = values[values.len() / 2];
    // AgX tops out at code 250: a pixel at its top in every channel is clipped white.
    let white = snake.iter().filter(|p| p.iter().all(|&c| c >= 249.0 / 255.0)).count();
    let (coloured, white) = (coloured as f64 / n, white as f64 / n);
    eprintln!(
        "the default picture at 256²: {:.1} % of the snake's {n} pixels coloured, median value {median:.3}, {:.2} % \
         clipped white",
        100.0 * coloured,
        100.0 * white
    );
    assert!(coloured >= 0.05 && median >= 0.3 && white <= 0.02, "{coloured} coloured, median {median}, {white} white");
}
