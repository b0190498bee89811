//! The surface pass (vertex stage, tangent frames, per-fragment directions) against the CPU reference.

use diffract::display::tone::encode;
use diffract::display::Tone;
use diffract::material::Settings;
use diffract::material::{Material, Reach};
use diffract::physics::colour::xyz_to_linear_srgb;
use diffract::physics::exact::{Method, Reference};
use diffract::physics::formats::png::PngScale;
use diffract::render::offscreen::render_surface;
use diffract::render::SceneView;
use diffract::scene::camera::Camera;
use diffract::scene::mesh::Mesh;
use glam::{DVec3, Vec3, Vec4};

use crate::harness::gpu_test;

const ONE: ash::vk::SampleCountFlags = ash::vk::SampleCountFlags::TYPE_1;

const HALF: f32 = 1.0;

/// A quad whose tangents are turned by `tangent_deg` (with `handedness`), and the view it is drawn under.
fn scene(tangent_deg: f32, handedness: f32) -> (Mesh, SceneView) {
    let mut mesh = Mesh::quad(HALF);
    let (s, c) = tangent_deg.to_radians().sin_cos();
    for v in &mut mesh.vertices {
        v.tangent = [c, s, 0.0, handedness];
    }
    let view = SceneView {
        camera: Camera {
            position: Vec3::new(0.35, -0.25, 2.4),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 40.0,
            near: 0.1,
            far: 10.0,
        },
        light_dir: Vec3::new(-0.3, 0.45, 0.84).normalize(),
        sun: 1.0,
        ambient: 0.0,
        sky_sh: [[0.0; 4]; 9],
        models: vec![glam::Mat4::IDENTITY],
        shadow_casters: None,
        behind: None,
        lighting: None,
        background: [0.0, 0.0, 0.0, 1.0],
        lamps: diffract::light::lamp::LampUniforms::NONE,
    };
    (mesh, view)
}

/// The world point under pixel (x, y) on the z = 0 plane, if it lies on the quad away from its border.
fn unproject(view: &SceneView, w: u32, h: u32, x: u32, y: u32) -> Option<Vec3> {
    let inv = view.camera.view_projection(w as f32 / h as f32).inverse();
    let ndc = |px: u32, n: u32| (px as f32 + 0.5) / n as f32 * 2.0 - 1.0;
    let (nx, ny) = (ndc(x, w), ndc(y, h));
    let near = inv * Vec4::new(nx, ny, diffract::scene::camera::NEAR_DEPTH, 1.0);
    let far = inv * Vec4::new(nx, ny, diffract::scene::camera::FAR_DEPTH, 1.0);
    let (a, b) = (near.truncate() / near.w, far.truncate() / far.w);
    let t = a.z / (a.z - b.z);
    let p = a + (b - a) * t;
    let margin = 0.06 * HALF;
    (p.x.abs() < HALF - margin && p.y.abs() < HALF - margin).then_some(p)
}

#[test]
fn surface_pixels_match_the_cpu_reference_in_a_rotated_tangent_frame() {
    let scale = PngScale { pixel_size_um: 0.065, height_um: 0.375 };
    let hf = diffract::physics::formats::load(&crate::harness::place::afm("elaphe-100px.png"), Some(scale))
        .unwrap()
        .tiled(3, 3)
        .unwrap();
    let settings = Settings { lambda_step_nm: 10.0, coherence_um: 8.0, ..Settings::default() };
    let mut material = Material::prepare(&hf, settings, &Reach::ANY).unwrap();
    material.set_display(2.0, diffract::display::Tone::Clip);
    let reference = Reference::new(&hf, material.window, Method::Taylor, material.plan).unwrap();
    let (w, h) = (64u32, 48u32);
    let (mesh, sc) = scene(30.0, -1.0);
    let (linear, display, display_filmic) = gpu_test(|ctx| {
        let l = render_surface(ctx, &material, &mesh, &sc, w, h, false).unwrap();
        let d = render_surface(ctx, &material, &mesh, &sc, w, h, true).unwrap();
        material.set_display(2.0, Tone::Filmic);
        let f = render_surface(ctx, &material, &mesh, &sc, w, h, true).unwrap();
        (l.linear().unwrap().to_vec(), d.rgba8().unwrap().to_vec(), f.rgba8().unwrap().to_vec())
    });
    // The patch frame: x = tangent, y = handedness · (n × t), z = n.
    let (s, c) = 30f64.to_radians().sin_cos();
    let t = DVec3::new(c, s, 0.0);
    let n = DVec3::Z;
    let b = -n.cross(t);
    let to_patch = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
    let omega_i = to_patch(sc.light_dir.as_dvec3());
    let (mut compared, mut lit) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let Some(p) = unproject(&sc, w, h, x, y) else { continue };
            let omega_r = to_patch((sc.camera.position - p).as_dvec3().normalize());
            let cpu = xyz_to_linear_srgb(reference.flss_xyz(omega_i, omega_r, &material.sampling));
            let i = ((y * w + x) * 4) as usize;
            let gpu = DVec3::new(linear[i].into(), linear[i + 1].into(), linear[i + 2].into());
            let scale = cpu.abs().max_element().max(1e-4);
            compared += 1;
            if cpu.max_element() > 1e-3 {
                lit += 1;
            }
            assert!((gpu - cpu).abs().max_element() / scale < 5e-3, "pixel ({x}, {y}): GPU {gpu} vs CPU {cpu}");
            // The shader's own exposure and tone curve (the sRGB transfer function clipped, and AgX) agree with
            // the CPU's to one code value.
            for (tone, shown) in [(Tone::Clip, &display), (Tone::Filmic, &display_filmic)] {
                let expected = encode(gpu, 2f64.exp2(), tone);
                for k in 0..3 {
                    assert!(
                        shown[i + k].abs_diff(expected[k]) <= 1,
                        "pixel ({x}, {y}) {} display {:?} vs {expected:?}",
                        tone.name(),
                        &shown[i..i + 3]
                    );
                }
            }
        }
    }
    assert!(compared > 1000 && lit > 20, "compared {compared}, lit {lit}");
}

#[test]
fn material_orientation_turns_the_patch_like_the_tangent() {
    use diffract::render::offscreen::OffscreenFrames;
    use diffract::render::surface::{orientation, MaterialInput, RendererSetup, SceneRenderer, SurfaceMaterial};
    let scale = PngScale { pixel_size_um: 0.065, height_um: 0.375 };
    let hf = diffract::physics::formats::load(&crate::harness::place::afm("elaphe-100px.png"), Some(scale))
        .unwrap()
        .tiled(2, 2)
        .unwrap();
    let settings = Settings { lambda_step_nm: 20.0, coherence_um: 8.0, ..Settings::default() };
    let material = Material::prepare(&hf, settings, &Reach::ANY).unwrap();
    let (w, h) = (48u32, 40u32);
    let render = |tangent_deg: f32, orientation_deg: f32| {
        let (mesh, sc) = scene(tangent_deg, 1.0);
        gpu_test(|ctx| {
            let surface =
                SurfaceMaterial { orientation: orientation(orientation_deg), pigment: [0.0; 3], matte: false };
            let inputs = [MaterialInput { material: &material, surface }];
            let setup = RendererSetup::forward(OffscreenFrames::format(false), false, ONE);
            let extent = ash::vk::Extent2D { width: w, height: h };
            let renderer = SceneRenderer::new(ctx, (&inputs, &[(&mesh, 0)]), setup, (&sc, extent)).unwrap();
            let frames = OffscreenFrames::new(ctx, w, h, false, ONE).unwrap();
            let frame = frames.render(ctx, &renderer, sc.background).unwrap();
            // SAFETY: render waited.
            unsafe {
                frames.destroy(ctx);
                renderer.destroy(ctx);
            }
            frame.linear().unwrap().to_vec()
        })
    };
    let by_tangent = render(30.0, 0.0);
    let by_orientation = render(0.0, 30.0);
    let unrotated = render(0.0, 0.0);
    let diff = |a: &[f32], b: &[f32]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
    let peak = by_tangent.iter().fold(0.0f32, |m, v| m.max(*v));
    assert!(peak > 1e-3, "something is lit");
    assert!(
        diff(&by_tangent, &by_orientation) < 1e-4 * peak.max(1.0),
        "orientation 30° equals a tangent turned by 30°"
    );
    assert!(diff(&by_tangent, &unrotated) > 1e-3 * peak, "and differs from the unturned patch");
}

/// A quad of uniform pigment, turned 20° in the image and lit only by the sky, drawn with `samples` per pixel:
/// linear RGBA rows.
fn silhouette_frame(samples: u32, material: &Material) -> (Vec<f32>, u32, u32) {
    let (frame, w, h) = silhouette(samples, material, true);
    (frame.linear().unwrap().to_vec(), w, h)
}

/// [`silhouette_frame`]'s frame itself, the quad said to be drawn front first (as it is) or not.
fn silhouette(samples: u32, material: &Material, front_first: bool) -> (diffract::render::Frame, u32, u32) {
    use diffract::render::offscreen::OffscreenFrames;
    use diffract::render::surface::{orientation, MaterialInput, RendererSetup, SceneRenderer, SurfaceMaterial};
    let (w, h) = (64u32, 64u32);
    let (mut mesh, mut sc) = scene(0.0, 1.0);
    mesh.front_first = front_first;
    sc.camera.position = Vec3::new(0.0, 0.0, 4.0);
    sc.models = vec![glam::Mat4::from_rotation_z(20f32.to_radians())];
    sc.light_dir = -Vec3::Z; // the sun behind the quad: no diffraction, no sunlit pigment
    sc.ambient = 1.0; // lit by the sky alone
    let linear = gpu_test(|ctx| {
        let samples = ctx.sample_count(samples, diffract::render::LINEAR_FORMAT).unwrap();
        let surface = SurfaceMaterial { orientation: orientation(0.0), pigment: [0.5, 0.5, 0.5], matte: false };
        let inputs = [MaterialInput { material, surface }];
        let setup = RendererSetup::forward(OffscreenFrames::format(false), false, samples);
        let extent = ash::vk::Extent2D { width: w, height: h };
        let renderer = SceneRenderer::new(ctx, (&inputs, &[(&mesh, 0)]), setup, (&sc, extent)).unwrap();
        let frames = OffscreenFrames::new(ctx, w, h, false, samples).unwrap();
        let frame = frames.render(ctx, &renderer, sc.background).unwrap();
        // SAFETY: render waited.
        unsafe {
            frames.destroy(ctx);
            renderer.destroy(ctx);
        }
        frame
    });
    (linear, w, h)
}

#[test]
fn a_frame_is_timed_pass_by_pass_and_the_passes_make_the_frame() {
    use diffract::render::pass;
    let hf = diffract::physics::heightfield::HeightField::new(32, 32, 0.1, 0.1, vec![0.0; 32 * 32]).unwrap();
    let settings = Settings { lambda_step_nm: 40.0, coherence_um: 3.2, ..Settings::default() };
    let material = Material::prepare(&hf, settings, &Reach::ANY).unwrap();
    // A flat quad hides nothing (`Mesh::front_first`) and needs no depth pre-pass; a mesh that may hide itself
    // gets one.
    for (samples, front_first, expected) in [
        (1, true, vec![pass::SHADING, pass::COPY]),
        (4, true, vec![pass::SHADING, pass::RESOLVE, pass::COPY]),
        (1, false, vec![pass::DEPTH, pass::SHADING, pass::COPY]),
        (4, false, vec![pass::DEPTH, pass::SHADING, pass::RESOLVE, pass::COPY]),
    ] {
        let (frame, _, _) = silhouette(samples, &material, front_first);
        let times = frame.times.clone().expect("lavapipe has timestamps");
        let names: Vec<&str> = times.passes.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, expected, "{samples} sample(s)");
        assert!(times.passes.iter().all(|p| p.ms.is_finite() && p.ms >= 0.0), "{times:?}");
        // The passes are laps between consecutive timestamps: they tile the frame.
        assert_eq!(frame.gpu_ms(), Some(times.passes.iter().map(|p| p.ms).sum()));
        assert!(times.total_ms() > 0.0 && times.pass_ms(pass::SHADING).unwrap() > 0.0, "{times:?}");
        assert_eq!(times.pass_ms(pass::PRESENT), None);
    }
}

#[test]
fn multisampling_gives_silhouette_pixels_intermediate_values() {
    let scale = PngScale { pixel_size_um: 0.065, height_um: 0.375 };
    let hf = diffract::physics::formats::load(&crate::harness::place::afm("elaphe-100px.png"), Some(scale)).unwrap();
    let settings = Settings { lambda_step_nm: 20.0, coherence_um: 6.5, ..Settings::default() };
    let material = Material::prepare(&hf, settings, &Reach::ANY).unwrap();
    // Pixels between the background (0) and the quad's colour: partly covered ones.
    let partial = |samples: u32| {
        let (linear, _, _) = silhouette_frame(samples, &material);
        let green: Vec<f32> = linear.chunks(4).map(|p| p[1]).collect();
        let inside = green.iter().copied().fold(0.0f32, f32::max);
        assert!(inside > 0.1, "the quad is drawn ({inside})");
        let count = green.iter().filter(|&&g| g > 0.1 * inside && g < 0.85 * inside).count();
        (count, green.iter().filter(|&&g| g >= 0.85 * inside).count())
    };
    let (aliased, area_1) = partial(1);
    let (smoothed, area_4) = partial(4);
    // The quad's outline crosses about 4 × 30 pixels; with 4 samples most of those are partly covered.
    assert_eq!(aliased, 0, "one sample per pixel: a pixel is in or out");
    assert!(smoothed > 60, "4 samples per pixel: {smoothed} silhouette pixels take intermediate values");
    assert!(area_4.abs_diff(area_1) < smoothed, "the covered area stays ({area_1} vs {area_4})");
}

/// The snake draws its triangles front first (`Mesh::front_first`: rows of scales from the head back, the eyes
/// before the head), so its frame needs no depth pre-pass: drawn with the depth test alone it is the frame the
/// pre-pass gives, but for pixels where two triangles lie at exactly the same depth (the first drawn keeps such a
/// pixel, as in the G-buffer, where with the pre-pass the last does).
#[test]
fn the_snake_drawn_front_first_is_the_frame_a_depth_pre_pass_gives() {
    use crate::capture::{capture_views, scene_materials};
    use diffract::scene::Scene;
    let mut scene = Scene::load(&crate::harness::place::assets().join("scenes/elaphe-snake-sun.toml")).unwrap();
    assert!(scene.objects[0].mesh.front_first);
    let (w, h) = (128, 128);
    let [front_first, pre_pass] = gpu_test(|ctx| {
        let materials = scene_materials(ctx, &scene, (w, h), &Default::default());
        let render = |scene: &Scene| {
            let frame = capture_views(ctx, scene, &materials, (w, h), ONE, &[SceneView::of(scene)]).remove(0);
            let times = frame.times.clone().expect("lavapipe has timestamps");
            (frame.linear().unwrap().to_vec(), times.pass_ms(diffract::render::pass::DEPTH).is_some())
        };
        let (drawn_front_first, had_pre_pass) = render(&scene);
        assert!(!had_pre_pass, "a front-first mesh is drawn without the pre-pass");
        scene.objects[0].mesh.front_first = false;
        let (drawn_after_pre_pass, had_pre_pass) = render(&scene);
        assert!(had_pre_pass, "any other mesh after one");
        [drawn_front_first, drawn_after_pre_pass]
    });
    let pixels = |f: &[f32]| f.chunks(4).map(|p| [p[0], p[1], p[2]]).collect::<Vec<_>>();
    let (a, b) = (pixels(&front_first), pixels(&pre_pass));
    let snake = a.iter().filter(|p| p.iter().any(|&c| c > 0.0)).count();
    let differ = a.iter().zip(&b).filter(|(p, q)| p != q).count();
    assert!(snake > 2000, "the snake covers {snake} pixels");
    assert!(differ <= snake / 500, "{differ} of the snake's {snake} pixels differ");
}

/// Depth that holds what the camera accepts: a ground of 10⁴ units seen with near 0.01 and far 10⁵ (far/near
/// 10⁷, the most a scene may ask) draws the frame that near 0.1 and far 10³ draw (before reversed depth, 97 % of
/// it came out black: the depth buffer could not tell the ground from the far plane).
#[test]
fn a_large_ground_under_a_wide_depth_range_draws_as_under_a_narrow_one() {
    let scene = |near: &str, far: &str| {
        let text = format!(
            "[camera]\nposition = [0.0, 2.0, 6.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 40.0\nnear = {near}\n\
             far = {far}\n\n[light]\ndirection = [0.3, 1.0, 0.5]\nenvironment = \"none\"\n\n[material.ground]\n\
             pigment = [0.3, 0.3, 0.3]\n\n[material.ball]\npigment = [0.6, 0.6, 0.6]\n\n[[object]]\n\
             shape = \"ground\"\nmaterial = \"ground\"\nscale = 1e4\n\n[[object]]\nshape = \"sphere\"\n\
             material = \"ball\"\ntranslate = [0.0, 1.0, 0.0]\n"
        );
        diffract::scene::Scene::parse(&text, "ground.toml", std::path::Path::new(".")).unwrap()
    };
    let size = (96, 96);
    let wide = crate::capture::render_scene(&scene("0.01", "1e5"), size);
    let narrow = crate::capture::render_scene(&scene("0.1", "1e3"), size);
    let (mut lit, mut differ) = (0, 0);
    for (a, b) in wide.chunks_exact(4).zip(narrow.chunks_exact(4)) {
        if b[..3].iter().all(|&c| c > 0.0) {
            lit += 1;
            differ += usize::from((0..3).any(|c| (a[c] - b[c]).abs() > 0.01 * b[c]));
        }
    }
    // The narrow range's far plane cuts the ground a pixel row or two below the horizon.
    assert!(lit > size.0 as usize * size.1 as usize / 3, "lit {lit}");
    assert!(differ * 50 < lit, "{differ} of {lit} lit pixels differ");
}
