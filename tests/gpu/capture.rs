//! Scenes drawn as `diffract render` draws them, for the tests that compare frames: the materials a scene needs,
//! and its views drawn by one renderer.

use ash::vk::SampleCountFlags;
use diffract::gpu::vk::{Context, Owned};
use diffract::material::Material;
use diffract::material::SettingsPatch;
use diffract::render::capture::{prepare_materials, scene_reaches, SceneCapture};
use diffract::render::{Frame, SceneView};
use diffract::scene::Scene;

use crate::harness::gpu_test;

/// The materials `scene` needs at its own camera, drawn at `w`×`h`, with `overrides`: as `diffract render`
/// prepares them (each baked table covers what this frame shows).
pub fn scene_materials(ctx: &Context, scene: &Scene, (w, h): (u32, u32), overrides: &SettingsPatch) -> Vec<Material> {
    let reaches = scene_reaches(ctx, scene, &[(scene.camera, scene.light_dir)], w, h).unwrap();
    prepare_materials(scene, overrides, &reaches).unwrap()
}

/// `views` of `scene` drawn one after another by one renderer with `materials`, at `w`×`h` and `samples` per
/// pixel: its frames.
pub fn capture_views(
    ctx: &Context,
    scene: &Scene,
    materials: &[Material],
    (w, h): (u32, u32),
    samples: SampleCountFlags,
    views: &[SceneView],
) -> Vec<Frame> {
    let mut capture = Owned::new(ctx, SceneCapture::new(ctx, scene, materials, w, h, samples).unwrap());
    views.iter().map(|view| capture.render(ctx, view).unwrap()).collect()
}

/// `scene` drawn from its own camera at `w`×`h`, one sample per pixel, with its own settings: linear RGBA.
pub fn render_scene(scene: &Scene, size: (u32, u32)) -> Vec<f32> {
    gpu_test(|ctx| {
        let materials = scene_materials(ctx, scene, size, &Default::default());
        let one = SampleCountFlags::TYPE_1;
        capture_views(ctx, scene, &materials, size, one, &[SceneView::of(scene)]).remove(0).linear().unwrap().to_vec()
    })
}

/// `scene`'s frame at `size`, one sample per pixel, through `path`: linear RGBA.
pub fn one_sample_frame(scene: &Scene, size: (u32, u32), path: diffract::render::visibility::ShadingPath) -> Vec<f32> {
    gpu_test(|ctx| {
        let materials = scene_materials(ctx, scene, size, &SettingsPatch::default());
        let one = SampleCountFlags::TYPE_1;
        let mut capture = Owned::new(ctx, SceneCapture::with_path(ctx, scene, &materials, size, one, path).unwrap());
        capture.render(ctx, &SceneView::of(scene)).unwrap().linear().unwrap().to_vec()
    })
}
