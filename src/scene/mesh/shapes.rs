//! Built-in shapes with proper normals and tangents (the procedural snake is in [`crate::scene::mesh::snake`]).
//!
//! Tangent conventions (the patch's x axis): plane and cube faces along their u; disk radial (a grating patch
//! then has circular tracks, like a CD); sphere along the parallels; cylinder along its axis; snake along the
//! body, from tail to head.

use glam::Vec3;

use crate::gpu::interface::Vertex;
use crate::scene::mesh::{grid_indices, Mesh, UNTINTED};

/// The shapes a scene can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    Plane,
    Disk,
    Sphere,
    Cylinder,
    Cube,
    Snake,
    /// A horizontal square under the scene, [`GROUND_HALF`] each side of the origin at y = 0, facing up: it
    /// receives the sun's shadow and casts none.
    Ground,
}

/// Half the ground's edge at unit scale (world units): wide enough to reach the horizon of a close view.
pub const GROUND_HALF: f32 = 50.0;

impl Shape {
    /// The shape at unit size (plane and cube edges 2, disk and sphere radius 1, cylinder radius 1 and height 2,
    /// snake 4 long, ground 100 wide).
    /// Closed shapes (sphere, cube, snake) are one-sided ([`Mesh::one_sided`]); a plane, disk or open cylinder
    /// shows its back.
    pub fn build(self) -> Mesh {
        match self {
            Shape::Plane => Mesh::quad(1.0),
            Shape::Disk => disk(1.0, 96, 24),
            Shape::Sphere => Mesh::uv_sphere(1.0, 96, 48),
            Shape::Cylinder => cylinder(1.0, 2.0, 96, 16),
            Shape::Cube => Mesh { one_sided: true, front_first: true, ..cube(1.0) },
            Shape::Snake => crate::scene::mesh::snake::snake(&crate::scene::mesh::snake::SnakeSpec::default()),
            Shape::Ground => ground(GROUND_HALF),
        }
    }
}

/// A square of half-edge `half` in the y = 0 plane, normal +y, tangent along +x.
pub fn ground(half: f32) -> Mesh {
    let mut m = Mesh::quad(half);
    for v in &mut m.vertices {
        let [x, y, _] = v.position;
        v.position = [x, 0.0, -y];
        v.normal = [0.0, 1.0, 0.0];
    }
    m
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
                pigment: UNTINTED,
            });
        }
    }
    grid_indices(&mut m, rings, sectors, true);
    m.front_first = true;
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
                pigment: UNTINTED,
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
                pigment: UNTINTED,
            });
        }
        m.indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    m
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn check_outward_and_frames(m: &Mesh, centre: impl Fn(Vec3) -> Vec3, name: &str) {
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

    /// Culling back faces is safe only where every triangle's front (counter-clockwise, as the pipelines take
    /// it) faces the way its vertex normals point. Every shape but the open cylinder (whose outside hides its
    /// inside) hides nothing behind what is drawn before it, and needs no depth pre-pass.
    #[test]
    fn one_sided_shapes_wind_their_fronts_along_the_normals() {
        for shape in [Shape::Plane, Shape::Disk, Shape::Sphere, Shape::Cylinder, Shape::Cube, Shape::Snake] {
            let m = shape.build();
            assert_eq!(m.one_sided, matches!(shape, Shape::Sphere | Shape::Cube | Shape::Snake), "{shape:?}");
            assert_eq!(m.front_first, shape != Shape::Cylinder, "{shape:?}");
            if !m.one_sided {
                continue;
            }
            let mut against = 0;
            for tri in m.indices.chunks_exact(3) {
                let v: Vec<_> = tri.iter().map(|&i| &m.vertices[i as usize]).collect();
                let p: Vec<Vec3> = v.iter().map(|v| Vec3::from(v.position)).collect();
                let face = (p[1] - p[0]).cross(p[2] - p[0]);
                let normals: Vec3 = v.iter().map(|v| Vec3::from(v.normal)).sum();
                // Degenerate triangles (a pole's, a tip's) cover no pixel: their side does not matter.
                let longest = (0..3).map(|k| (p[(k + 1) % 3] - p[k]).length_squared()).fold(0.0, f32::max);
                if face.length() > 1e-3 * longest && face.dot(normals) <= 0.0 {
                    against += 1;
                }
            }
            assert_eq!(against, 0, "{shape:?}: {against} triangles face against their normals");
        }
    }
}
