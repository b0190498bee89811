//! Triangle meshes with a tangent frame per vertex. The tangent orients a height-field patch on the surface:
//! its `xyz` is the patch's x axis, `w` the handedness of the bitangent (patch y = w · normal × tangent).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// One vertex as the shaders read it (binding 0, interleaved).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub tangent: [f32; 4],
    pub uv: [f32; 2],
}
const _: () = assert!(std::mem::size_of::<Vertex>() == 48);

#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    /// A UV sphere of the given radius; the tangent runs along the parallels (increasing longitude).
    pub fn uv_sphere(radius: f32, segments: u32, rings: u32) -> Self {
        let mut vertices = Vec::with_capacity(((segments + 1) * (rings + 1)) as usize);
        for r in 0..=rings {
            let v = r as f32 / rings as f32;
            let theta = v * std::f32::consts::PI;
            for s in 0..=segments {
                let u = s as f32 / segments as f32;
                let phi = u * std::f32::consts::TAU;
                let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
                let t = Vec3::new(-phi.sin(), 0.0, -phi.cos());
                vertices.push(Vertex {
                    position: (n * radius).to_array(),
                    normal: n.to_array(),
                    tangent: [t.x, t.y, t.z, 1.0],
                    uv: [u, v],
                });
            }
        }
        let mut indices = Vec::with_capacity((segments * rings * 6) as usize);
        let row = segments + 1;
        for r in 0..rings {
            for s in 0..segments {
                let a = r * row + s;
                let b = a + row;
                indices.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
            }
        }
        Self { vertices, indices }
    }
}

impl Mesh {
    /// A square of half-size `half` in the z = 0 plane, normal +z, tangent +x, UVs over [0, 1]².
    pub fn quad(half: f32) -> Self {
        let corner = |x: f32, y: f32| Vertex {
            position: [x * half, y * half, 0.0],
            normal: [0.0, 0.0, 1.0],
            tangent: [1.0, 0.0, 0.0, 1.0],
            uv: [0.5 * (x + 1.0), 0.5 * (1.0 - y)],
        };
        Self {
            vertices: vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)],
            indices: vec![0, 1, 2, 0, 2, 3],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_triangles_face_outwards() {
        let m = Mesh::uv_sphere(1.0, 16, 8);
        for tri in m.indices.chunks(3) {
            let p: Vec<Vec3> = tri.iter().map(|&i| Vec3::from(m.vertices[i as usize].position)).collect();
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            if n.length() < 1e-6 {
                continue; // degenerate triangles at the poles
            }
            let centre = (p[0] + p[1] + p[2]) / 3.0;
            assert!(n.dot(centre) > 0.0, "counter-clockwise triangles must face outwards");
        }
    }

    #[test]
    fn tangents_are_unit_and_perpendicular_to_normals() {
        let m = Mesh::uv_sphere(1.0, 16, 8);
        for v in &m.vertices {
            let t = Vec3::new(v.tangent[0], v.tangent[1], v.tangent[2]);
            assert!((t.length() - 1.0).abs() < 1e-5);
            assert!(t.dot(Vec3::from(v.normal)).abs() < 1e-5);
        }
    }
}
