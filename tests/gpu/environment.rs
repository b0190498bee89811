//! The environment behind a scene: every background pixel shows the map's radiance in the view ray's direction,
//! in the frame's units (the sun's radiance), turned by `rotation_deg` and scaled by `intensity`.
//!
//! The map is a ramp — texel (x, y) holds (x + ½, y + ½, 1) — so that bilinear filtering reproduces the texture
//! coordinate itself: a pixel's red and green, over the scale, are where its ray lands in the map (u·W, v·H).

use diffract::render::capture::{prepare_materials, scene_reaches, SceneCapture};
use diffract::render::SceneView;
use diffract::scene::Scene;
use diffract::shading::SettingsPatch;
use glam::DVec3;

use crate::harness::gpu_test;

const W: u32 = 64;
const H: u32 = 32;

#[test]
fn the_background_is_the_map_along_each_view_ray() {
    let dir = crate::harness::place::scratch_root().join(format!("environment-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rgba: Vec<f32> = (0..W * H).flat_map(|i| [(i % W) as f32 + 0.5, (i / W) as f32 + 0.5, 1.0, 1.0]).collect();
    diffract::output::write_exr_rgb(&dir.join("ramp.exr"), W, H, &rgba).unwrap();
    let (rotation_deg, intensity): (f64, f64) = (40.0, 1000.0);
    let text = format!(
        r#"
[camera]
position = [0.0, 1.0, 0.0]
target = [1.0, 1.3, -0.4]
fov_y_deg = 100.0

[light]
direction = [0.2, 0.8, 0.3]
environment = "ramp.exr"
rotation_deg = {rotation_deg}
intensity = {intensity}

[[object]]
shape = "sphere"
material = "grey"
translate = [30.0, 9.0, -12.0]
scale = 0.5

[material.grey]
pigment = [0.5, 0.5, 0.5]

[render]
samples = 1
"#
    );
    let scene = Scene::parse(&text, "env.toml", &dir).unwrap();
    let (w, h) = (96u32, 64u32);
    let linear = gpu_test(|ctx| {
        let reaches = scene_reaches(ctx, &scene, &[(scene.camera, scene.light_dir)], w, h).unwrap();
        let materials = prepare_materials(&scene, &SettingsPatch::default(), &reaches).unwrap();
        let mut capture = SceneCapture::new(ctx, &scene, &materials, w, h, ash::vk::SampleCountFlags::TYPE_1).unwrap();
        let frame = capture.render(ctx, &SceneView::of(&scene));
        // SAFETY: render waited.
        unsafe { capture.destroy(ctx) };
        frame.unwrap().linear().unwrap().to_vec()
    });
    let sun = diffract::physics::sky::Sky::new(3.0, scene.light_dir.as_dvec3()).unwrap().sun_xyz().y;
    let scale = intensity / sun;
    let inv = scene.camera.view_projection(w as f32 / h as f32).inverse().as_dmat4();
    let mut compared = 0;
    for y in 0..h {
        for x in 0..w {
            let ndc = |p: u32, n: u32| (f64::from(p) + 0.5) / f64::from(n) * 2.0 - 1.0;
            let far = inv * glam::DVec4::new(ndc(x, w), ndc(y, h), 1.0, 1.0);
            let d: DVec3 = (far.truncate() / far.w - scene.camera.position.as_dvec3()).normalize();
            let azimuth = d.x.atan2(d.z) - rotation_deg.to_radians();
            let u = (azimuth / std::f64::consts::TAU + 0.5).rem_euclid(1.0) * f64::from(W);
            let v = (0.5 - d.y.asin() / std::f64::consts::PI) * f64::from(H);
            // Beside the seam and the poles the filter wraps or clamps; the sphere covers a few pixels.
            if !(1.0..f64::from(W) - 1.0).contains(&u) || !(1.0..f64::from(H) - 1.0).contains(&v) {
                continue;
            }
            let i = ((y * w + x) * 4) as usize;
            let got = [linear[i], linear[i + 1], linear[i + 2]].map(|c| f64::from(c) / scale);
            if got[2] < 0.5 {
                continue; // the sphere
            }
            // Bilinear weights are fixed point on a GPU: within a 256th of a texel.
            assert!(
                (got[0] - u).abs() < 0.01 && (got[1] - v).abs() < 0.01,
                "pixel ({x}, {y}): {got:?}, want ({u}, {v})"
            );
            assert!((got[2] - 1.0).abs() < 1e-4, "pixel ({x}, {y}): {got:?}");
            compared += 1;
        }
    }
    assert!(compared > (w * h) as usize * 8 / 10, "compared {compared}");
    std::fs::remove_dir_all(&dir).unwrap();
}
