//! The visibility buffer (`render::visibility`) draws what the forward pass draws: every shipped scene at one and
//! at four samples per pixel, the same materials, both paths, compared pixel by pixel as a PNG would hold them.
//! (Against the exact reference the two paths measure the same error: docs/performance.md, "The visibility
//! buffer, built".)

use diffract::gpu::vk::Owned;
use diffract::material::SettingsPatch;
use diffract::render::capture::SceneCapture;
use diffract::render::visibility::ShadingPath;
use diffract::render::SceneView;
use diffract::scene::Scene;

use crate::capture::scene_materials;
use crate::harness::gpu_test;

/// `scene`'s frame at `size` with `samples` per pixel, forward and through the visibility buffer: linear RGBA.
fn both_paths(scene: &Scene, size: (u32, u32), samples: u32) -> [Vec<f32>; 2] {
    gpu_test(|ctx| {
        let materials = scene_materials(ctx, scene, size, &SettingsPatch::default());
        let samples = ctx.sample_count(samples, diffract::render::LINEAR_FORMAT).unwrap();
        [ShadingPath::Forward, ShadingPath::Visibility].map(|path| {
            let capture = SceneCapture::with_path(ctx, scene, &materials, size, samples, path).unwrap();
            let mut capture = Owned::new(ctx, capture);
            capture.render(ctx, &SceneView::of(scene)).unwrap().linear().unwrap().to_vec()
        })
    })
}

#[test]
fn the_visibility_buffer_draws_what_the_forward_pass_draws() {
    let dir = crate::harness::place::assets().join("scenes");
    let mut scenes: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    scenes.sort();
    for path in scenes.iter().filter(|p| p.extension().is_some_and(|e| e == "toml")) {
        let scene = Scene::load(path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy();
        for samples in [1, 4] {
            let (w, h) = (96, 96);
            let [forward, visibility] = both_paths(&scene, (w, h), samples);
            let ev = scene.render.exposure_ev.unwrap();
            let [a, b] = [&forward, &visibility]
                .map(|f| diffract::display::tone::to_rgba8(f, ev, diffract::display::Tone::Clip));
            let diffs: Vec<i32> = a
                .chunks(4)
                .zip(b.chunks(4))
                .map(|(p, q)| (0..3).map(|c| (i32::from(p[c]) - i32::from(q[c])).abs()).max().unwrap())
                .collect();
            let over = |t: i32| diffs.iter().filter(|&&d| d > t).count();
            let mean: f64 = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
            let max = diffs.iter().max().unwrap();
            eprintln!("{name}, {samples} sample(s): 8-bit difference mean {mean:.4}, max {max}; over 4: {}", over(4));
            // Both shade each visible triangle once per pixel at its centre and weigh it by its samples. They
            // differ by float rounding, and where a glint's colour turns within a pixel (the sunlit snakes'
            // sparkles, at this size a pixel or two per scale) by the footprint's finite difference: the forward
            // pass's derivatives come from the device's 2×2 quads, the visibility buffer's from the triangle's
            // plane at the quad's pixels.
            // Where a normal map turns the normal through tens of degrees within a few pixels (skin-maps.toml's
            // scale borders, 77° over three pixels at this size), the two differences part further: 1 in 20 pixels.
            let maps = scene.objects.iter().any(|o| o.mesh.maps.normal.is_some());
            let share = if maps { 20 } else { 50 };
            assert!(mean < 1.0, "{name}, {samples} sample(s): mean 8-bit difference {mean}");
            assert!(
                over(4) * share < diffs.len(),
                "{name}, {samples} sample(s): {} of {} pixels differ by more than 4 levels",
                over(4),
                diffs.len()
            );
            // The two are different drawings, not one image read twice.
            assert!(forward.iter().zip(&visibility).any(|(f, v)| f != v), "{name}, {samples} sample(s)");
        }
    }
}
