//! The sun's shadow against closed forms: a matte ball above a matte ground, lit by the sun alone, is ray-cast
//! on the CPU (an exact sphere and plane) and every pixel away from an edge must match — the ground in the
//! ball's shadow black, the rest of it and the ball's lit side at albedo·Ω_sun/π·cos θ_i (a Lambertian surface
//! under a sun whose mirror glint is 1), with no acne on either.

use diffract::material::SettingsPatch;
use diffract::physics::optics::SUN_SOLID_ANGLE;
use diffract::render::SceneView;
use diffract::scene::camera::{FAR_DEPTH, NEAR_DEPTH};
use diffract::scene::Scene;
use glam::{DVec3, Vec4};

use crate::capture::{capture_views, scene_materials};
use crate::harness::gpu_test;

const BALL: DVec3 = DVec3::new(0.0, 1.6, 0.0);
const RADIUS: f64 = 1.0;
const ALBEDO: [f64; 2] = [0.6, 0.3]; // ball, ground

/// A matte ball of [`RADIUS`] at `ball` over a matte ground, seen and lit as `head` (its `[camera]` and `[light]`)
/// says.
fn ball_scene(head: &str, ball: DVec3) -> Scene {
    let text = format!(
        r#"{head}
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
        x = ball.x,
        y = ball.y,
        z = ball.z
    );
    Scene::parse(&text, "shadow.toml", std::path::Path::new(".")).unwrap()
}

fn scene(shadows: bool) -> Scene {
    let head = format!(
        "[camera]\nposition = [3.0, 6.0, 7.0]\ntarget = [-1.2, 0.4, 0.0]\nfov_y_deg = 40.0\n\n[light]\n\
         direction = [1.0, 1.1, 0.35]\nenvironment = \"none\"\nshadows = {shadows}\n"
    );
    ball_scene(&head, BALL)
}

fn render(scene: &Scene, size: (u32, u32)) -> Vec<f32> {
    crate::capture::render_scene(scene, size)
}

/// `views` of `scene` drawn one after another by one renderer at `size`, one sample per pixel: linear RGBA each.
fn render_views(scene: &Scene, size: (u32, u32), views: &[SceneView]) -> Vec<Vec<f32>> {
    gpu_test(|ctx| {
        let materials = scene_materials(ctx, scene, size, &SettingsPatch::default());
        let frames = capture_views(ctx, scene, &materials, size, ash::vk::SampleCountFlags::TYPE_1, views);
        frames.iter().map(|f| f.linear().unwrap().to_vec()).collect()
    })
}

/// Distance from `c` to the ray `o + t·d` (t ≥ 0; unit d), and the ray's first hit on the sphere if any.
pub(crate) fn ray_sphere(o: DVec3, d: DVec3, c: DVec3, r: f64) -> (f64, Option<DVec3>) {
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
    let (near, far) = (at(f64::from(NEAR_DEPTH)), at(f64::from(FAR_DEPTH)));
    let (o, d) = (near, (far - near).normalize());
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
    check_scene(&scene(shadows), shadows)
}

/// [`check`] of a scene that shows the ball and the ground as [`scene`]'s do.
fn check_scene(scene: &Scene, shadows: bool) -> (usize, usize) {
    let scene = scene.clone();
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

/// An object far outside the view (a cube 900 km away, beyond the camera's far plane) does not take the shadow
/// map's resolution from the shadows the camera sees: the map covers what is seen (before, fitted to every
/// caster, the ball's shadow vanished: 0 of 299 pixels).
#[test]
fn a_far_object_leaves_the_shadows_in_view_as_they_are() {
    let head = "[camera]\nposition = [3.0, 6.0, 7.0]\ntarget = [-1.2, 0.4, 0.0]\nfov_y_deg = 40.0\n\n[light]\n\
                direction = [1.0, 1.1, 0.35]\nenvironment = \"none\"\nshadows = true\n\n\
                [[object]]\nshape = \"cube\"\nmaterial = \"ball\"\ntranslate = [900000.0, 1.0, 0.0]\n";
    let far = ball_scene(head, BALL);
    assert_eq!(far.objects.len(), 3);
    let (compared, dark) = check_scene(&far, true);
    assert!(compared > 10_000 && dark > 300, "compared {compared}, in shadow or unlit {dark}");
}

/// One renderer draws views with and without shadows (each with its own pipeline: `SPEC_SHADOWS` compiles the
/// lookups out of the second), switching both ways, and each frame is the one a renderer made for it draws.
#[test]
fn a_renderer_switches_between_views_with_and_without_shadows() {
    let scene = scene(true);
    let (w, h) = (64, 48);
    let with = SceneView::of(&scene);
    let without = SceneView { shadow_casters: None, ..SceneView::of(&scene) };
    let frames = render_views(&scene, (w, h), &[with.clone(), without.clone(), with, without]);
    assert_eq!(frames[0], frames[2], "shadows again");
    assert_eq!(frames[1], frames[3], "no shadows again");
    assert_ne!(frames[0], frames[1], "the ball's shadow");
    assert_eq!(frames[0], render(&scene, (w, h)), "a renderer that only drew shadows");
    assert_eq!(frames[1], render(&self::scene(false), (w, h)), "a renderer that never drew shadows");
}

/// How far a penumbra's pixels are from the share of a light's disc they should show: over the pixels strictly
/// inside it (2–98 % visible), the count, the mean |error| and the mean error; over all, the worst.
#[derive(Default)]
pub(crate) struct Penumbra {
    pub pixels: usize,
    sum: f64,
    signed: f64,
    pub worst: f64,
}

impl Penumbra {
    /// A pixel showing `got` of the light where the closed form says `share`.
    pub fn add(&mut self, got: f64, share: f64) {
        self.worst = self.worst.max((got - share).abs());
        if share > 0.02 && share < 0.98 {
            self.pixels += 1;
            self.sum += (got - share).abs();
            self.signed += got - share;
        }
    }

    /// The mean |error| and the mean error.
    pub fn mean_and_bias(&self) -> (f64, f64) {
        (self.sum / self.pixels as f64, self.signed / self.pixels as f64)
    }
}

/// The fraction of the sun's disc (angular radius `a`) that a sphere of angular radius `b`, its centre `c` away
/// from the sun's, leaves visible: one minus the two discs' overlap over the sun's (small angles: plane circles).
pub(crate) fn visible_share(a: f64, b: f64, c: f64) -> f64 {
    let overlap = if c >= a + b {
        0.0
    } else if c <= (a - b).abs() {
        std::f64::consts::PI * a.min(b).powi(2)
    } else {
        let lens = (-c + a + b) * (c + a - b) * (c - a + b) * (c + a + b);
        a * a * ((c * c + a * a - b * b) / (2.0 * c * a)).acos()
            + b * b * ((c * c + b * b - a * a) / (2.0 * c * b)).acos()
            - 0.5 * lens.max(0.0).sqrt()
    };
    1.0 - overlap / (std::f64::consts::PI * a * a)
}

/// A ball 40 units above the ground casts an umbra ringed by the penumbra of the sun's 0.53° disc, some 0.37
/// units wide: each ground pixel must show the share of the disc the ball leaves visible (the overlap of two
/// discs, closed form): on average within 3 % of the sun's light and unbiased within 1 %, every pixel within 10 %
/// (the filter's steps).
#[test]
fn a_high_ball_casts_the_penumbra_of_the_suns_disc() {
    let light = DVec3::new(0.3, 1.0, 0.2).normalize();
    let ball = DVec3::new(0.0, 40.0, 0.0);
    let centre = ball - light * (ball.y / light.y);
    let head = format!(
        "[camera]\nposition = [{x}, 8.0, {z1}]\ntarget = [{x}, 0.0, {z}]\nfov_y_deg = 25.0\n\n[light]\n\
         direction = [0.3, 1.0, 0.2]\nenvironment = \"none\"\n",
        x = centre.x,
        z = centre.z,
        z1 = centre.z + 0.001
    );
    let scene = ball_scene(&head, ball);
    let size = (160u32, 120u32);
    let linear = render(&scene, size);
    let sun = SUN_SOLID_ANGLE / std::f64::consts::PI;
    let lit = ALBEDO[1] * sun * light.y;
    let alpha = (SUN_SOLID_ANGLE / std::f64::consts::PI).sqrt();
    let inv = scene.camera.view_projection(size.0 as f32 / size.1 as f32).inverse().as_dmat4();
    let mut penumbra = Penumbra::default();
    for y in 0..size.1 {
        for x in 0..size.0 {
            let ndc = |p: u32, n: u32| (f64::from(p) + 0.5) / f64::from(n) * 2.0 - 1.0;
            let at = |z: f64| {
                let v = inv * glam::DVec4::new(ndc(x, size.0), ndc(y, size.1), z, 1.0);
                v.truncate() / v.w
            };
            let (near, far) = (at(f64::from(NEAR_DEPTH)), at(f64::from(FAR_DEPTH)));
            let (o, d) = (near, (far - near).normalize());
            let g = o - d * (o.y / d.y);
            let to_ball = ball - g;
            let beta = (RADIUS / to_ball.length()).asin();
            let gamma = light.dot(to_ball.normalize()).clamp(-1.0, 1.0).acos();
            let share = visible_share(alpha, beta, gamma);
            let i = ((y * size.0 + x) * 4) as usize;
            penumbra.add(f64::from(linear[i]) / lit, share);
        }
    }
    // Measured on lavapipe: 2701 penumbra pixels, mean |error| 0.018 of the sun's light, mean error +0.003, the
    // worst 0.076 (the filter's 32 taps are the steps of a penumbra 170 texels wide).
    let ((mean, bias), worst) = (penumbra.mean_and_bias(), penumbra.worst);
    assert!(penumbra.pixels > 500, "only {} pixels in the penumbra", penumbra.pixels);
    assert!(mean < 0.03 && bias.abs() < 0.01, "penumbra: mean |error| {mean:.4}, mean error {bias:.4}");
    assert!(worst < 0.1, "the worst pixel is {worst:.3} of the sun's light off the disc's visible share");
}

/// The map depends on the sun and the objects, not on the camera: one renderer keeps its map while only the
/// camera moves and draws it again when the sun or an object moves, and each frame is the one a renderer made for
/// its view alone draws.
#[test]
fn the_shadow_map_is_drawn_again_when_the_sun_or_an_object_moves() {
    let head = |camera: &str, sun: &str| {
        format!(
            "[camera]\nposition = {camera}\ntarget = [-1.2, 0.4, 0.0]\nfov_y_deg = 40.0\n\n[light]\n\
             direction = {sun}\nenvironment = \"none\"\n"
        )
    };
    let scenes = [
        ball_scene(&head("[3.0, 6.0, 7.0]", "[1.0, 1.1, 0.35]"), BALL),
        // The camera moves: the same map.
        ball_scene(&head("[-4.0, 5.0, 6.0]", "[1.0, 1.1, 0.35]"), BALL),
        // The sun moves.
        ball_scene(&head("[-4.0, 5.0, 6.0]", "[-0.6, 1.0, 0.5]"), BALL),
        // The ball moves.
        ball_scene(&head("[-4.0, 5.0, 6.0]", "[-0.6, 1.0, 0.5]"), BALL + DVec3::new(0.8, 0.0, -0.5)),
        // And back: the first view again.
        ball_scene(&head("[3.0, 6.0, 7.0]", "[1.0, 1.1, 0.35]"), BALL),
    ];
    let (w, h) = (64, 48);
    let views: Vec<SceneView> = scenes.iter().map(SceneView::of).collect();
    let frames = render_views(&scenes[0], (w, h), &views);
    for (i, scene) in scenes.iter().enumerate() {
        assert_eq!(frames[i], render(scene, (w, h)), "view {i}: a renderer that only drew it");
    }
    assert_eq!(frames[0], frames[4]);
    assert!(frames.windows(2).all(|f| f[0] != f[1]), "every view differs from the one before");
}
