//! Wavefront OBJ through `tobj`: every model of the file merged into one mesh, triangulated; normals computed
//! when the file has none, tangents from the UVs (else the long-axis fallback of [`Mesh::compute_tangents`]); the
//! maps its MTL names (`map_Kd`, `norm` or `map_Bump`).

use std::fmt::Write as _;
use std::path::Path;

use crate::error::{Error, Result};
use crate::gpu::interface::Vertex;
use crate::scene::mesh::maps::{MapKind, SurfaceMaps, Texture};
use crate::scene::mesh::Mesh;

/// The most vertices a mesh may have (a guard against hostile files; a detailed snake scan has ~10⁵).
pub const MAX_VERTICES: usize = 20_000_000;

/// Loads an OBJ file.
pub fn load(path: &Path) -> Result<Mesh> {
    let bytes = crate::io::input::read(path, crate::io::input::MAX_OBJ_BYTES, "mesh")?;
    parse(path, &bytes)
}

/// Parses the bytes of an OBJ file (`path` names it in messages).
pub fn parse(path: &Path, bytes: &[u8]) -> Result<Mesh> {
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true };
    // A `mtllib` is read beside the file for its maps (a scene names its own material for everything else).
    let dir = path.parent().unwrap_or(Path::new("."));
    let (models, materials) = tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &options, |name| {
        let bytes = crate::io::input::read(&dir.join(name), MAX_MTL_BYTES, "material library");
        let bytes = bytes.map_err(|e| {
            log::warn!("{}: its mtllib {}: {e}; its maps are not read", path.display(), name.display());
            tobj::LoadError::OpenFileFailed
        })?;
        tobj::load_mtl_buf(&mut std::io::Cursor::new(bytes))
    })
    .map_err(|e| Error::input(path, format!("not a readable OBJ: {e}")))?;
    let mut mesh = Mesh { maps: mtl_maps(path, &models, &materials.unwrap_or_default())?, ..Mesh::default() };
    let (mut has_normals, mut has_uvs) = (true, true);
    for model in &models {
        let m = &model.mesh;
        let count = m.positions.len() / 3;
        if mesh.vertices.len() + count > MAX_VERTICES {
            return Err(Error::input(path, format!("more than {MAX_VERTICES} vertices")));
        }
        has_normals &= m.normals.len() == m.positions.len();
        has_uvs &= m.texcoords.len() / 2 == count;
        let mut part = Mesh::default();
        for i in 0..count {
            let p = [m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]];
            if p.iter().any(|c| !c.is_finite()) {
                return Err(Error::input(path, format!("vertex {} of {:?} is not finite", i + 1, model.name)));
            }
            let normal = if m.normals.len() == m.positions.len() {
                [m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]]
            } else {
                [0.0, 0.0, 1.0]
            };
            let uv =
                if m.texcoords.len() / 2 == count { [m.texcoords[2 * i], m.texcoords[2 * i + 1]] } else { [0.0; 2] };
            // Vertex colours (`v x y z r g b`, as MeshLab writes them) tint the material's pigment.
            let pigment = match m.vertex_color.get(3 * i..3 * i + 3) {
                Some(&[r, g, b]) if [r, g, b].iter().all(|c| c.is_finite() && *c >= 0.0) => [r, g, b],
                Some(_) => {
                    return Err(Error::input(
                        path,
                        format!("vertex {} of {:?}: its colour is not three non-negative numbers", i + 1, model.name),
                    ))
                }
                None => crate::scene::mesh::UNTINTED,
            };
            part.vertices.push(Vertex { position: p, normal, tangent: [1.0, 0.0, 0.0, 1.0], uv, pigment });
        }
        part.indices = m.indices.clone();
        if part.indices.iter().any(|&i| i as usize >= count) {
            return Err(Error::input(path, format!("a face of {:?} refers to a missing vertex", model.name)));
        }
        mesh.append(&part);
    }
    if mesh.indices.is_empty() {
        return Err(Error::input(path, "the OBJ has no faces"));
    }
    if !has_normals {
        mesh.compute_normals();
    } else {
        for v in &mut mesh.vertices {
            let n = glam::Vec3::from(v.normal);
            v.normal = n.try_normalize().unwrap_or(glam::Vec3::Z).to_array();
        }
    }
    mesh.compute_tangents(has_uvs);
    Ok(mesh)
}

/// The most bytes an MTL file may take.
pub const MAX_MTL_BYTES: u64 = 16 << 20;

/// The maps of the MTL materials `models` use (`map_Kd`: the pigment map; `norm`, or `map_Bump`/`bump` as
/// exporters write a normal map there: the normal map), read beside `path`, rows turned for the OBJ's v (up the
/// image). One object takes one set: where the models use several, the first is taken and a warning says so.
fn mtl_maps(path: &Path, models: &[tobj::Model], materials: &[tobj::Material]) -> Result<SurfaceMaps> {
    let mut used: Vec<(Option<String>, Option<String>)> = Vec::new();
    for id in models.iter().filter_map(|m| m.mesh.material_id) {
        let Some(m) = materials.get(id) else { continue };
        let normal = m.unknown_param.get("norm").cloned().or_else(|| m.normal_texture.clone());
        let maps = (m.diffuse_texture.clone(), normal);
        if (maps.0.is_some() || maps.1.is_some()) && !used.contains(&maps) {
            used.push(maps);
        }
    }
    let Some((pigment, normal)) = used.first() else { return Ok(SurfaceMaps::default()) };
    if used.len() > 1 {
        log::warn!("{}: its materials name {} sets of maps; one object takes the first", path.display(), used.len());
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let load = |name: &Option<String>, kind| {
        name.as_deref()
            .map(|n| Texture::load(&dir.join(map_file(n)), kind).map(std::sync::Arc::new))
            .transpose()
            .map_err(|e| Error::input(path, format!("its MTL's map: {e}")))
    };
    Ok(SurfaceMaps { pigment: load(pigment, MapKind::Pigment)?, normal: load(normal, MapKind::Normal)? }.flipped())
}

/// A map statement's file: the last word where options (`-bm 0.5 file.png`) come first.
fn map_file(statement: &str) -> &str {
    match statement.trim() {
        s if s.starts_with('-') => s.split_whitespace().last().unwrap_or(s),
        s => s,
    }
}

/// Writes `mesh` as OBJ with positions, UVs and normals, and vertex colours (`v x y z r g b`) where a vertex's
/// pigment is tinted (OBJ has no tangents: a reader derives them from the UVs, which for diffract's shapes run
/// along the tangent).
pub fn save(path: &Path, mesh: &Mesh, comment: &str) -> Result<()> {
    let mut text = String::with_capacity(mesh.vertices.len() * 96);
    writeln!(text, "# {}", comment.replace('\n', " ")).unwrap();
    let tinted = mesh.vertices.iter().any(|v| v.pigment != crate::scene::mesh::UNTINTED);
    for v in &mesh.vertices {
        let [x, y, z] = v.position;
        if tinted {
            let [r, g, b] = v.pigment;
            writeln!(text, "v {x} {y} {z} {r} {g} {b}").unwrap();
        } else {
            writeln!(text, "v {x} {y} {z}").unwrap();
        }
    }
    for v in &mesh.vertices {
        writeln!(text, "vt {} {}", v.uv[0], v.uv[1]).unwrap();
    }
    for v in &mesh.vertices {
        writeln!(text, "vn {} {} {}", v.normal[0], v.normal[1], v.normal[2]).unwrap();
    }
    for tri in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [tri[0] + 1, tri[1] + 1, tri[2] + 1];
        writeln!(text, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}").unwrap();
    }
    crate::io::output::write_file(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::snake::{snake, SnakeSpec};

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("diffract-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn snake_round_trips_with_tangents_from_uvs() {
        let spec = SnakeSpec { scale_rows: 0, segments: 60, sides: 12, ..SnakeSpec::default() };
        let m = snake(&spec);
        let p = scratch("snake.obj");
        save(&p, &m, "test").unwrap();
        let back = load(&p).unwrap();
        assert_eq!(back.indices.len(), m.indices.len());
        let mut aligned = 0;
        for (a, b) in m.vertices.iter().zip(&back.vertices) {
            let (ta, tb) = (glam::Vec3::from_slice(&a.tangent[..3]), glam::Vec3::from_slice(&b.tangent[..3]));
            if ta.dot(tb) > 0.9 {
                aligned += 1;
            }
        }
        assert!(
            aligned as f32 > 0.9 * m.vertices.len() as f32,
            "{aligned} of {} tangents survive the round trip",
            m.vertices.len()
        );
    }

    #[test]
    fn the_corn_pattern_round_trips_as_vertex_colours() {
        let spec = SnakeSpec { scale_rows: 12, scales_around: 6, ..SnakeSpec::default() };
        let m = snake(&spec);
        assert!(m.vertices.iter().any(|v| v.pigment != crate::scene::mesh::UNTINTED), "the snake is patterned");
        let p = scratch("corn.obj");
        save(&p, &m, "test").unwrap();
        let back = load(&p).unwrap();
        // tobj (single_index) numbers the loaded vertices in the order the faces first use them, which the head's
        // grid of rings does not follow: each loaded vertex carries the colour of a saved one at its position and uv
        // (an eye's pupil edge is two rings at one place, black inside and coloured outside).
        let close = |x: &[f32], y: &[f32]| x.iter().zip(y).all(|(a, b)| (a - b).abs() < 1e-5);
        for b in &back.vertices {
            let twin = m
                .vertices
                .iter()
                .any(|a| close(&a.position, &b.position) && close(&a.uv, &b.uv) && close(&a.pigment, &b.pigment));
            assert!(twin, "{b:?} has no saved twin");
        }
        std::fs::write(&p, "v 0 0 0 1 -1 0\nv 1 0 0 1 1 1\nv 0 1 0 1 1 1\nf 1 2 3\n").unwrap();
        assert!(load(&p).unwrap_err().to_string().contains("colour"), "a negative colour is refused");
    }

    #[test]
    fn an_mtls_maps_come_with_the_mesh_rows_turned_for_its_v() {
        let obj = scratch("mtl.obj");
        let dir = obj.parent().unwrap();
        // Top row red, bottom row blue (PNG rows run top to bottom).
        let png = image::RgbImage::from_fn(2, 2, |_, y| image::Rgb(if y == 0 { [255, 0, 0] } else { [0, 0, 255] }));
        png.save(dir.join("mtl-kd.png")).unwrap();
        image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 255])).save(dir.join("mtl-n.png")).unwrap();
        std::fs::write(dir.join("mtl.mtl"), "newmtl a\nmap_Kd mtl-kd.png\nnorm -bm 1 mtl-n.png\n").unwrap();
        let text = "mtllib mtl.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
        std::fs::write(&obj, text).unwrap();
        let mesh = load(&obj).unwrap();
        let pigment = mesh.maps.pigment.expect("map_Kd read");
        // v = 0 is the image's bottom row in an OBJ: the uploaded rows start there.
        assert_eq!(pigment.levels[0][0], [0, 0, 255, 255]);
        assert_eq!(mesh.maps.normal.expect("norm read").levels[0][0], [128, 128, 255, 255]);
        // Without its MTL the mesh still loads, without maps.
        std::fs::remove_file(dir.join("mtl.mtl")).unwrap();
        assert!(load(&obj).unwrap().maps.is_empty());
    }

    #[test]
    fn missing_normals_and_uvs_are_derived() {
        let p = scratch("tri.obj");
        std::fs::write(&p, "v 0 0 0\nv 4 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let m = load(&p).unwrap();
        for v in &m.vertices {
            assert_eq!(v.normal, [0.0, 0.0, 1.0]);
            assert_eq!(&v.tangent[..3], &[1.0, 0.0, 0.0], "fallback: the long axis (x) in the tangent plane");
        }
    }

    #[test]
    fn hostile_objs_are_refused() {
        let p = scratch("bad.obj");
        std::fs::write(&p, "v 0 0 0\nf 1 2 3\n").unwrap();
        assert!(load(&p).is_err());
        std::fs::write(&p, "v 0 0 0\n").unwrap();
        assert!(load(&p).unwrap_err().to_string().contains("no faces"));
        assert!(load(Path::new("/no/such.obj")).is_err());
    }
}
