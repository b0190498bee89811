//! Built-in shapes with proper normals and tangents, and the procedural snake.
//!
//! Tangent conventions (the patch's x axis): plane and cube faces along their u; disk radial (a grating patch
//! then has circular tracks, like a CD); sphere along the parallels; cylinder along its axis; snake along the
//! body, from tail to head.

use glam::Vec3;

use super::{Mesh, Vertex};

/// The shapes a scene can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    Plane,
    Disk,
    Sphere,
    Cylinder,
    Cube,
    Snake,
}

impl Shape {
    /// The shape at unit size (plane and cube edges 2, disk and sphere radius 1, cylinder radius 1 and height 2,
    /// snake 4 long).
    pub fn build(self) -> Mesh {
        match self {
            Shape::Plane => Mesh::quad(1.0),
            Shape::Disk => disk(1.0, 96, 24),
            Shape::Sphere => Mesh::uv_sphere(1.0, 96, 48),
            Shape::Cylinder => cylinder(1.0, 2.0, 96, 16),
            Shape::Cube => cube(1.0),
            Shape::Snake => snake(&SnakeSpec::default()),
        }
    }
}

/// A disk of radius `r` in the z = 0 plane, normal +z, tangent radial.
pub fn disk(r: f32, sectors: u32, rings: u32) -> Mesh {
    let mut m = Mesh::default();
    for ring in 0..=rings {
        let rr = r * ring as f32 / rings as f32;
        for s in 0..=sectors {
            let a = s as f32 / sectors as f32 * std::f32::consts::TAU;
            let (sin, cos) = a.sin_cos();
            m.vertices.push(Vertex {
                position: [rr * cos, rr * sin, 0.0],
                normal: [0.0, 0.0, 1.0],
                tangent: [cos, sin, 0.0, 1.0],
                uv: [ring as f32 / rings as f32, s as f32 / sectors as f32],
            });
        }
    }
    grid_indices(&mut m, rings, sectors, true);
    m
}

/// A cylinder of radius `r` and height `h` around the y axis, open ends, tangent along the axis.
pub fn cylinder(r: f32, h: f32, sectors: u32, rows: u32) -> Mesh {
    let mut m = Mesh::default();
    for row in 0..=rows {
        let y = h * (row as f32 / rows as f32 - 0.5);
        for s in 0..=sectors {
            let a = s as f32 / sectors as f32 * std::f32::consts::TAU;
            let n = Vec3::new(a.sin(), 0.0, a.cos());
            m.vertices.push(Vertex {
                position: (n * r + Vec3::Y * y).to_array(),
                normal: n.to_array(),
                tangent: [0.0, 1.0, 0.0, 1.0],
                uv: [row as f32 / rows as f32, s as f32 / sectors as f32],
            });
        }
    }
    grid_indices(&mut m, rows, sectors, false);
    m
}

/// A cube of half-size `half`: six faces with their own normals; tangents along each face's u.
pub fn cube(half: f32) -> Mesh {
    let mut m = Mesh::default();
    for (n, u) in [
        (Vec3::Z, Vec3::X),
        (-Vec3::Z, -Vec3::X),
        (Vec3::X, -Vec3::Z),
        (-Vec3::X, Vec3::Z),
        (Vec3::Y, Vec3::X),
        (-Vec3::Y, Vec3::X),
    ] {
        let v = n.cross(u);
        let base = m.vertices.len() as u32;
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            m.vertices.push(Vertex {
                position: ((n + u * a + v * b) * half).to_array(),
                normal: n.to_array(),
                tangent: [u.x, u.y, u.z, 1.0],
                uv: [0.5 * (a + 1.0), 0.5 * (1.0 - b)],
            });
        }
        m.indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    m
}

/// Indices of a (rows+1)×(cols+1) vertex grid; `ccw_from_row_order` picks the winding that faces outwards for
/// the generators above.
fn grid_indices(m: &mut Mesh, rows: u32, cols: u32, ccw_from_row_order: bool) {
    let stride = cols + 1;
    for r in 0..rows {
        for c in 0..cols {
            let a = r * stride + c;
            let b = a + stride;
            if ccw_from_row_order {
                m.indices.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
            } else {
                m.indices.extend_from_slice(&[a, a + 1, b, a + 1, b + 1, b]);
            }
        }
    }
}

/// The procedural snake: a tapering tube along a sinuous spine lying on the ground (y = 0), tail at −x.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnakeSpec {
    /// Spine length (along x before the waves).
    pub length: f32,
    /// Body radius at its widest.
    pub radius: f32,
    /// Number of S-bends along the body.
    pub waves: f32,
    /// Sideways amplitude of the bends.
    pub amplitude: f32,
    /// Rings along the body and vertices around it (of the smooth body; scales use their own grid).
    pub segments: u32,
    pub sides: u32,
    /// Flat scales: rows along the body and scales around it (0 rows: a smooth body).
    pub scale_rows: u32,
    pub scales_around: u32,
    /// Each scale rises towards its free, tail-side edge by this much (scales overlap like roof tiles), so its
    /// normal leans towards the head, degrees.
    pub scale_tilt_deg: f32,
    /// And is turned about the body's axis by up to this much, at random, degrees.
    pub scale_jitter_deg: f32,
    pub seed: u64,
}

impl Default for SnakeSpec {
    fn default() -> Self {
        Self {
            length: 4.0,
            radius: 0.13,
            waves: 1.4,
            amplitude: 0.32,
            segments: 360,
            sides: 40,
            scale_rows: 110,
            scales_around: 20,
            scale_tilt_deg: 8.0,
            scale_jitter_deg: 6.0,
            seed: 1,
        }
    }
}

/// Radius profile along the body, t ∈ [0, 1] from tail to head: a long taper to the tail tip, a slight neck,
/// a rounded head.
fn body_radius(t: f32) -> f32 {
    let tail = (t / 0.45).min(1.0).powf(0.75);
    let neck = 1.0 - 0.25 * (-((t - 0.86) / 0.035).powi(2)).exp();
    let head = if t > 0.93 { (1.0 - ((t - 0.93) / 0.07).powi(2)).max(0.0).sqrt() } else { 1.0 };
    tail * neck * head
}

/// The spine point at t (tail 0 to head 1); the bends fade towards the head so it points forwards.
fn spine(spec: &SnakeSpec, t: f32) -> Vec3 {
    let fade = 1.0 - 0.6 * t;
    let z = spec.amplitude * fade * (std::f32::consts::TAU * spec.waves * t).sin();
    Vec3::new((t - 0.5) * spec.length, 0.0, z)
}

/// The cross-section is flattened underneath like a real snake's belly.
const FLATTEN: f32 = 0.8;

/// The smooth body's surface point, normal and along-body direction at t (tail 0 to head 1) and angle a.
fn body_surface(spec: &SnakeSpec, t: f32, a: f32) -> (Vec3, Vec3, Vec3) {
    let dt = 1.0 / spec.segments.max(2) as f32;
    let c = spine(spec, t);
    let ahead = spine(spec, (t + dt).min(1.0));
    let behind = spine(spec, (t - dt).max(0.0));
    let along = (ahead - behind).normalize();
    let side = along.cross(Vec3::Y).normalize();
    let up = side.cross(along);
    let r = spec.radius * body_radius(t);
    // The taper tilts the normal towards the tail where the radius grows.
    let slope =
        spec.radius * (body_radius((t + dt).min(1.0)) - body_radius((t - dt).max(0.0))) / (ahead - behind).length();
    let (sin, cos) = a.sin_cos();
    let position = c + (side * cos + up * (FLATTEN * sin)) * r + Vec3::Y * (FLATTEN * spec.radius);
    let around = (side * cos + up * (sin / FLATTEN)).normalize();
    let normal = (around - along * slope).normalize();
    (position, normal, along)
}

/// Builds the snake; tangents run along the body (tail to head), u = t along the body, v around it. With
/// `scale_rows > 0` the body is a mosaic of flat scales, each with one normal (leaning towards the tail, with a
/// random wobble): a flat scale carries one grating orientation over many pixels, as on a real snake.
pub fn snake(spec: &SnakeSpec) -> Mesh {
    if spec.scale_rows > 0 && spec.scales_around > 0 {
        return scaled_snake(spec);
    }
    let mut m = Mesh::default();
    for i in 0..=spec.segments {
        let t = i as f32 / spec.segments as f32;
        for s in 0..=spec.sides {
            let v = s as f32 / spec.sides as f32;
            let (position, normal, along) = body_surface(spec, t, v * std::f32::consts::TAU);
            let tangent = (along - normal * normal.dot(along)).normalize();
            m.vertices.push(Vertex {
                position: position.to_array(),
                normal: normal.to_array(),
                tangent: [tangent.x, tangent.y, tangent.z, 1.0],
                uv: [t, v],
            });
        }
    }
    grid_indices(&mut m, spec.segments, spec.sides, true);
    m
}

/// The mosaic of flat scales, overlapping like roof tiles: each is attached along its head-side edge, reaches
/// back over the scale behind it by `SCALE_OVERLAP` of a row, and its free (tail-side) edge is lifted so that the
/// scale rises by `scale_tilt_deg`: its normal leans towards the head. Rows are staggered by half a scale and
/// scales widened by `SCALE_WIDEN` so that no gap shows. Each scale has one normal (from its corners, then a
/// random turn about the body's axis) and one tangent.
fn scaled_snake(spec: &SnakeSpec) -> Mesh {
    const SCALE_OVERLAP: f32 = 0.45;
    const SCALE_WIDEN: f32 = 0.12;
    let mut m = Mesh::default();
    let mut rng = spec.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut random = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f32 / (1u64 << 53) as f32 * 2.0 - 1.0
    };
    let (rows, around) = (spec.scale_rows, spec.scales_around);
    let row = 1.0 / rows as f32;
    let tilt = spec.scale_tilt_deg.to_radians().tan();
    for i in 0..rows {
        let t1 = (i + 1) as f32 * row;
        let t0 = (i as f32 - SCALE_OVERLAP) * row;
        let stagger = if i % 2 == 0 { 0.0 } else { 0.5 };
        for j in 0..around {
            let v0 = (j as f32 + stagger - SCALE_WIDEN) / around as f32;
            let v1 = (j as f32 + stagger + 1.0 + SCALE_WIDEN) / around as f32;
            // The attached edge lies on the body; the free edge is lifted along the body's normal.
            let corner = |t: f32, v: f32, lifted: bool| {
                let (p, n, _) = body_surface(spec, t.clamp(0.0, 1.0), v * std::f32::consts::TAU);
                let (p_front, _, _) = body_surface(spec, t1.clamp(0.0, 1.0), v * std::f32::consts::TAU);
                if lifted {
                    p + n * (p_front - p).length() * tilt
                } else {
                    p
                }
            };
            let c = [corner(t0, v0, true), corner(t1, v0, false), corner(t1, v1, false), corner(t0, v1, true)];
            let geometric = (c[1] - c[0]).cross(c[3] - c[0]) + (c[3] - c[2]).cross(c[1] - c[2]);
            let Some(n) = geometric.try_normalize() else { continue };
            let along = (c[1] + c[2] - c[0] - c[3]).normalize();
            // The wobble turns the scale about the body's axis: each scale sits a little differently around the
            // body, which changes the colour it sends to a viewer but not the plane it diffracts in.
            let normal =
                (glam::Quat::from_axis_angle(along, spec.scale_jitter_deg.to_radians() * random()) * n).normalize();
            let tangent = (along - normal * normal.dot(along)).normalize();
            let base = m.vertices.len() as u32;
            for (p, (t, v)) in c.iter().zip([(t0, v0), (t1, v0), (t1, v1), (t0, v1)]) {
                m.vertices.push(Vertex {
                    position: p.to_array(),
                    normal: normal.to_array(),
                    tangent: [tangent.x, tangent.y, tangent.z, 1.0],
                    uv: [t.clamp(0.0, 1.0), v.rem_euclid(1.0)],
                });
            }
            m.indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_outward_and_frames(m: &Mesh, centre: impl Fn(Vec3) -> Vec3, name: &str) {
        let mut facing = 0;
        let mut total = 0;
        for tri in m.indices.chunks(3) {
            let p: Vec<Vec3> = tri.iter().map(|&i| Vec3::from(m.vertices[i as usize].position)).collect();
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            if n.length() < 1e-9 {
                continue;
            }
            let mid = (p[0] + p[1] + p[2]) / 3.0;
            total += 1;
            let vn = Vec3::from(m.vertices[tri[0] as usize].normal);
            if n.dot(vn) > 0.0 && n.dot(mid - centre(mid)) >= -1e-6 {
                facing += 1;
            }
        }
        assert!(
            facing as f32 > 0.99 * total as f32,
            "{name}: {facing}/{total} triangles wind with their normals, outwards"
        );
        for v in &m.vertices {
            let (n, t) = (Vec3::from(v.normal), Vec3::new(v.tangent[0], v.tangent[1], v.tangent[2]));
            assert!((n.length() - 1.0).abs() < 1e-4 && (t.length() - 1.0).abs() < 1e-4, "{name}: unit frame");
            assert!(n.dot(t).abs() < 1e-4, "{name}: tangent ⟂ normal");
        }
    }

    #[test]
    fn shapes_face_outwards_with_orthonormal_frames() {
        check_outward_and_frames(&Shape::Sphere.build(), |_| Vec3::ZERO, "sphere");
        check_outward_and_frames(&Shape::Cylinder.build(), |p| Vec3::new(0.0, p.y, 0.0), "cylinder");
        check_outward_and_frames(&Shape::Cube.build(), |_| Vec3::ZERO, "cube");
        check_outward_and_frames(&Shape::Disk.build(), |p| p - Vec3::Z, "disk");
        check_outward_and_frames(&Shape::Plane.build(), |p| p - Vec3::Z, "plane");
    }

    #[test]
    fn snake_tangents_run_along_the_body_and_normals_outwards() {
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
    fn scales_are_flat_tilted_and_face_outwards() {
        let spec = SnakeSpec::default();
        let m = snake(&spec);
        assert_eq!(m.vertices.len() as u32, 4 * spec.scale_rows * spec.scales_around);
        check_outward_and_frames(&m, |p| p, "scaled snake (winding only)");
        let smooth = SnakeSpec { scale_rows: 0, ..spec };
        let mut leans = Vec::new();
        for quad in m.vertices.chunks(4) {
            assert!(
                quad.iter().all(|v| v.normal == quad[0].normal && v.tangent == quad[0].tangent),
                "one frame per scale"
            );
            let t = 0.5 * (quad[0].uv[0] + quad[1].uv[0]);
            if (0.1..0.8).contains(&t) {
                let (_, n, along) = body_surface(&smooth, t, 0.0);
                let _ = n;
                leans.push(-Vec3::from(quad[0].normal).dot(along));
            }
        }
        let mean = leans.iter().sum::<f32>() / leans.len() as f32;
        assert!((mean + spec.scale_tilt_deg.to_radians().sin()).abs() < 0.03, "scales lean towards the head: {mean}");
    }
}
