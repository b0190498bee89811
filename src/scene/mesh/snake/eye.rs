//! The snake's eyes: round domes on the head's surface with a black pupil in a coloured iris, as geometry.

use glam::Vec3;

use crate::gpu::interface::Vertex;
use crate::scene::mesh::snake::pattern::PatternField;
use crate::scene::mesh::snake::{body_surface, SnakeSpec};
use crate::scene::mesh::Mesh;

/// Where the eyes sit: along the body (t) and their angle from the middle of the back, radians.
const EYE_T: f32 = 0.972;
const EYE_FROM_TOP: f32 = 1.0;
/// The eye's radius as a length along the body in t, and its rings: the pupil's edge (a sharp colour edge, two
/// rings at one radius), the rim where the dome meets the head, and a skirt that tucks under the head's surface.
const EYE_RADIUS_T: f32 = 0.0042;
pub(super) const EYE_RINGS: [(f32, bool); 6] =
    [(0.3, true), (0.6, true), (0.6, false), (0.8, false), (1.0, false), (1.0, false)];
pub(super) const EYE_SECTORS: u32 = 24;

/// One eye (`side` −1 or 1: which side of the head): a round dome on the head's surface, raised up to 0.42 of its
/// radius, with a black pupil in a coloured iris — geometry, so that its edges stay round at any distance, where
/// a painted eye would follow the head's grid.
pub(super) fn eye(spec: &SnakeSpec, m: &mut Mesh, pattern: &PatternField, side: f32) {
    let frame = EyeFrame::new(spec, side);
    let (pupil, iris) = pattern.eye_tints();
    let base = m.vertices.len() as u32;
    m.vertices.push(frame.vertex(0.0, 0.0, dome(0.0), pupil, false));
    for (ring, &(r, is_pupil)) in EYE_RINGS.iter().enumerate() {
        let skirt = ring == EYE_RINGS.len() - 1;
        for k in 0..EYE_SECTORS {
            let (sin, cos) = (std::f32::consts::TAU * k as f32 / EYE_SECTORS as f32).sin_cos();
            let lift = if skirt { -0.1 } else { dome(r) };
            m.vertices.push(frame.vertex(r * cos, r * sin, lift, if is_pupil { pupil } else { iris }, skirt));
        }
    }
    let triangles = eye_triangles(base);
    // Fronts outwards: the winding that the first triangle's normal agrees with.
    let position = |i: u32| Vec3::from(m.vertices[i as usize].position);
    let [a, b, c] = triangles[0];
    let face = (position(b) - position(a)).cross(position(c) - position(a));
    let flip = face.dot(Vec3::from(m.vertices[a as usize].normal)) < 0.0;
    for [a, b, c] in triangles {
        m.indices.extend_from_slice(&if flip { [a, c, b] } else { [a, b, c] });
    }
}

/// The dome's height at `r` eye radii from its centre, in eye radii along the head's normal.
fn dome(r: f32) -> f32 {
    0.12 + 0.3 * (1.0 - r * r).max(0.0)
}

/// The head's tangent plane at an eye, and the map from a point (x, y) of it (in eye radii, x along the body) to
/// the head's parameters (t, a) under it.
struct EyeFrame<'a> {
    spec: &'a SnakeSpec,
    side: f32,
    /// The eye's centre in parameters and in the world.
    t0: f32,
    a0: f32,
    centre: Vec3,
    /// The head's surface derivatives at the centre, in t and in the angle.
    e_t: Vec3,
    e_a: Vec3,
    /// An orthonormal frame of the tangent plane, `tangent_t` along the body.
    tangent_t: Vec3,
    tangent_b: Vec3,
    /// The eye's radius in world units.
    radius: f32,
}

impl<'a> EyeFrame<'a> {
    fn new(spec: &'a SnakeSpec, side: f32) -> Self {
        let (t0, a0) = (EYE_T, std::f32::consts::FRAC_PI_2 + side * EYE_FROM_TOP);
        // (x, y) along the tangent plane's orthonormal frame become parameter offsets through the derivatives, so
        // the eye is round in the world although the tapering head's parameters are neither isotropic nor
        // orthogonal.
        const STEP: f32 = 1e-3;
        let at = |t: f32, a: f32| body_surface(spec, t, a).0;
        let e_t = (at(t0 + STEP, a0) - at(t0 - STEP, a0)) / (2.0 * STEP);
        let e_a = (at(t0, a0 + STEP) - at(t0, a0 - STEP)) / (2.0 * STEP);
        let tangent_t = e_t.normalize();
        let tangent_b = (e_a - tangent_t * tangent_t.dot(e_a)).normalize();
        let radius = EYE_RADIUS_T * e_t.length();
        Self { spec, side, t0, a0, centre: at(t0, a0), e_t, e_a, tangent_t, tangent_b, radius }
    }

    /// Parameter offsets for an offset (u, v) in the tangent plane, to first order.
    fn solve(&self, u: f32, v: f32) -> (f32, f32) {
        let da = v / self.tangent_b.dot(self.e_a);
        ((u - da * self.tangent_t.dot(self.e_a)) / self.e_t.length(), da)
    }

    /// The point of the head that the tangent plane's (x, y) lies over (seen along the normal), by a few Newton
    /// steps from the first-order guess: the head's section curves too fast round the jaw for that guess alone.
    fn params(&self, x: f32, y: f32) -> (f32, f32) {
        let (mut t, mut a) = (self.t0, self.a0);
        for _ in 0..4 {
            let d = body_surface(self.spec, t, a).0 - self.centre;
            let (dt, da) = self
                .solve(x * self.radius - d.dot(self.tangent_t), self.side * y * self.radius - d.dot(self.tangent_b));
            (t, a) = (t + dt, a + da);
        }
        (t, a)
    }

    /// The dome at (x, y) in eye radii; `lift` in eye radii along the head's normal (the skirt: below it).
    fn surface(&self, x: f32, y: f32, lift: f32) -> Vec3 {
        let (t, a) = self.params(x, y);
        let (p, n, _) = body_surface(self.spec, t, a);
        p + n * (lift * self.radius)
    }

    /// The vertex at (x, y) lifted by `lift`, tinted `tint`; `flat`: with the head's normal instead of the
    /// dome's.
    fn vertex(&self, x: f32, y: f32, lift: f32, tint: [f32; 3], flat: bool) -> Vertex {
        let (t, a) = self.params(x, y);
        let (on_head, body_normal, body_along) = body_surface(self.spec, t, a);
        let p = on_head + body_normal * (lift * self.radius);
        let n = if flat {
            body_normal
        } else {
            const D: f32 = 1e-3;
            let r = |x: f32, y: f32| (x * x + y * y).sqrt();
            let dx = self.surface(x + D, y, dome(r(x + D, y))) - self.surface(x - D, y, dome(r(x - D, y)));
            let dy = self.surface(x, y + D, dome(r(x, y + D))) - self.surface(x, y - D, dome(r(x, y - D)));
            let n = dx.cross(dy).try_normalize().unwrap_or(body_normal);
            if n.dot(body_normal) < 0.0 {
                -n
            } else {
                n
            }
        };
        let tangent =
            (body_along - n * n.dot(body_along)).try_normalize().unwrap_or_else(|| n.any_orthonormal_vector());
        Vertex {
            position: p.to_array(),
            normal: n.to_array(),
            tangent: [tangent.x, tangent.y, tangent.z, 1.0],
            uv: [t, (self.a0 / std::f32::consts::TAU + 0.25).rem_euclid(1.0)],
            pigment: tint,
        }
    }
}

/// An eye's triangles, its centre at vertex `base` and its rings after it: the centre's fan, then a band of quads
/// between consecutive rings (none across the pupil's doubled ring).
fn eye_triangles(base: u32) -> Vec<[u32; 3]> {
    let ring_start = |ring: u32| base + 1 + ring * EYE_SECTORS;
    let mut triangles = Vec::new();
    for k in 0..EYE_SECTORS {
        triangles.push([base, ring_start(0) + k, ring_start(0) + (k + 1) % EYE_SECTORS]);
    }
    for ring in 0..EYE_RINGS.len() as u32 - 1 {
        if EYE_RINGS[ring as usize].1 != EYE_RINGS[ring as usize + 1].1 {
            continue;
        }
        for k in 0..EYE_SECTORS {
            let (a, b) = (ring_start(ring) + k, ring_start(ring) + (k + 1) % EYE_SECTORS);
            let (c, d) = (ring_start(ring + 1) + k, ring_start(ring + 1) + (k + 1) % EYE_SECTORS);
            triangles.push([a, c, b]);
            triangles.push([b, c, d]);
        }
    }
    triangles
}
