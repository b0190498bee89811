//! The procedural snake: a tapering body along an S-curve, lying on the ground (y = 0), tail at −x and head at
//! +x, covered in domed scales that overlap like roof tiles in the staggered (diamond) rows of a colubrid's back,
//! and painted with a corn snake's pattern. Everything follows from a [`SnakeSpec`] and its seed.
//!
//! Frames: the tangent runs along the body (tail to head), u = t along the body, v around it. Each scale is a
//! fan of triangles whose normals follow its dome, so the patch frame — and with it the diffracted colour — turns
//! across every scale, as on a real snake's skin. The pattern is carried as vertex pigment tints (relative to
//! [`CORN_GROUND`], the material's pigment in the default scene).

mod eye;
mod pattern;

use glam::{Quat, Vec3};

use self::eye::eye;
use self::pattern::PatternField;
use crate::gpu::interface::Vertex;
use crate::scene::mesh::grid_indices;
use crate::scene::mesh::{Mesh, UNTINTED};

/// The skin's colour pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Pattern {
    /// A corn snake (Pantherophis guttatus): red-orange saddles bordered in black on a lighter orange-tan ground,
    /// smaller blotches on the flanks, a cream belly, eyes with black pupils in red irises.
    #[default]
    Corn,
    /// One colour (the material's pigment), as a sunbeam snake.
    Plain,
}

/// The corn snake's ground colour, linear RGB albedo: the material pigment that the pattern's tints are relative
/// to (the default scene's pigment).
pub const CORN_GROUND: [f32; 3] = [0.60, 0.22, 0.06];
/// The saddles' red-orange, their black border and the cream belly (linear RGB albedo).
const CORN_SADDLE: [f32; 3] = [0.42, 0.045, 0.015];
const CORN_BORDER: [f32; 3] = [0.025, 0.02, 0.018];
const CORN_BELLY: [f32; 3] = [0.70, 0.60, 0.42];

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnakeSpec {
    /// Spine length (along x before the bends).
    pub length: f32,
    /// Body radius at its widest.
    pub radius: f32,
    /// Number of S-bends along the body.
    pub waves: f32,
    /// Sideways amplitude of the bends.
    pub amplitude: f32,
    /// Rings along the body and vertices around it (of the smooth body; scales are fans of their own).
    pub segments: u32,
    pub sides: u32,
    /// Rows of scales along the body and scales around it (0 rows: a smooth body). Neighbouring rows are offset
    /// by half a scale, so the scales sit in diagonal (diamond) rows.
    pub scale_rows: u32,
    pub scales_around: u32,
    /// Each scale rises towards its free, tail-side edge by this much (scales overlap like roof tiles), so its
    /// normal leans towards the head, degrees.
    pub scale_tilt_deg: f32,
    /// How high each scale's dome rises, relative to its half-width (0: flat scales; at most
    /// [`MAX_SCALE_DOME`]).
    pub scale_dome: f32,
    /// Points around each scale's outline: a scale is a fan of this many triangles from its crest to its edge,
    /// whose interpolated normals carry the dome (a parabolic dome's slope grows linearly from the crest, so
    /// interpolating the normal from crest to edge follows it closely).
    pub scale_outline: u32,
    /// Each scale is turned about the body's axis by up to this much, at random, degrees.
    pub scale_jitter_deg: f32,
    pub pattern: Pattern,
    pub seed: u64,
}

/// The highest dome a scene may ask for: as high as the scale is half wide.
pub const MAX_SCALE_DOME: f32 = 1.0;

impl Default for SnakeSpec {
    fn default() -> Self {
        Self {
            length: 4.0,
            radius: 0.13,
            waves: 1.4,
            amplitude: 0.32,
            segments: 360,
            sides: 40,
            scale_rows: 100,
            scales_around: 27,
            scale_tilt_deg: 8.0,
            scale_dome: 0.35,
            scale_outline: 16,
            scale_jitter_deg: 4.0,
            pattern: Pattern::Corn,
            seed: 1,
        }
    }
}

/// Where the neck is narrowest, where the head's plates take over from the body's scales, and where the jaws are
/// widest (t from tail 0 to snout 1).
const NECK: f32 = 0.9;
const HEAD_START: f32 = 0.925;
const JAW: f32 = 0.945;

/// Half-width and half-height of the cross-section along the body, relative to the radius, t ∈ [0, 1] from tail
/// to snout: a long taper to the tail tip, a narrow neck, then a colubrid's head — a little wider than the neck
/// at the jaws, flatter than the body, narrowing to a blunt, rounded snout (about 1.4 times as long as wide).
fn cross_section(t: f32) -> (f32, f32) {
    // The taper ends at t = 0.45 without a crease: its slope falls to zero there (a quadratic ease).
    let s = (t / 0.45).min(1.0);
    let tail = (s * (2.0 - s)).powf(0.75);
    let neck = 1.0 - 0.22 * (-((t - NECK) / 0.025).powi(2)).exp();
    let jaw = 1.0 + 0.12 * (-((t - JAW) / 0.018).powi(2)).exp();
    // From the jaws the head narrows towards the snout, and its last stretch is rounded off (an elliptical cap).
    let narrowing = smoothstep(0.95, 0.99, t);
    let taper = 1.0 - 0.4 * narrowing;
    let cap = if t > 0.985 { (1.0 - ((t - 0.985) / 0.015).powi(2)).max(0.0).sqrt() } else { 1.0 };
    let width = tail * neck * jaw * taper * cap;
    // The body's section is flattened underneath like a real snake's belly; the head is flatter still.
    let flat = 0.8 - 0.3 * smoothstep(NECK, JAW, t);
    let height = tail * neck * flat * (1.0 - 0.25 * narrowing) * cap;
    (width, height)
}

fn smoothstep(edge0: f32, edge1: f32, x: f32) -> f32 {
    let u = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    u * u * (3.0 - 2.0 * u)
}

/// The spine point at t (tail 0 to snout 1); the bends fade towards the head so that it points forwards.
fn spine(spec: &SnakeSpec, t: f32) -> Vec3 {
    let fade = 1.0 - 0.6 * t;
    let z = spec.amplitude * fade * (std::f32::consts::TAU * spec.waves * t).sin();
    Vec3::new((t - 0.5) * spec.length, 0.0, z)
}

/// The smooth body's surface point, normal and along-body direction at t (tail 0 to snout 1) and angle a around
/// the body (π/2: the middle of the back, −π/2: the belly).
fn body_surface(spec: &SnakeSpec, t: f32, a: f32) -> (Vec3, Vec3, Vec3) {
    let dt = 1.0 / spec.segments.max(2) as f32;
    let (t0, t1) = ((t - dt).max(0.0), (t + dt).min(1.0));
    let along = (spine(spec, t1) - spine(spec, t0)).normalize();
    let side = along.cross(Vec3::Y).normalize();
    let up = side.cross(along);
    let (sin, cos) = a.sin_cos();
    let section = |t: f32| {
        let (w, h) = cross_section(t);
        let c = spine(spec, t) + Vec3::Y * (0.8 * spec.radius);
        c + (side * (w * cos) + up * (h * sin)) * spec.radius
    };
    let position = section(t);
    // The normal from the surface's two directions: around the section, and along the body (the taper tilts it).
    let (w, h) = cross_section(t);
    let around = side * (-w * sin) + up * (h * cos);
    let lengthwise = section(t1) - section(t0);
    let normal = around.cross(lengthwise).try_normalize().unwrap_or_else(|| (side * cos + up * sin).normalize());
    let normal = if normal.dot(side * cos + up * sin) < 0.0 { -normal } else { normal };
    (position, normal, along)
}

/// A deterministic stream of numbers in [−1, 1) (xorshift).
struct Random(u64);

impl Random {
    fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f32 / (1u64 << 53) as f32 * 2.0 - 1.0
    }
}

/// Builds the snake: domed scales and a head of smooth plates (or, with `scale_rows` = 0, a smooth body with
/// untinted vertices).
pub fn snake(spec: &SnakeSpec) -> Mesh {
    if spec.scale_rows > 0 && spec.scales_around > 0 {
        return scaled(spec);
    }
    let mut m = Mesh { one_sided: true, ..Mesh::default() };
    smooth_part(spec, &mut m, (0.0, 1.0), (spec.segments, spec.sides), None);
    m
}

/// Appends the smooth body surface between t0 and t1 (tail 0 to snout 1) as a grid of `segments` rings of `sides`
/// quads, tinted by `pattern` if given.
fn smooth_part(
    spec: &SnakeSpec,
    m: &mut Mesh,
    (t0, t1): (f32, f32),
    (segments, sides): (u32, u32),
    pattern: Option<&PatternField>,
) {
    let mut part = Mesh::default();
    for i in 0..=segments {
        let t = t0 + (t1 - t0) * i as f32 / segments as f32;
        for s in 0..=sides {
            let v = s as f32 / sides as f32;
            let a = v * std::f32::consts::TAU;
            let (position, normal, along) = body_surface(spec, t, a);
            let tangent = (along - normal * normal.dot(along)).try_normalize().unwrap_or(along);
            part.vertices.push(Vertex {
                position: position.to_array(),
                normal: normal.to_array(),
                tangent: [tangent.x, tangent.y, tangent.z, 1.0],
                uv: [t, v],
                pigment: pattern.map_or(UNTINTED, |p| p.tint(t, a)),
            });
        }
    }
    grid_indices(&mut part, segments, sides, true);
    let base = m.vertices.len() as u32;
    m.vertices.extend(part.vertices);
    m.indices.extend(part.indices.into_iter().map(|i| base + i));
}

/// How far a scale reaches from its centre, in rows: back over the row behind it (its free edge) and forwards
/// under the row ahead (the same, so that the dome's slope is continuous across its middle); sideways in scales
/// (beyond 0.5 it overlaps its neighbours). With the rows 1/100 of the body's length and 27 scales around, the
/// part of each scale left uncovered by the row ahead is about 1.4 rows long (0.055) and one scale wide (0.027) at
/// the middle of the body: about twice as long as wide, as a colubrid's dorsal scales (the Elaphe has 25–27 rows
/// around).
const REACH_BACK: f32 = 1.1;
const REACH_FRONT: f32 = 1.1;
const HALF_WIDTH: f32 = 0.62;
/// Rings and vertices around of the head's smooth surface: fine enough for its eye stripes and crown (the eyes are
/// their own geometry), coarse enough not to slow the viewer (64×72 cost it about a tenth of its frame).
const HEAD_GRID: (u32, u32) = (40, 48);
/// The exponent of the scale's outline |x|^p + |y|^p = 1: 1 is a diamond, 2 an ellipse (the paraboloid dome
/// vanishes on it); where the next row covers it, two ellipses leave a pointed, diamond-like exposed part.
const OUTLINE_EXPONENT: f32 = 2.0;

/// The point of the outline's interior for the square grid point (sx, sy) ∈ [−1, 1]²
/// (concentric squares map to concentric outlines).
fn outline_interior(sx: f32, sy: f32) -> (f32, f32) {
    let r = sx.abs().max(sy.abs());
    if r == 0.0 {
        return (0.0, 0.0);
    }
    let (dx, dy) = (sx / r, sy / r);
    let k = (dx.abs().powf(OUTLINE_EXPONENT) + dy.abs().powf(OUTLINE_EXPONENT)).powf(-1.0 / OUTLINE_EXPONENT);
    (r * k * dx, r * k * dy)
}

/// The dome's height at outline point (x, y), 1 at its crest and 0 on its (elliptical) outline: a paraboloid,
/// whose slope grows linearly from the crest, as the rasterizer interpolates a fan's vertex normals — so the
/// interpolated normal follows the dome to second order and the colour bands run straight across the fan's edges
/// (`a_scales_interpolated_normal_follows_its_dome`). It is not clamped at the outline, so that the finite
/// differences of [`scale_vertex`] there see the dome's own slope on both sides.
fn dome(x: f32, y: f32) -> f32 {
    1.0 - x * x - y * y
}

/// The mosaic of domed scales. Row i's scales are centred at t = (i + ½)/rows, offset around the body by half a
/// scale in odd rows; each reaches [`REACH_BACK`] rows back and [`REACH_FRONT`] forwards, so that the free,
/// tail-side part of every scale lies over the attached part of the row behind it, lifted along the body's normal
/// by `scale_tilt_deg` (roof tiles) and domed across. Normals come from the dome's surface; each scale is also
/// turned at random about the body's axis by up to `scale_jitter_deg`.
fn scaled(spec: &SnakeSpec) -> Mesh {
    let mut m = Mesh { one_sided: true, ..Mesh::default() };
    let mut random = Random::new(spec.seed);
    let pattern = PatternField::new(spec.pattern, spec.seed);
    let (rows, around, outline) = (spec.scale_rows, spec.scales_around, spec.scale_outline.max(3));
    let row = 1.0 / rows as f32;
    // The body's scales, up to the head, each row's triangles apart.
    let mut scale_rows: Vec<Vec<u32>> = Vec::new();
    for i in 0..rows {
        let row_start = m.indices.len();
        let t_centre = (i as f32 + 0.5) * row;
        if t_centre >= HEAD_START {
            break;
        }
        let stagger = if i % 2 == 0 { 0.0 } else { 0.5 };
        for j in 0..around {
            let v_centre = (j as f32 + 0.5 + stagger) / around as f32;
            let turn = spec.scale_jitter_deg.to_radians() * random.next();
            let tint = pattern.tint(t_centre, angle(v_centre));
            let surface = |x: f32, y: f32| scale_surface(spec, (t_centre, v_centre), x, y);
            let base = m.vertices.len() as u32;
            let mut push =
                |(x, y)| m.vertices.push(scale_vertex(spec, &surface, (x, y), (t_centre, v_centre), turn, tint));
            push((0.0, 0.0));
            for k in 0..outline {
                push(outline_point(k, outline));
            }
            for k in 0..outline {
                m.indices.extend_from_slice(&[base, base + 1 + k, base + 1 + (k + 1) % outline]);
            }
        }
        scale_rows.push(m.indices.split_off(row_start));
    }
    // The head's large, smooth plates (from under the last row of scales to the snout), then its two eyes.
    let start = HEAD_START - REACH_BACK * row;
    smooth_part(spec, &mut m, (start, 1.0), HEAD_GRID, Some(&pattern));
    let head = std::mem::take(&mut m.indices);
    for side in [-1.0, 1.0] {
        eye(spec, &mut m, &pattern, side);
    }
    let eyes = std::mem::take(&mut m.indices);
    // Front first (`Mesh::front_first`): each row of scales lies over the row behind it (towards the tail), so the
    // rows go from the head backwards; then the eyes, then the head they lie on (whose start the last row covers).
    m.indices.extend(scale_rows.into_iter().rev().flatten());
    m.indices.extend(eyes);
    m.indices.extend(head);
    m.front_first = true;
    m
}

/// The scale's outline point k of `outline`: a point of the square's edge (concentric squares map to concentric
/// outlines), counterclockwise from the free edge's middle (−x) like the grid of (x, y) it stands for.
fn outline_point(k: u32, outline: u32) -> (f32, f32) {
    let (sin, cos) = (std::f32::consts::TAU * k as f32 / outline as f32).sin_cos();
    let edge = cos.abs().max(sin.abs());
    outline_interior(-cos / edge, -sin / edge)
}

/// The surface of the scale centred at (t_centre, v_centre) at its point (x, y) of the outline's interior: x from
/// −1 (free edge) to 1 (attached edge), y across.
fn scale_surface(spec: &SnakeSpec, (t_centre, v_centre): (f32, f32), x: f32, y: f32) -> Vec3 {
    let (row, around) = (1.0 / spec.scale_rows as f32, spec.scales_around as f32);
    let t_front = (t_centre + REACH_FRONT * row).min(1.0);
    // The first row's scales stop just short of the tail's tip, where the body's radius is nil: clamped at the tip,
    // the triangles by their free edge's middle folded over.
    let back = (REACH_BACK * row).min(0.8 * t_centre);
    let t = (t_centre + x * if x < 0.0 { back } else { REACH_FRONT * row }).clamp(0.0, 1.0);
    let v = v_centre + y * HALF_WIDTH / around;
    let (p, n, _) = body_surface(spec, t, angle(v));
    let (w, h) = cross_section(t);
    let half_width = HALF_WIDTH / around * std::f32::consts::TAU * spec.radius * 0.5 * (w + h);
    let lift = spec.scale_tilt_deg.to_radians().tan() * (t_front - t) * spec.length;
    p + n * (lift + spec.scale_dome * half_width * dome(x, y))
}

/// The angle around the body of v ∈ [0, 1) (v = 0 under the belly, ½ on the back).
fn angle(v: f32) -> f32 {
    (v - 0.25) * std::f32::consts::TAU
}

/// One vertex of a scale: its position on the dome, the dome's normal (turned by `turn` about the body's axis)
/// and a tangent along the scale, towards the head.
fn scale_vertex(
    spec: &SnakeSpec,
    surface: &impl Fn(f32, f32) -> Vec3,
    (x, y): (f32, f32),
    (t_centre, v_centre): (f32, f32),
    turn: f32,
    tint: [f32; 3],
) -> Vertex {
    const STEP: f32 = 1e-2;
    let p = surface(x, y);
    let d_along = surface(x + STEP, y) - surface(x - STEP, y);
    let d_across = surface(x, y + STEP) - surface(x, y - STEP);
    let (_, body_normal, along) = body_surface(spec, t_centre, angle(v_centre));
    let mut n = d_across.cross(d_along).try_normalize().unwrap_or(body_normal);
    if n.dot(body_normal) < 0.0 {
        n = -n;
    }
    let n = (Quat::from_axis_angle(along, turn) * n).normalize();
    let lengthwise = d_along.try_normalize().unwrap_or(along);
    let tangent = (lengthwise - n * n.dot(lengthwise)).try_normalize().unwrap_or_else(|| n.any_orthonormal_vector());
    Vertex {
        position: p.to_array(),
        normal: n.to_array(),
        tangent: [tangent.x, tangent.y, tangent.z, 1.0],
        uv: [t_centre, v_centre.rem_euclid(1.0)],
        pigment: tint,
    }
}

#[cfg(test)]
mod tests {
    use super::eye::{EYE_RINGS, EYE_SECTORS};
    use super::pattern::relative_to_ground;
    use super::*;
    use crate::scene::mesh::shapes::tests::check_outward_and_frames;

    #[test]
    fn smooth_body_tangents_run_along_it_and_normals_outwards() {
        let spec = SnakeSpec { scale_rows: 0, ..SnakeSpec::default() };
        let m = snake(&spec);
        check_outward_and_frames(&m, |p| p, "snake (winding only)");
        for (k, v) in m.vertices.iter().enumerate() {
            let t = (k as u32 / (spec.sides + 1)) as f32 / spec.segments as f32;
            if !(0.05..0.9).contains(&t) {
                continue;
            }
            let along = (spine(&spec, t + 0.001) - spine(&spec, t - 0.001)).normalize();
            let tangent = Vec3::new(v.tangent[0], v.tangent[1], v.tangent[2]);
            assert!(tangent.dot(along) > 0.95, "tangent along the body at t = {t}");
            let axis = spine(&spec, t) + Vec3::Y * (0.8 * spec.radius);
            assert!(Vec3::from(v.normal).dot(Vec3::from(v.position) - axis) > 0.0, "normal outwards at t = {t}");
        }
        let (lo, hi) = m.bounds();
        assert!((hi.x - lo.x - spec.length).abs() < 0.3 && lo.y >= -1e-3, "lies on the ground, {lo} {hi}");
    }

    #[test]
    fn the_head_is_wider_than_the_neck_and_flatter_than_the_body() {
        let (neck, _) = cross_section(NECK);
        let (head, head_height) = cross_section(0.95);
        let (body, body_height) = cross_section(0.6);
        assert!(head > 1.2 * neck, "head {head} vs neck {neck}");
        assert!(head_height / head < body_height / body, "the head is flatter");
        assert!(cross_section(1.0).0 < 0.05 && cross_section(0.0).0 < 0.05, "tapers to the snout and the tail");
    }

    #[test]
    fn the_eyes_are_round_raised_domes_with_a_black_pupil() {
        let spec = SnakeSpec::default();
        let m = snake(&spec);
        let per_eye = 1 + EYE_RINGS.len() * EYE_SECTORS as usize;
        let eyes = &m.vertices[m.vertices.len() - 2 * per_eye..];
        let pupil = PatternField::new(Pattern::Corn, spec.seed).eye_tints().0;
        for eye in eyes.chunks(per_eye) {
            let centre = Vec3::from(eye[0].position);
            assert_eq!(eye[0].pigment, pupil);
            // The rim (ring 4, where the dome meets the head), seen along the eye's axis (the centre's normal):
            // equally far from the centre all round.
            let axis = Vec3::from(eye[0].normal);
            let rim: Vec<f32> = eye[1 + 4 * EYE_SECTORS as usize..][..EYE_SECTORS as usize]
                .iter()
                .map(|v| {
                    let d = Vec3::from(v.position) - centre;
                    (d - axis * axis.dot(d)).length()
                })
                .collect();
            let (lo, hi) = rim.iter().fold((f32::MAX, 0.0f32), |(lo, hi), &d| (lo.min(d), hi.max(d)));
            assert!(hi < 1.1 * lo, "a round eye: rim distances {lo}..{hi}: {rim:?}");
            // Raised: the centre stands off the head's surface by 0.42 eye radii.
            let (surface, normal, _) = body_surface(&spec, eye[0].uv[0], angle(eye[0].uv[1]));
            assert!((centre - surface).dot(normal) > 0.3 * lo, "the eye bulges");
        }
    }

    #[test]
    fn scales_are_domed_lean_towards_the_head_and_face_outwards() {
        let spec = SnakeSpec::default();
        let m = snake(&spec);
        let per_scale = (spec.scale_outline + 1) as usize;
        let row = 1.0 / spec.scale_rows as f32;
        let rows = (0..spec.scale_rows).filter(|&i| (i as f32 + 0.5) * row < HEAD_START).count();
        let head = ((HEAD_GRID.0 + 1) * (HEAD_GRID.1 + 1)) as usize;
        let eyes = 2 * (1 + EYE_RINGS.len() * EYE_SECTORS as usize);
        assert_eq!(m.vertices.len(), per_scale * rows * spec.scales_around as usize + head + eyes);
        check_outward_and_frames(&m, |p| p, "scaled snake (winding only)");
        let (mut leans, mut spreads) = (Vec::new(), Vec::new());
        for scale in m.vertices.chunks(per_scale) {
            let t = scale[0].uv[0];
            if !(0.1..0.8).contains(&t) {
                continue;
            }
            let (_, _, along) = body_surface(&spec, t, angle(scale[0].uv[1]));
            let normals: Vec<Vec3> = scale.iter().map(|v| Vec3::from(v.normal)).collect();
            let mean = normals.iter().sum::<Vec3>().normalize();
            leans.push(-mean.dot(along));
            // The dome: the normals across one scale spread over several degrees.
            spreads.push(normals.iter().map(|n| n.angle_between(mean)).fold(0.0f32, f32::max).to_degrees());
        }
        let lean = leans.iter().sum::<f32>() / leans.len() as f32;
        // The lift tilts each scale by scale_tilt_deg; the dome, longer in front than behind, takes some of it back.
        let tilt = spec.scale_tilt_deg.to_radians().sin();
        assert!((-1.2 * tilt..-0.4 * tilt).contains(&lean), "scales lean towards the head: {lean} (tilt {tilt})");
        let spread = spreads.iter().sum::<f32>() / spreads.len() as f32;
        assert!(spread > 10.0, "each scale's normals follow its dome: {spread}°");
        let flat = snake(&SnakeSpec { scale_dome: 0.0, scale_jitter_deg: 0.0, ..spec });
        let flat_spread = flat.vertices[per_scale * 2000..per_scale * 2001]
            .iter()
            .map(|v| Vec3::from(v.normal).angle_between(Vec3::from(flat.vertices[per_scale * 2000].normal)))
            .fold(0.0f32, f32::max)
            .to_degrees();
        assert!(flat_spread < spread / 2.0, "without a dome the scale is nearly flat: {flat_spread}°");
    }

    /// How far the normal that the rasterizer interpolates across a scale's fan (its vertices' normals, weighted by
    /// barycentric coordinates, then normalised as the shaders do) turns from the dome's own normal at the same
    /// point, degrees: the largest over the points of a grid inside each triangle of the scales in the body's
    /// middle, and the mean of each scale's largest.
    fn fan_normal_error(spec: &SnakeSpec) -> (f32, f32) {
        let spec = SnakeSpec { scale_jitter_deg: 0.0, ..*spec };
        let m = snake(&spec);
        let outline = spec.scale_outline.max(3);
        let per_scale = (outline + 1) as usize;
        let points: Vec<(f32, f32)> =
            std::iter::once((0.0, 0.0)).chain((0..outline).map(|k| outline_point(k, outline))).collect();
        let (mut worst, mut sum, mut scales) = (0.0f32, 0.0f32, 0);
        for scale in m.vertices.chunks(per_scale).take(spec.scale_rows as usize * spec.scales_around as usize) {
            let (t_centre, v_centre) = (scale[0].uv[0], scale[0].uv[1]);
            if !(0.3..0.7).contains(&t_centre) {
                continue;
            }
            let surface = |x: f32, y: f32| scale_surface(&spec, (t_centre, v_centre), x, y);
            let mut largest = 0.0f32;
            for k in 0..outline as usize {
                let corners = [0, 1 + k, 1 + (k + 1) % outline as usize];
                const N: usize = 8;
                for i in 0..=N {
                    for j in 0..=N - i {
                        let b = [i as f32 / N as f32, j as f32 / N as f32, (N - i - j) as f32 / N as f32];
                        let (mut n, mut x, mut y) = (Vec3::ZERO, 0.0, 0.0);
                        for (&c, w) in corners.iter().zip(b) {
                            n += w * Vec3::from(scale[c].normal);
                            x += w * points[c].0;
                            y += w * points[c].1;
                        }
                        let exact = Vec3::from(
                            scale_vertex(&spec, &surface, (x, y), (t_centre, v_centre), 0.0, UNTINTED).normal,
                        );
                        largest = largest.max(n.normalize().angle_between(exact).to_degrees());
                    }
                }
            }
            worst = worst.max(largest);
            sum += largest;
            scales += 1;
        }
        (worst, sum / scales as f32)
    }

    #[test]
    fn a_scales_interpolated_normal_follows_its_dome() {
        // A paraboloid's slope grows linearly across the scale, as the rasterizer interpolates: the fan follows
        // it to second order. (A dome whose slope grew faster towards the outline's tips, as the earlier rounded
        // diamond's, turned its interpolated normal 8° (dome 0.12) and 18° (0.35) from the dome's, and the
        // colour bands kinked at each fan edge.)
        for (dome, worst_bound, mean_bound) in [(0.12, 0.5, 0.3), (0.35, 2.0, 1.5)] {
            let (worst, mean) = fan_normal_error(&SnakeSpec { scale_dome: dome, ..SnakeSpec::default() });
            assert!(
                worst < worst_bound && mean < mean_bound,
                "dome {dome}: the interpolated normal turns up to {worst:.2}° from the dome's, {mean:.2}° at a mean scale"
            );
        }
    }

    #[test]
    fn the_corn_pattern_has_saddles_borders_and_ground_and_is_deterministic() {
        let m = snake(&SnakeSpec::default());
        let count = |colour: [f32; 3]| {
            let tint = relative_to_ground(colour);
            m.vertices.iter().filter(|v| v.pigment == tint).count() as f32 / m.vertices.len() as f32
        };
        let (saddle, border, ground) = (count(CORN_SADDLE), count(CORN_BORDER), count(CORN_GROUND));
        assert!(saddle > 0.1 && border > 0.05 && ground > 0.2, "saddle {saddle}, border {border}, ground {ground}");
        assert_eq!(m.vertices, snake(&SnakeSpec::default()).vertices, "the same seed gives the same snake");
        let other = snake(&SnakeSpec { seed: 2, ..SnakeSpec::default() });
        assert_ne!(m.vertices, other.vertices, "another seed another snake");
        let plain = snake(&SnakeSpec { pattern: Pattern::Plain, ..SnakeSpec::default() });
        assert!(plain.vertices.iter().all(|v| v.pigment == UNTINTED));
    }
}
