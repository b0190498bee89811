//! Lamps against closed forms: a matte ground under a point lamp follows the inverse-square and cosine laws
//! (E(θ)/E(0) = cos³θ on a plane 1 m below a lamp) at its candela's absolute level (a white matte surface 1 m under a
//! 1 cd lamp has radiance 1/π cd/m²), on both shading paths; a ball under a lamp shadows the ground where the rays
//! from the lamp's centre are blocked (ray-cast on the CPU), and a large lamp's penumbra is the share of its disc
//! the ball leaves visible.

use diffract::render::visibility::ShadingPath;
use diffract::scene::Scene;
use glam::{DVec3, Vec4};

const SIZE: u32 = 96;
const ALBEDO: f64 = 0.5;
const INTENSITY_CD: f64 = 3.0;

/// A matte ground of [`ALBEDO`] under a point lamp 1 m above the origin, seen from straight above (3 m up,
/// 70° across, so that the frame reaches 60° from the lamp's foot), lit by the lamp alone.
fn lamp_scene() -> Scene {
    lamps_scene(&[INTENSITY_CD])
}

/// [`lamp_scene`] with a lamp of each of `intensities_cd` (candela) in the one lamp's place.
fn lamps_scene(intensities_cd: &[f64]) -> Scene {
    let lamps: String = intensities_cd
        .iter()
        .map(|i| {
            format!("[[lamp]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity_cd = {i}\nradius_m = 0.001\n\n")
        })
        .collect();
    let text = format!(
        r#"[camera]
position = [0.0, 3.0, 0.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov_y_deg = 70.0

[light]
environment = "none"

{lamps}[[object]]
shape = "ground"
material = "white"

[material.white]
pigment = [{ALBEDO}, {ALBEDO}, {ALBEDO}]

[render]
samples = 1
"#
    );
    Scene::parse(&text, "lamp.toml", std::path::Path::new(".")).unwrap()
}

/// Where pixel (x, y) of `scene`'s camera meets the ground (y = 0).
fn ground_point(scene: &Scene, x: u32, y: u32) -> DVec3 {
    let inverse = scene.camera.view_projection(1.0).inverse();
    let ndc = |z: f32| {
        let p = inverse
            * Vec4::new((x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0, (y as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0, z, 1.0);
        (p.truncate() / p.w).as_dvec3()
    };
    let (a, b) = (ndc(0.5), ndc(0.9));
    a + (b - a) * (a.y / (a.y - b.y))
}

fn render(scene: &Scene, path: ShadingPath) -> Vec<f32> {
    crate::capture::one_sample_frame(scene, (SIZE, SIZE), path)
}

#[test]
fn a_matte_ground_under_a_point_lamp_follows_cos_cubed_at_its_candela() {
    let scene = lamp_scene();
    assert!(!scene.sun && scene.lamps.len() == 1);
    follows_cos_cubed(&scene);
}

/// The shaders write each lamp out at its own index, up to the most a scene holds (`EACH_LAMP`, lamps.glsl): eight
/// lamps in one place of 1, 2, …, 8 parts of [`INTENSITY_CD`]/36 light the ground as the one lamp does (a lamp
/// left out, or one read at another's index, would not add up).
#[test]
fn eight_lamps_each_add_their_own_light() {
    let parts: Vec<f64> = (1..=8).map(|k| INTENSITY_CD * k as f64 / 36.0).collect();
    let scene = lamps_scene(&parts);
    assert_eq!(scene.lamps.len(), diffract::gpu::interface::MAX_LAMPS as usize);
    follows_cos_cubed(&scene);
}

/// Every pixel of `scene`'s ground within 60° of the lamps' foot reads ρ·I·cos³θ/π for lamps of [`INTENSITY_CD`]
/// in all, on both shading paths, within 1 %.
fn follows_cos_cubed(scene: &Scene) {
    for path in [ShadingPath::Forward, ShadingPath::Visibility] {
        let frame = render(scene, path);
        let (mut worst, mut checked, mut widest) = (0.0f64, 0, 0.0f64);
        for y in 0..SIZE {
            for x in 0..SIZE {
                let p = ground_point(scene, x, y);
                let cos = 1.0 / (1.0 + p.x * p.x + p.z * p.z).sqrt();
                if cos < 60f64.to_radians().cos() {
                    continue;
                }
                let px = &frame[4 * (y * SIZE + x) as usize..][..3];
                let luminance = 0.2126 * px[0] as f64 + 0.7152 * px[1] as f64 + 0.0722 * px[2] as f64;
                // cd/m²: ρ·I·cos³θ/(π·(1 m)²) (the disc's 1 mm adds 10⁻⁶).
                let expected = ALBEDO * INTENSITY_CD * cos.powi(3) / std::f64::consts::PI;
                worst = worst.max((luminance / expected - 1.0).abs());
                widest = widest.max(cos.acos().to_degrees());
                checked += 1;
            }
        }
        eprintln!("{path:?}: {checked} pixels within {widest:.1}° of the lamp's foot, worst {worst:.2e}");
        assert!(checked > 1000 && widest > 59.0, "{checked} pixels to {widest}°");
        assert!(worst < 0.01, "{path:?}: a pixel {worst} off ρ·I·cos³θ/π");
    }
}

const BALL: DVec3 = DVec3::new(0.0, 1.2, 0.0);
const BALL_RADIUS: f64 = 0.5;
const BALL_ALBEDO: f64 = 0.6;

/// A matte ball over the matte ground of [`ALBEDO`], lit by one point lamp of [`INTENSITY_CD`] at `lamp` (its
/// disc `radius_m`) alone, seen obliquely.
fn ball_scene(lamp: DVec3, radius_m: f64, camera: (DVec3, DVec3, f64)) -> Scene {
    let (eye, target, fov) = camera;
    let text = format!(
        r#"[camera]
position = [{}, {}, {}]
target = [{}, {}, {}]
fov_y_deg = {fov}

[light]
environment = "none"

[[lamp]]
kind = "point"
position = [{}, {}, {}]
intensity_cd = {INTENSITY_CD}
radius_m = {radius_m}

[[object]]
shape = "sphere"
material = "ball"
scale = {BALL_RADIUS}
translate = [{}, {}, {}]

[[object]]
shape = "ground"
material = "white"

[material.ball]
pigment = [{BALL_ALBEDO}, {BALL_ALBEDO}, {BALL_ALBEDO}]

[material.white]
pigment = [{ALBEDO}, {ALBEDO}, {ALBEDO}]

[render]
samples = 1
"#,
        eye.x, eye.y, eye.z, target.x, target.y, target.z, lamp.x, lamp.y, lamp.z, BALL.x, BALL.y, BALL.z
    );
    Scene::parse(&text, "lamp-shadow.toml", std::path::Path::new(".")).unwrap()
}

/// The ray through pixel (x, y) of a w×h frame of `scene`'s camera: its origin and unit direction.
fn pixel_ray(scene: &Scene, (w, h): (u32, u32), (x, y): (u32, u32)) -> (DVec3, DVec3) {
    let inverse = scene.camera.view_projection(w as f32 / h as f32).inverse().as_dmat4();
    let ndc = |p: u32, n: u32| (f64::from(p) + 0.5) / f64::from(n) * 2.0 - 1.0;
    let at = |z: f64| {
        let v = inverse * glam::DVec4::new(ndc(x, w), ndc(y, h), z, 1.0);
        v.truncate() / v.w
    };
    // Depth 1 at the near plane, 0 at the far one.
    let (a, b) = (at(0.9), at(0.5));
    (a, (b - a).normalize())
}

/// A lamp's light on a Lambertian point `p` facing `n`, cd/m² (ρ·I·cos θ/(π(d² + r²)), as `Lamp::light_at`).
fn lambert(albedo: f64, lamp: DVec3, radius_m: f64, p: DVec3, n: DVec3) -> f64 {
    let to = lamp - p;
    albedo * INTENSITY_CD * n.dot(to.normalize()).max(0.0)
        / (std::f64::consts::PI * (to.length_squared() + radius_m * radius_m))
}

/// The luminance of pixel `i` of a linear RGBA frame.
fn luminance(frame: &[f32], i: usize) -> f64 {
    let px = &frame[4 * i..][..3];
    0.2126 * f64::from(px[0]) + 0.7152 * f64::from(px[1]) + 0.0722 * f64::from(px[2])
}

/// The lamp, its disc and the scene of the sharp-shadow tests.
const SHARP_LAMP: DVec3 = DVec3::new(0.9, 2.3, 0.5);
const SHARP_RADIUS_M: f64 = 0.002;

fn sharp_scene() -> Scene {
    ball_scene(SHARP_LAMP, SHARP_RADIUS_M, (DVec3::new(2.5, 4.0, 5.0), DVec3::new(-0.8, 0.3, -0.5), 50.0))
}

/// Where pixel (x, y) of `scene` (the ball's) meets the ground away from the ball and from the edge of the ball's
/// shadow under the lamp at `lamp`: the point, and whether the ball hides the lamp's centre from it.
fn ground_seen(scene: &Scene, size: (u32, u32), (x, y): (u32, u32), lamp: DVec3) -> Option<(DVec3, bool)> {
    use crate::shadow::ray_sphere;
    let (o, d) = pixel_ray(scene, size, (x, y));
    let (miss, hit) = ray_sphere(o, d, BALL, BALL_RADIUS);
    if hit.is_some() || (miss - BALL_RADIUS).abs() < 0.03 * BALL_RADIUS || d.y >= 0.0 {
        return None;
    }
    let g = o - d * (o.y / d.y);
    let to_lamp = lamp - g;
    let (gap, blocked) = ray_sphere(g, to_lamp.normalize(), BALL, BALL_RADIUS);
    let behind = blocked.is_some_and(|b| (b - g).length() < to_lamp.length());
    ((gap - BALL_RADIUS).abs() >= 0.03 * BALL_RADIUS).then_some((g, behind))
}

/// The G-buffer the exact reference reads holds each lamp's visible share as the frames have it: 0 where the
/// ball hides the lamp from the ground, 1 elsewhere (away from the edges).
#[test]
fn the_gbuffer_holds_the_share_of_a_lamp_no_shadow_hides() {
    let scene = sharp_scene();
    let size = (160u32, 120u32);
    let camera = (&scene.camera, scene.light_dir);
    let gbuffer = crate::harness::gpu_test(|ctx| {
        diffract::render::gbuffer::GBuffer::draw(ctx, &scene, camera, size, true).unwrap()
    });
    let (mut compared, mut dark) = (0, 0);
    for y in 0..size.1 {
        for x in 0..size.0 {
            let Some((_, behind)) = ground_seen(&scene, size, (x, y), SHARP_LAMP) else { continue };
            let seen = gbuffer.pixels[(y * size.0 + x) as usize].expect("the ground");
            let want = if behind { 0.0 } else { 1.0 };
            assert!(
                (seen.lamp_visible[0] - want).abs() < 0.01,
                "pixel ({x}, {y}): {} for {want}",
                seen.lamp_visible[0]
            );
            assert!(seen.lamp_visible[1..].iter().all(|&v| v == 1.0), "no other lamp: {:?}", seen.lamp_visible);
            compared += 1;
            dark += usize::from(behind);
        }
    }
    assert!(compared > 10_000 && dark > 500, "compared {compared}, in the shadow {dark}");
}

#[test]
fn a_ball_under_a_lamp_shadows_the_ground_where_the_lamps_rays_are_blocked() {
    use crate::shadow::ray_sphere;
    let (lamp, radius_m) = (SHARP_LAMP, SHARP_RADIUS_M);
    let scene = sharp_scene();
    let size = (160u32, 120u32);
    for path in [ShadingPath::Forward, ShadingPath::Visibility] {
        let frame = crate::capture::one_sample_frame(&scene, size, path);
        let (mut compared, mut dark, mut worst) = (0, 0, 0.0f64);
        for y in 0..size.1 {
            for x in 0..size.0 {
                let (o, d) = pixel_ray(&scene, size, (x, y));
                let (miss, hit) = ray_sphere(o, d, BALL, BALL_RADIUS);
                if (miss - BALL_RADIUS).abs() < 0.03 * BALL_RADIUS {
                    continue;
                }
                let want = if let Some(p) = hit {
                    let n = (p - BALL).normalize();
                    match n.dot((lamp - p).normalize()) {
                        c if c > 0.25 => lambert(BALL_ALBEDO, lamp, radius_m, p, n),
                        c if c < -0.05 => 0.0,
                        _ => continue,
                    }
                } else {
                    let Some((g, behind)) = ground_seen(&scene, size, (x, y), lamp) else { continue };
                    if behind {
                        0.0
                    } else {
                        lambert(ALBEDO, lamp, radius_m, g, DVec3::Y)
                    }
                };
                let got = luminance(&frame, (y * size.0 + x) as usize);
                let floor = 0.02 * lambert(ALBEDO, lamp, radius_m, DVec3::ZERO, DVec3::Y);
                let off = (got - want).abs() / want.max(floor);
                worst = worst.max(off);
                assert!(off < 0.01, "{path:?}, pixel ({x}, {y}): {got} cd/m² where {want} is expected");
                compared += 1;
                dark += usize::from(want == 0.0);
            }
        }
        eprintln!("{path:?}: {compared} pixels compared, {dark} dark, worst {worst:.2e}");
        assert!(compared > 10_000 && dark > 500, "{path:?}: compared {compared}, in shadow or unlit {dark}");
    }
}

/// A lamp 30 cm across, 2.4 m above a ball 1.2 m up, casts its umbra ringed by a penumbra some 15 cm wide: each
/// ground pixel must show the share of the lamp's disc the ball leaves visible (two discs' overlap, closed form) —
/// on average within 4 % of the lamp's light, unbiased within 1.5 %.
#[test]
fn a_large_lamp_casts_the_penumbra_of_its_disc() {
    let lamp = DVec3::new(0.4, 3.6, 0.2);
    let radius_m = 0.15;
    let foot = BALL + (BALL - lamp) * (BALL.y / (lamp.y - BALL.y));
    let scene = ball_scene(lamp, radius_m, (foot + DVec3::new(0.0, 3.0, 0.001), foot, 40.0));
    let size = (128u32, 128u32);
    let frame = crate::capture::one_sample_frame(&scene, size, ShadingPath::Forward);
    let mut penumbra = crate::shadow::Penumbra::default();
    for y in 0..size.1 {
        for x in 0..size.0 {
            let (o, d) = pixel_ray(&scene, size, (x, y));
            if crate::shadow::ray_sphere(o, d, BALL, BALL_RADIUS).1.is_some() {
                continue;
            }
            let g = o - d * (o.y / d.y);
            let (to_lamp, to_ball) = (lamp - g, BALL - g);
            let alpha = (radius_m / to_lamp.length()).atan();
            let beta = (BALL_RADIUS / to_ball.length()).asin();
            let gamma = to_lamp.normalize().dot(to_ball.normalize()).clamp(-1.0, 1.0).acos();
            let share = crate::shadow::visible_share(alpha, beta, gamma);
            let lit = lambert(ALBEDO, lamp, radius_m, g, DVec3::Y);
            penumbra.add(luminance(&frame, (y * size.0 + x) as usize) / lit, share);
        }
    }
    let ((mean, bias), (pixels, worst)) = (penumbra.mean_and_bias(), (penumbra.pixels, penumbra.worst));
    eprintln!("{pixels} penumbra pixels: mean |error| {mean:.4}, mean error {bias:+.4}, worst {worst:.3}");
    assert!(pixels > 500, "only {pixels} pixels in the penumbra");
    assert!(mean < 0.04 && bias.abs() < 0.015, "penumbra: mean |error| {mean:.4}, mean error {bias:.4}");
}
