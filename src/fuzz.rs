//! The entry points of the fuzz targets (`fuzz/fuzz_targets/`, run with cargo-fuzz) and of their corpus replay
//! in `cargo test` (`tests/fuzz_corpus.rs`): each takes arbitrary bytes as the content of a user's file and must
//! come back — with a value or a user error — without a panic, a hang or an unbounded allocation.

use std::path::Path;

use crate::physics::formats::gsf;
use crate::physics::formats::png::PngScale;

/// A Gwyddion Simple Field height field.
pub fn gsf(bytes: &[u8]) {
    if let Ok(hf) = gsf::parse(Path::new("fuzz.gsf"), bytes) {
        assert!(hf.heights_um.iter().all(|h| h.is_finite()) && hf.dx_um > 0.0 && hf.dy_um > 0.0);
    }
}

/// A greyscale PNG height field, at the Elaphe scan's units.
pub fn png_heightfield(bytes: &[u8]) {
    let scale = PngScale { pixel_size_um: 0.065, height_um: 0.375 };
    if let Ok(hf) = crate::physics::formats::png::from_bytes(Path::new("fuzz.png"), bytes, scale) {
        assert!(hf.heights_um.iter().all(|h| (0.0..=0.375).contains(h)));
    }
}

/// A Wavefront OBJ mesh (tobj, then normals and tangents).
pub fn obj(bytes: &[u8]) {
    if let Ok(mesh) = crate::scene::mesh::obj::parse(Path::new("fuzz.obj"), bytes) {
        let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
        for v in &mesh.vertices {
            assert!(finite(&v.position) && finite(&v.normal) && finite(&v.tangent), "{v:?}");
        }
        assert!(mesh.indices.iter().all(|&i| (i as usize) < mesh.vertices.len()));
    }
}

/// A scene file (TOML, then every check; relative paths resolve in a folder that does not exist).
pub fn scene(bytes: &[u8]) {
    let Ok(text) = std::str::from_utf8(bytes) else { return };
    let _ = crate::scene::Scene::parse(text, "fuzz.toml", Path::new("/nonexistent/diffract-fuzz"));
}
