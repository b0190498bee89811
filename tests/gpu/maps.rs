//! Surface maps against closed forms: a normal map that tilts every texel 10° towards +u puts a flat mirror's glint
//! where a mirror with that normal reflects the sun into the camera; a pigment map multiplies a matte ground's
//! radiance by its texels' linear values (sRGB decoded). Both shading paths.

use std::path::{Path, PathBuf};

use diffract::render::visibility::ShadingPath;
use diffract::scene::Scene;
use glam::{DVec3, Vec4};

const SIZE: u32 = 256;

/// A folder of test `name`'s maps.
fn maps_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("diffract-maps-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes an 8×8 PNG of one colour.
fn solid_png(dir: &Path, name: &str, rgb: [u8; 3]) {
    image::RgbImage::from_pixel(8, 8, image::Rgb(rgb)).save(dir.join(name)).unwrap();
}

/// The normal an 8-bit normal-map texel encodes, in the tangent frame (u, n × t, n).
fn decoded(rgb: [u8; 3]) -> DVec3 {
    DVec3::from_array(rgb.map(|c| f64::from(c) / 255.0 * 2.0 - 1.0)).normalize()
}

/// A ground of flat mirror (`generate = "flat"`) with the normal map `map`, seen from (0, 1, 2), the sun behind
/// the camera's target (towards (0, 1, −1)), so that the unmapped glint lies at (0, 0, 1).
fn glint_scene(dir: &Path, map: &str) -> Scene {
    let text = format!(
        r#"[camera]
position = [0.0, 1.0, 2.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_y_deg = 50.0

[light]
direction = [0.0, 1.0, -1.0]
environment = "none"

[[object]]
shape = "ground"
material = "mirror"

[material.mirror]
generate = "flat"
normal_map = "{map}"
pigment = [0.02, 0.02, 0.02]

[render]
samples = 1
"#
    );
    Scene::parse(&text, "glint.toml", dir).unwrap()
}

fn render(scene: &Scene, path: ShadingPath) -> Vec<f32> {
    crate::capture::one_sample_frame(scene, (SIZE, SIZE), path)
}

fn luminance(frame: &[f32], i: usize) -> f64 {
    0.2126 * f64::from(frame[4 * i]) + 0.7152 * f64::from(frame[4 * i + 1]) + 0.0722 * f64::from(frame[4 * i + 2])
}

/// The glint's centre (pixels, centre-based): the luminance-weighted mean of the pixels above half the brightest.
fn glint_centre(frame: &[f32]) -> (f64, f64) {
    let n = (SIZE * SIZE) as usize;
    let peak = (0..n).map(|i| luminance(frame, i)).fold(0.0, f64::max);
    let (mut sum, mut x, mut y) = (0.0, 0.0, 0.0);
    for i in (0..n).filter(|&i| luminance(frame, i) > 0.5 * peak) {
        let w = luminance(frame, i);
        sum += w;
        x += w * (i % SIZE as usize) as f64;
        y += w * (i / SIZE as usize) as f64;
    }
    (x / sum, y / sum)
}

/// Where on the ground (y = 0) a mirror of world normal `n` reflects the sun into the camera, in pixels.
fn predicted(scene: &Scene, n: DVec3) -> (f64, f64) {
    let l = scene.light_dir.as_dvec3().normalize();
    let r = 2.0 * l.dot(n) * n - l;
    let c = scene.camera.position.as_dvec3();
    let p = c - r * (c.y / r.y);
    let clip = scene.camera.view_projection(1.0) * Vec4::new(p.x as f32, p.y as f32, p.z as f32, 1.0);
    let ndc = clip.truncate() / clip.w;
    let pixel = |ndc: f32| (f64::from(ndc) + 1.0) / 2.0 * f64::from(SIZE) - 0.5;
    (pixel(ndc.x), pixel(ndc.y))
}

#[test]
fn a_normal_map_tilting_ten_degrees_puts_the_glint_where_that_normal_does() {
    let dir = maps_dir("glint");
    // sin 10°, 0, cos 10° encoded as (c + 1)/2: the texel tilts the normal 10.2° towards +u (+x on the ground).
    let (tilt, flat, down) = ([150, 128, 253], [128, 128, 255], [128, 106, 253]);
    solid_png(&dir, "tilt.png", tilt);
    solid_png(&dir, "flat.png", flat);
    solid_png(&dir, "down.png", down);
    // The ground's tangent frame: u along +x, n × t along −z, n up.
    let world = |m: DVec3| DVec3::new(m.x, m.z, -m.y);
    for (map, texel) in [("tilt.png", tilt), ("flat.png", flat), ("down.png", down)] {
        let scene = glint_scene(&dir, map);
        let expected = predicted(&scene, world(decoded(texel)));
        let inside = |c: f64| (8.0..f64::from(SIZE) - 8.0).contains(&c);
        assert!(inside(expected.0) && inside(expected.1), "{map}: the glint {expected:?} is not in the frame");
        for path in [ShadingPath::Forward, ShadingPath::Visibility] {
            let got = glint_centre(&render(&scene, path));
            let off = (got.0 - expected.0).hypot(got.1 - expected.1);
            eprintln!(
                "{map} {path:?}: glint at {got:.1?}, the mapped normal's mirror puts it at {expected:.1?}: {off:.2} px"
            );
            assert!(off < 3.0, "{map} {path:?}: the glint is {off} px from where its normal puts it");
        }
    }
    // The test can tell: the tilt moves the glint far more than the tolerance.
    let scene = glint_scene(&dir, "tilt.png");
    let (a, b) = (predicted(&scene, world(decoded(tilt))), predicted(&scene, world(decoded(flat))));
    assert!((a.0 - b.0).hypot(a.1 - b.1) > 30.0, "{a:?} {b:?}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_pigment_map_multiplies_a_matte_grounds_radiance_by_its_linear_texels() {
    let dir = maps_dir("pigment");
    // sRGB 188, 255, 64: linear 0.5029, 1, 0.0513.
    let texel = [188u8, 255, 64];
    solid_png(&dir, "pigment.png", texel);
    let linear = texel.map(|c| {
        let c = f64::from(c) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    });
    let scene = |map: &str| {
        let text = format!(
            r#"[camera]
position = [0.0, 2.0, 0.5]
target = [0.0, 0.0, 0.0]
fov_y_deg = 50.0

[light]
direction = [0.3, 1.0, 0.2]
environment = "none"

[[object]]
shape = "ground"
material = "soil"

[material.soil]
pigment = [0.8, 0.6, 0.4]
{map}

[render]
samples = 1
"#
        );
        Scene::parse(&text, "pigment.toml", &dir).unwrap()
    };
    let plain = scene("");
    let mapped = scene("pigment_map = \"pigment.png\"\nmap_size_m = 0.25");
    for path in [ShadingPath::Forward, ShadingPath::Visibility] {
        let (a, b) = (render(&plain, path), render(&mapped, path));
        let mut worst = 0f64;
        for i in (0..(SIZE * SIZE) as usize).filter(|&i| a[4 * i + 1] > 0.0) {
            for c in 0..3 {
                let ratio = f64::from(b[4 * i + c]) / f64::from(a[4 * i + c]);
                worst = worst.max((ratio / linear[c] - 1.0).abs());
            }
        }
        eprintln!("{path:?}: mapped / plain against the texels' linear values: worst {worst:.2e}");
        assert!(worst < 0.01, "{path:?}: {worst}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
