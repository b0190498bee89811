//! Writing files: frames as 8-bit sRGB PNG (display-referred) and 32-bit float OpenEXR (linear,
//! scene-referred), and every file diffract writes through a temporary file and a rename.
//!
//! Temporary files (made by `tempfile`) are named `.diffract-tmp-<pid>-<random>-<name>` in the target's folder: a run killed while writing
//! (SIGKILL, a power cut) leaves one behind, and the next run that writes in that folder removes every one whose
//! process is gone; Ctrl-C and SIGTERM remove the run's own before it exits ([`remove_temporaries_and_exit`]).

use std::collections::HashSet;
use std::ffi::OsStr;
use std::io::Write as _;
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::{Error, Result};

/// The prefix of every temporary file diffract writes (then the writer's process id, random letters and the name).
pub(crate) const TEMP_PREFIX: &str = ".diffract-tmp-";
/// The most bytes of the target's name a temporary file's name repeats (names stay under the 255-byte limit).
const TEMP_NAME_BYTES: usize = 128;

/// Temporary files being written now (removed on Ctrl-C), and folders already swept of stale ones.
static WRITING: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);
static SWEPT: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);

/// Removes the temporary files being written and ends the process with status 130 (what a shell reports for
/// Ctrl-C): what the command line does on Ctrl-C and SIGTERM (`cli`, with `ctrlc`), so that an interrupted write
/// leaves no temporary file behind (without it one stays until the next run in its folder).
pub fn remove_temporaries_and_exit() -> ! {
    // The lock is held until the process ends: a write that has created its temporary file has registered it
    // (both happen under this lock), and no write can create another after this snapshot.
    let writing = WRITING.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    for f in writing.iter().flatten() {
        let _ = std::fs::remove_file(f);
    }
    // SAFETY: _exit ends the process at once, without running destructors of state other threads hold.
    unsafe { libc::_exit(130) }
}

/// Writes `bytes` to `file` through a temporary file in the same folder, flushed to disk, then renamed over it:
/// an interrupted or failed write leaves an existing file as it was.
pub(crate) fn write_atomic(file: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = file.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    sweep_stale_temporaries(dir);
    // tempfile names it uniquely (random letters after our prefix and pid: two threads writing the same file each
    // rename their own whole copy) and removes it when a write or the rename fails. The mode is what
    // `File::create` gives (0666 less the umask), not tempfile's private 0600: the file becomes the user's output.
    let target = file.file_name().map(|f| f.as_bytes()).unwrap_or_default();
    let suffix = [b"-", &target[..target.len().min(TEMP_NAME_BYTES)]].concat();
    // Created and registered under one lock: a Ctrl-C handled in between would otherwise miss the new file.
    let mut writing = WRITING.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut tmp = tempfile::Builder::new()
        .prefix(&format!("{TEMP_PREFIX}{}-", std::process::id()))
        .suffix(OsStr::from_bytes(&suffix))
        .permissions(std::fs::Permissions::from_mode(0o666))
        .tempfile_in(dir)?;
    let path = tmp.path().to_path_buf();
    writing.get_or_insert_with(HashSet::new).insert(path.clone());
    drop(writing);
    let result = tmp
        .write_all(bytes)
        .and_then(|()| tmp.as_file().sync_all())
        .and_then(|()| tmp.persist(file).map(drop).map_err(|e| e.error));
    if let Some(set) = WRITING.lock().unwrap_or_else(std::sync::PoisonError::into_inner).as_mut() {
        set.remove(&path);
    }
    result
}

/// Removes the temporary files in `dir` left by diffract processes that no longer run (once per folder and
/// process). A file whose writer still runs, or whose name is not ours, is left alone.
fn sweep_stale_temporaries(dir: &Path) {
    let key = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    let first = SWEPT.lock().map(|mut s| s.get_or_insert_with(HashSet::new).insert(key)).unwrap_or(false);
    if !first {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(rest) = name.as_bytes().strip_prefix(TEMP_PREFIX.as_bytes()) else { continue };
        let pid = rest.iter().position(|&b| b == b'-').and_then(|end| std::str::from_utf8(&rest[..end]).ok());
        let Some(pid) = pid.and_then(|p| p.parse::<libc::pid_t>().ok()).filter(|&p| p > 0) else { continue };
        if !process_runs(pid) && entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Whether a process `pid` exists (a signal 0 reaches it, or it exists but is another user's).
fn process_runs(pid: libc::pid_t) -> bool {
    if pid as u32 == std::process::id() {
        return true;
    }
    // SAFETY: kill with signal 0 only checks that the process exists; it sends nothing.
    let r = unsafe { libc::kill(pid, 0) };
    r == 0 || std::io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
}

/// Checks, before any expensive work, that `path` names a PNG in a folder that exists.
pub(crate) fn check_png_path(path: &Path) -> Result<()> {
    check_path(path, "png")
}

/// Checks, before any expensive work, that `path` names an OpenEXR file in a folder that exists.
pub(crate) fn check_exr_path(path: &Path) -> Result<()> {
    check_path(path, "exr")
}

/// Checks an output path before any work: the extension, not a folder, not an existing special file (a
/// device, a pipe), in a folder that exists. The write itself is atomic ([`write_file`]).
pub(crate) fn check_path(path: &Path, extension: &str) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref() != Some(extension) {
        return Err(Error::output(path, format!("the output must be a .{extension} file")));
    }
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(Error::output(path, "it is a folder"));
        }
        if !meta.is_file() {
            return Err(Error::output(path, "it exists and is not a regular file"));
        }
    }
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::output(path, format!("the folder {} does not exist", parent.display())));
    }
    Ok(())
}

/// Refuses, before any work, an output that is one of the run's inputs: the same file as one it reads (its device
/// and inode, whatever the names: `./`, `..`, a hard link, a symlink). Writing it would replace what the run reads
/// (a map written over its own height field). `outputs` and `inputs` are (what it is, the path given).
pub fn check_not_inputs(outputs: &[(&str, &Path)], inputs: &[(&str, &Path)]) -> Result<()> {
    use std::os::unix::fs::MetadataExt;
    let identity = |path: &Path| std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()));
    for &(flag, output) in outputs {
        // An output that does not exist yet cannot be a file the run reads.
        let Some(id) = identity(output) else { continue };
        if let Some((what, input)) = inputs.iter().find(|(_, input)| identity(input) == Some(id)) {
            return Err(Error::output(
                output,
                format!("{flag} is {what} {}, which this run reads: name another file", input.display()),
            ));
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file in the same folder, flushed to disk, then renamed over
/// it: a full disk or a failed write reports the error and leaves an existing file as it was.
pub(crate) fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic(path, bytes).map_err(|e| Error::output(path, e))
}

/// Encodes an image in memory in `format`.
fn encode(path: &Path, img: image::DynamicImage, format: image::ImageFormat) -> Result<Vec<u8>> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, format).map_err(|e| Error::output(path, e))?;
    Ok(bytes.into_inner())
}

/// Writes tightly packed RGBA8 (sRGB-encoded, top row first) as a PNG.
pub fn write_png_rgba8(path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    check_png_path(path)?;
    let img = image::RgbaImage::from_raw(width, height, rgba8.to_vec())
        .ok_or_else(|| Error::output(path, "image data does not match its size"))?;
    write_file(path, &encode(path, img.into(), image::ImageFormat::Png)?)
}

/// Writes 16-bit grey (top row first) as a PNG.
pub fn write_png_gray16(path: &Path, width: u32, height: u32, grey: Vec<u16>) -> Result<()> {
    check_png_path(path)?;
    let img = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(width, height, grey)
        .ok_or_else(|| Error::output(path, "image data does not match its size"))?;
    write_file(path, &encode(path, img.into(), image::ImageFormat::Png)?)
}

/// What a frame's values mean, written into its EXR: OpenEXR's standard `whiteLuminance` (the luminance in cd/m²
/// of RGB (1, 1, 1)) where the frame is in physical units, and a line that says so (its `comments`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameUnits {
    pub white_luminance: Option<f64>,
    pub comment: String,
}

/// Writes linear RGB (from RGBA float pixels, top row first) as an OpenEXR file with 32-bit float R, G, B.
pub fn write_exr_rgb(path: &Path, width: u32, height: u32, rgba: &[f32]) -> Result<()> {
    write_exr_rgb_in(path, width, height, rgba, &FrameUnits::default())
}

/// [`write_exr_rgb`], saying the frame's `units` in its header.
pub fn write_exr_rgb_in(path: &Path, width: u32, height: u32, rgba: &[f32], units: &FrameUnits) -> Result<()> {
    check_exr_path(path)?;
    use exr::prelude::{Encoding, Image, SpecificChannels, Vec2, WritableImage};
    let (w, h) = (width as usize, height as usize);
    if rgba.len() != 4 * w * h {
        return Err(Error::output(path, "image data does not match its size"));
    }
    // 32-bit floats, ZIP-compressed (lossless; a smooth sky shrinks severalfold): half floats would hold the
    // sun's 1.6·10⁹ cd/m² as infinity.
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let i = 4 * (y * w + x);
        (rgba[i], rgba[i + 1], rgba[i + 2])
    });
    let mut image = Image::from_encoded_channels((w, h), Encoding::SMALL_LOSSLESS, channels);
    let attributes = &mut image.layer_data.attributes;
    attributes.white_luminance = units.white_luminance.map(|l| l as f32);
    attributes.comments = (!units.comment.is_empty()).then(|| exr::prelude::Text::from(units.comment.as_str()));
    let mut bytes = std::io::Cursor::new(Vec::new());
    image.write().to_buffered(&mut bytes).map_err(|e| Error::output(path, e))?;
    write_file(path, &bytes.into_inner())
}

/// Writes linear RGB (alpha dropped) as a Radiance HDR file (RGBE: 8-bit mantissas with a shared exponent, about
/// 1 % resolution), atomically.
pub fn write_hdr_rgb(path: &Path, width: u32, height: u32, rgba: &[f32]) -> Result<()> {
    check_path(path, "hdr")?;
    write_float_rgb(path, width, height, rgba, image::ImageFormat::Hdr)
}

fn write_float_rgb(path: &Path, width: u32, height: u32, rgba: &[f32], format: image::ImageFormat) -> Result<()> {
    let rgb: Vec<f32> = rgba.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let img = image::Rgb32FImage::from_raw(width, height, rgb)
        .ok_or_else(|| Error::output(path, "image data does not match its size"))?;
    write_file(path, &encode(path, img.into(), format)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An EXR holds every f32 exactly (the sun above 10⁶ too, beyond half floats), ZIP-compressed: a smooth
    /// sky takes a fraction of its raw size (before, the encoder wrote it uncompressed).
    #[test]
    fn exr_is_lossless_and_compressed() {
        let dir = std::env::temp_dir().join(format!("diffract-exr-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let sky = crate::physics::sky::Sky::at_of_model(Default::default(), 3.0, 40.0, 0.0, 0.2).unwrap();
        let map = crate::light::environment::EnvironmentMap::of_sky_and_sun(&sky, 256, 0.2).unwrap();
        let rgba = map.to_rgba();
        let path = dir.join("sky.exr");
        write_exr_rgb(&path, map.width, map.height, &rgba).unwrap();
        let raw = (map.width * map.height * 12) as u64;
        let size = std::fs::metadata(&path).unwrap().len();
        assert!(size * 2 < raw, "{size} bytes against {raw} raw");
        let back = crate::light::environment::EnvironmentMap::load(&path).unwrap();
        assert_eq!((back.width, back.height), (map.width, map.height));
        assert!(back.rgb.iter().zip(&map.rgb).all(|(a, b)| a == b), "not bit-exact");
        assert!(map.rgb.iter().flatten().fold(0.0f32, |m, &v| m.max(v)) > 1e6, "the sun (beyond f16) is in the map");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A file written through the temporary file has the mode `File::create` gives (0666 less the umask, not
    /// tempfile's private 0600), its whole content, and no temporary file left beside it.
    #[test]
    fn atomic_write_keeps_mode_and_leaves_nothing() {
        let dir = std::env::temp_dir().join(format!("diffract-output-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let plain = dir.join("plain.png");
        std::fs::File::create(&plain).unwrap();
        let written = dir.join("frame.png");
        write_atomic(&written, b"frame bytes").unwrap();
        write_atomic(&written, b"second").unwrap();
        assert_eq!(std::fs::read(&written).unwrap(), b"second");
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&written), mode(&plain));
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| n.starts_with(TEMP_PREFIX))
            .collect();
        assert!(left.is_empty(), "{left:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
