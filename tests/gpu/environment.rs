//! The environment behind a scene: every background pixel shows the map's radiance in the view ray's direction,
//! in the frame's units (the sun's radiance), turned by `rotation_deg` and scaled by `intensity`.
//!
//! The map is a ramp — texel (x, y) holds (x + ½, y + ½, 1) — so that bilinear filtering reproduces the texture
//! coordinate itself: a pixel's red and green, over the scale, are where its ray lands in the map (u·W, v·H).

use diffract::scene::Scene;
use glam::DVec3;

const W: u32 = 64;
const H: u32 = 32;

/// `scene` rendered at `w`×`h`, one sample per pixel: its linear RGBA.
fn render_linear(scene: &Scene, w: u32, h: u32) -> Vec<f32> {
    crate::capture::render_scene(scene, (w, h))
}

#[test]
fn the_background_is_the_map_along_each_view_ray() {
    let dir = crate::harness::place::scratch_root().join(format!("environment-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rgba: Vec<f32> = (0..W * H).flat_map(|i| [(i % W) as f32 + 0.5, (i / W) as f32 + 0.5, 1.0, 1.0]).collect();
    diffract::io::output::write_exr_rgb(&dir.join("ramp.exr"), W, H, &rgba).unwrap();
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
    let linear = render_linear(&scene, w, h);
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

/// The furnace in a frame: a ball of a flat (mirror) material with no pigment inside a uniform environment, the sun
/// pointed away from the camera, reflects the environment times its Fresnel reflectance R(θ_r) at every pixel
/// (`light::prefilter`: the moments of a mirror against a constant light are its reflectance). Only where the sun's
/// own glint is not seen: the camera looks at the ball's side away from it.
#[test]
fn a_mirror_ball_in_a_uniform_environment_reflects_it_by_fresnel() {
    let dir = crate::harness::place::scratch_root().join(format!("furnace-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let radiance = 5000.0f32;
    let rgba: Vec<f32> = (0..W * H).flat_map(|_| [radiance, radiance, radiance, 1.0]).collect();
    diffract::io::output::write_exr_rgb(&dir.join("white.exr"), W, H, &rgba).unwrap();
    let text = r#"
[camera]
position = [0.0, 0.0, -3.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 40.0

[light]
direction = [0.0, 0.5, 1.0]
environment = "white.exr"

[[object]]
shape = "sphere"
material = "mirror"

[material.mirror]
generate = "flat"
size_um = 8.0
pigment = [0.0, 0.0, 0.0]

[render]
samples = 1
"#;
    let scene = Scene::parse(text, "furnace.toml", &dir).unwrap();
    let (w, h) = (48u32, 48u32);
    let linear = render_linear(&scene, w, h);
    let sun = diffract::physics::sky::Sky::new(3.0, scene.light_dir.as_dvec3()).unwrap().sun_xyz().y;
    let l = f64::from(radiance) / sun;
    let inv = scene.camera.view_projection(w as f32 / h as f32).inverse().as_dmat4();
    let camera = scene.camera.position.as_dvec3();
    let (mut worst, mut compared) = (0.0f64, 0);
    for y in 0..h {
        for x in 0..w {
            let ndc = |p: u32, n: u32| (f64::from(p) + 0.5) / f64::from(n) * 2.0 - 1.0;
            let far = inv * glam::DVec4::new(ndc(x, w), ndc(y, h), 1.0, 1.0);
            let d: DVec3 = (far.truncate() / far.w - camera).normalize();
            // The ray against the unit sphere at the origin (the mesh is finely tessellated: its normals are the
            // sphere's within a fraction of a degree; pixels near the silhouette are left out).
            let b = camera.dot(d);
            let disc = b * b - (camera.length_squared() - 1.0);
            if disc <= 0.0 {
                continue;
            }
            let p = camera + d * (-b - disc.sqrt());
            let cos_r = p.dot(-d);
            if cos_r < 0.5 {
                continue;
            }
            let omega_r = DVec3::new(0.0, (1.0 - cos_r * cos_r).sqrt(), cos_r);
            let mirror = DVec3::new(0.0, -omega_r.y, omega_r.z);
            let r = diffract::physics::optics::normal_reflectance(diffract::physics::optics::SKIN_INDEX)
                * diffract::physics::optics::fresnel_ratio(mirror, omega_r, diffract::physics::optics::SKIN_INDEX);
            let i = ((y * w + x) * 4) as usize;
            let got = DVec3::new(f64::from(linear[i]), f64::from(linear[i + 1]), f64::from(linear[i + 2])) / (r * l);
            worst = worst.max((got - DVec3::ONE).abs().max_element());
            compared += 1;
        }
    }
    eprintln!("furnace in a frame: {compared} pixels within 60° of the view, worst {worst:.4} from R(θ)·L");
    assert!(compared > 500, "{compared}");
    assert!(worst < 0.01, "worst {worst}");
}
