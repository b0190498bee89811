//! Reading the user's input files (scenes, meshes, height fields) with bounds: only regular files (a FIFO
//! would block the open, a device never ends), and never more bytes than a file of its kind can sensibly have,
//! checked before anything is allocated.

use std::io::Read as _;
use std::path::Path;

use crate::error::{Error, Result};

/// The largest scene file read (a scene is a page of TOML).
pub const MAX_SCENE_BYTES: u64 = 1 << 20;
/// The largest OBJ file read (about the size of the OBJ reader's vertex limit, `mesh::obj::MAX_VERTICES`, as text).
pub const MAX_OBJ_BYTES: u64 = 2 << 30;

/// Checks that `path` is a regular file and returns its length in bytes.
pub fn check_file(path: &Path) -> Result<u64> {
    let meta = std::fs::metadata(path).map_err(|e| Error::input(path, format!("cannot open: {e}")))?;
    if meta.is_dir() {
        return Err(Error::input(path, "is a folder, not a file"));
    }
    if !meta.is_file() {
        return Err(Error::input(path, "is not a regular file (a device, a pipe or a socket)"));
    }
    Ok(meta.len())
}

/// Reads a regular file of at most `limit` bytes (`what` names its kind in the message).
pub fn read(path: &Path, limit: u64, what: &str) -> Result<Vec<u8>> {
    let len = check_file(path)?;
    let too_big = |len: u64| {
        Error::input(path, format!("is {} MiB; {what} files may have at most {} MiB", len >> 20, limit >> 20))
    };
    if len > limit {
        return Err(too_big(len));
    }
    let file = std::fs::File::open(path).map_err(|e| Error::input(path, format!("cannot open: {e}")))?;
    let mut bytes = Vec::with_capacity(len as usize);
    // One byte more than allowed tells a file that grew since it was measured.
    file.take(limit + 1).read_to_end(&mut bytes).map_err(|e| Error::input(path, format!("cannot read: {e}")))?;
    if bytes.len() as u64 > limit {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_files_and_oversized_files_are_refused() {
        assert!(check_file(Path::new("/dev/zero")).unwrap_err().to_string().contains("not a regular file"));
        assert!(check_file(Path::new("/")).unwrap_err().to_string().contains("folder"));
        let dir = std::env::temp_dir().join(format!("diffract-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("big.toml");
        std::fs::write(&f, vec![b'#'; 2048]).unwrap();
        assert!(read(&f, 1024, "scene").unwrap_err().to_string().contains("at most"));
        assert_eq!(read(&f, 4096, "scene").unwrap().len(), 2048);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
