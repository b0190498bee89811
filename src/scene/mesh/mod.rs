//! Triangle meshes with a tangent frame per vertex. The tangent orients a height-field patch on the surface:
//! its `xyz` is the patch's x axis, `w` the handedness of the bitangent (patch y = w · normal × tangent).
//!
//! - [`shapes`]: built-in shapes (plane, disk, sphere, cylinder, cube).
//! - [`snake`]: the procedural snake (domed scales in diagonal rows, head, S-curve, a corn snake's pattern).
//! - [`obj`]: Wavefront OBJ in and out (tobj), with normals computed when missing and tangents from the UVs,
//!   else from the mesh's long axis ([`Mesh::compute_tangents`]); an MTL's maps.
//! - [`maps`]: pigment and normal maps, with their mip chains.

pub mod maps;
pub mod obj;
pub mod shapes;
pub mod snake;

use glam::Vec3;

use crate::gpu::interface::Vertex;

/// A vertex pigment that leaves the material's as it is.
pub const UNTINTED: [f32; 3] = [1.0; 3];

#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    /// Every triangle turns its front (counter-clockwise) the way its normals point and its back is never seen
    /// (a closed surface): the renderer may cull back faces, which on lavapipe saves a fifth of the default
    /// snake's frame. False for loaded meshes, whose winding is not known.
    pub one_sided: bool,
    /// Its triangles come in an order in which none is hidden by one drawn after it, from wherever the renderer
    /// may look (with back faces culled where [`Self::one_sided`]): a flat or convex shape, or the snake, whose
    /// eyes come before the head they lie on and whose rows of scales come before the rows they overlap. Drawn with
    /// the depth test alone, hidden fragments then fail it before they are shaded, and the renderer leaves out its
    /// depth pre-pass (the snake's S-curve can still hide a few, which are shaded and then covered). False for
    /// loaded meshes.
    pub front_first: bool,
    /// Its pigment and normal maps, read at the vertices' UVs (none by default).
    pub maps: maps::SurfaceMaps,
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
                    pigment: UNTINTED,
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
        Self { vertices, indices, one_sided: true, front_first: true, maps: maps::SurfaceMaps::default() }
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
            pigment: UNTINTED,
        };
        Self {
            vertices: vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)],
            indices: vec![0, 1, 2, 0, 2, 3],
            one_sided: false,
            front_first: true,
            maps: maps::SurfaceMaps::default(),
        }
    }
}

impl Mesh {
    /// Area-weighted vertex normals from the triangles (for meshes that come without).
    pub fn compute_normals(&mut self) {
        let mut acc = vec![Vec3::ZERO; self.vertices.len()];
        for tri in self.indices.chunks_exact(3) {
            let p: Vec<Vec3> = tri.iter().map(|&i| Vec3::from(self.vertices[i as usize].position)).collect();
            let n = (p[1] - p[0]).cross(p[2] - p[0]);
            for &i in tri {
                acc[i as usize] += n;
            }
        }
        for (v, n) in self.vertices.iter_mut().zip(acc) {
            v.normal = n.try_normalize().unwrap_or(Vec3::Z).to_array();
        }
    }

    /// Tangents from the UVs (x follows increasing u), orthogonalised against the normals; where the UVs give
    /// none (missing or degenerate), the documented fallback: the mesh's longest bounding-box axis projected onto
    /// the tangent plane (the thesis likewise projected one global body axis; model.md §4).
    pub fn compute_tangents(&mut self, has_uvs: bool) {
        let mut tan = vec![Vec3::ZERO; self.vertices.len()];
        let mut bit = vec![Vec3::ZERO; self.vertices.len()];
        if has_uvs {
            for tri in self.indices.chunks_exact(3) {
                let v: Vec<&Vertex> = tri.iter().map(|&i| &self.vertices[i as usize]).collect();
                let (e1, e2) = (
                    Vec3::from(v[1].position) - Vec3::from(v[0].position),
                    Vec3::from(v[2].position) - Vec3::from(v[0].position),
                );
                let (du1, dv1) = (v[1].uv[0] - v[0].uv[0], v[1].uv[1] - v[0].uv[1]);
                let (du2, dv2) = (v[2].uv[0] - v[0].uv[0], v[2].uv[1] - v[0].uv[1]);
                let det = du1 * dv2 - du2 * dv1;
                if det.abs() < 1e-12 {
                    continue;
                }
                let t = (e1 * dv2 - e2 * dv1) / det;
                let b = (e2 * du1 - e1 * du2) / det;
                for &i in tri {
                    tan[i as usize] += t;
                    bit[i as usize] += b;
                }
            }
        }
        let axis = self.long_axis();
        for ((v, t), b) in self.vertices.iter_mut().zip(tan).zip(bit) {
            let n = Vec3::from(v.normal);
            let from_uv = (t - n * n.dot(t)).try_normalize();
            let (t, w) = match from_uv {
                Some(t) => (t, if n.cross(t).dot(b) < 0.0 { -1.0 } else { 1.0 }),
                None => (fallback_tangent(n, axis), 1.0),
            };
            v.tangent = [t.x, t.y, t.z, w];
        }
    }

    /// The unit axis along which the mesh's bounding box is longest.
    pub fn long_axis(&self) -> Vec3 {
        let (lo, hi) = self.bounds();
        let e = hi - lo;
        if e.x >= e.y && e.x >= e.z {
            Vec3::X
        } else if e.y >= e.z {
            Vec3::Y
        } else {
            Vec3::Z
        }
    }

    /// (min, max) corners of the bounding box.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.vertices.iter().fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), v| {
            (lo.min(Vec3::from(v.position)), hi.max(Vec3::from(v.position)))
        })
    }

    /// Appends `other` (for multi-part OBJ files and compound shapes).
    pub fn append(&mut self, other: &Mesh) {
        let base = self.vertices.len() as u32;
        self.vertices.extend_from_slice(&other.vertices);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }
}

/// `axis` projected onto the plane of `n`, or another axis where `axis` is (nearly) parallel to `n`.
pub(crate) fn fallback_tangent(n: Vec3, axis: Vec3) -> Vec3 {
    for a in [axis, Vec3::X, Vec3::Y, Vec3::Z] {
        if let Some(t) = (a - n * n.dot(a)).try_normalize() {
            if t.dot(a) > 0.2 {
                return t;
            }
        }
    }
    n.any_orthonormal_vector()
}

/// Indices of a (rows+1)×(cols+1) vertex grid; `ccw_from_row_order` picks the winding that faces outwards for
/// the generators ([`shapes`], [`snake`]).
pub(crate) fn grid_indices(m: &mut Mesh, rows: u32, cols: u32, ccw_from_row_order: bool) {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_default_vertex_is_untinted() {
        assert_eq!(Vertex::default().pigment, UNTINTED);
    }

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
