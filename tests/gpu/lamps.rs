//! Lamps against closed forms: a matte ground under a point lamp follows the inverse-square and cosine laws
//! (E(θ)/E(0) = cos³θ on a plane 1 m below a lamp) at its candela's absolute level (a white matte surface 1 m under a
//! 1 cd lamp has radiance 1/π cd/m²), on both shading paths.

use diffract::render::visibility::ShadingPath;
use diffract::scene::Scene;
use glam::{DVec3, Vec4};

const SIZE: u32 = 96;
const ALBEDO: f64 = 0.5;
const INTENSITY_CD: f64 = 3.0;

/// A matte ground of [`ALBEDO`] under a point lamp 1 m above the origin, seen from straight above (3 m up,
/// 70° across, so that the frame reaches 60° from the lamp's foot), lit by the lamp alone.
fn lamp_scene() -> Scene {
    let text = format!(
        r#"[camera]
position = [0.0, 3.0, 0.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov_y_deg = 70.0

[light]
environment = "none"

[[lamp]]
kind = "point"
position = [0.0, 1.0, 0.0]
intensity_cd = {INTENSITY_CD}
radius_m = 0.001

[[object]]
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
    for path in [ShadingPath::Forward, ShadingPath::Visibility] {
        let frame = render(&scene, path);
        let (mut worst, mut checked, mut widest) = (0.0f64, 0, 0.0f64);
        for y in 0..SIZE {
            for x in 0..SIZE {
                let p = ground_point(&scene, x, y);
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
