//! The sun's shadow against closed forms: a matte ball above a matte ground, lit by the sun alone, is ray-cast
//! on the CPU (an exact sphere and plane) and every pixel away from an edge must match — the ground in the
//! ball's shadow black, the rest of it and the ball's lit side at albedo·Ω_sun/π·cos θ_i (a Lambertian surface
//! under a sun whose mirror glint is 1), with no acne on either.

use diffract::physics::optics::SUN_SOLID_ANGLE;
use diffract::render::capture::{prepare_materials, scene_reaches, SceneCapture};
use diffract::render::SceneView;
use diffract::scene::Scene;
use diffract::shading::SettingsPatch;
use glam::{DVec3, Vec4};

use crate::harness::gpu_test;

const BALL: DVec3 = DVec3::new(0.0, 1.6, 0.0);
const RADIUS: f64 = 1.0;
const ALBEDO: [f64; 2] = [0.6, 0.3]; // ball, ground

fn scene(shadows: bool) -> Scene {
    let text = format!(
        r#"
[camera]
position = [3.0, 6.0, 7.0]
target = [-1.2, 0.4, 0.0]
fov_y_deg = 40.0

[light]
direction = [1.0, 1.1, 0.35]
shadows = {shadows}

[material.ball]
pigment = [{a}, {a}, {a}]

[material.ground]
pigment = [{g}, {g}, {g}]

[[object]]
shape = "sphere"
material = "ball"
translate = [{x}, {y}, {z}]

[[object]]
shape = "ground"
material = "ground"

[render]
samples = 1
"#,
        a = ALBEDO[0],
        g = ALBEDO[1],
        x = BALL.x,
        y = BALL.y,
        z = BALL.z
    );
    Scene::parse(&text, "shadow.toml", std::path::Path::new(".")).unwrap()
}

fn render(scene: &Scene, (w, h): (u32, u32)) -> Vec<f32> {
    gpu_test(|ctx| {
        let reaches = scene_reaches(ctx, scene, &[(scene.camera, scene.light_dir)], w, h).unwrap();
        let materials = prepare_materials(scene, &SettingsPatch::default(), &reaches).unwrap();
        let one = ash::vk::SampleCountFlags::TYPE_1;
        let mut capture = SceneCapture::new(ctx, scene, &materials, w, h, one).unwrap();
        let frame = capture.render(ctx, &SceneView::of(scene));
        // SAFETY: render waited.
        unsafe { capture.destroy(ctx) };
        frame.unwrap().linear().unwrap().to_vec()
    })
}

/// Distance from `c` to the ray `o + t·d` (t ≥ 0; unit d), and the ray's first hit on the sphere if any.
fn ray_sphere(o: DVec3, d: DVec3, c: DVec3, r: f64) -> (f64, Option<DVec3>) {
    let t_closest = (c - o).dot(d).max(0.0);
    let miss = (o + d * t_closest - c).length();
    let hit = (miss < r).then(|| o + d * (t_closest - (r * r - miss * miss).sqrt()));
    (miss, hit)
}

/// What the pixel (x, y) of a w×h frame shows: Some(expected linear grey) or None near an edge (silhouettes,
/// the shadow's boundary, the ball's terminator), where the tessellation and the filter may differ.
fn expected(scene: &Scene, shadows: bool, (w, h): (u32, u32), (x, y): (u32, u32)) -> Option<f64> {
    let inv = scene.camera.view_projection(w as f32 / h as f32).inverse().as_dmat4();
    let ndc = |p: u32, n: u32| (f64::from(p) + 0.5) / f64::from(n) * 2.0 - 1.0;
    let at = |z: f64| {
        let v = inv * glam::DVec4::new(ndc(x, w), ndc(y, h), z, 1.0);
        v.truncate() / v.w
    };
    let (o, d) = (at(0.0), (at(1.0) - at(0.0)).normalize());
    let light = scene.light_dir.as_dvec3().normalize();
    let sun = SUN_SOLID_ANGLE / std::f64::consts::PI;
    let (miss, hit) = ray_sphere(o, d, BALL, RADIUS);
    if (miss - RADIUS).abs() < 0.03 * RADIUS {
        return None;
    }
    if let Some(p) = hit {
        let cos = (p - BALL).normalize().dot(light);
        // Beside the terminator the tessellated normals and the shadow's offset may disagree.
        return match cos {
            c if c > 0.25 => Some(ALBEDO[0] * sun * c),
            c if c < -0.05 => Some(0.0),
            _ => None,
        };
    }
    if d.y >= 0.0 {
        return None;
    }
    let g = o - d * (o.y / d.y);
    if g.x.abs() > 40.0 || g.z.abs() > 40.0 {
        return None;
    }
    let (gap, blocked) = ray_sphere(g, light, BALL, RADIUS);
    if shadows && (gap - RADIUS).abs() < 0.03 * RADIUS {
        return None;
    }
    let lit = if shadows && blocked.is_some() { 0.0 } else { 1.0 };
    Some(ALBEDO[1] * sun * light.y * lit)
}

fn check(shadows: bool) -> (usize, usize) {
    let scene = scene(shadows);
    let size = (160, 120);
    let linear = render(&scene, size);
    let lit_ground = ALBEDO[1] * SUN_SOLID_ANGLE / std::f64::consts::PI * scene.light_dir.as_dvec3().normalize().y;
    let (mut compared, mut dark) = (0, 0);
    for y in 0..size.1 {
        for x in 0..size.0 {
            let Some(want) = expected(&scene, shadows, size, (x, y)) else { continue };
            let i = ((y * size.0 + x) * 4) as usize;
            let got = Vec4::from_slice(&linear[i..i + 4]).as_dvec4();
            for c in 0..3 {
                assert!(
                    (got[c] - want).abs() <= 0.01 * want.max(lit_ground * 0.1),
                    "shadows {shadows}, pixel ({x}, {y}) channel {c}: {} where {want} is expected",
                    got[c]
                );
            }
            compared += 1;
            dark += usize::from(want == 0.0);
        }
    }
    (compared, dark)
}

#[test]
fn a_ball_shadows_the_ground_where_its_rays_are_blocked_and_nowhere_else() {
    let (compared, dark) = check(true);
    // The frame shows the shadow and the lit ground and ball around it.
    assert!(compared > 10_000 && dark > 300, "compared {compared}, in shadow or unlit {dark}");
    // Without shadows the same ground is lit everywhere: only the ball's far side is dark.
    let (compared, dark_unshadowed) = check(false);
    assert!(compared > 10_000 && dark_unshadowed * 2 < dark, "compared {compared}, unlit {dark_unshadowed}");
}
