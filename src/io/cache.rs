//! The on-disk cache of expensive results (the profiler's exact references, the baked tables and their estimates):
//! where it lives (`$DIFFRACT_CACHE` when set — empty or `off`: none —, else `$XDG_CACHE_HOME/diffract`, else
//! `~/.cache/diffract`), the stable hash that names its files, and writes that never leave half a file
//! ([`crate::io::output::write_atomic`]).
//!
//! Every entry ([`store`], [`load`]) carries its kind, the versions of diffract and of the kind that wrote it, the
//! plan it was computed for, its length and a CRC-32 of all of it. A read opens the file without blocking, accepts
//! only a regular file of the length its header says (and at most what the caller expects), and checks every field
//! and the checksum before the bytes are used; anything else is recomputed with a note. The cache costs time when
//! it fails, never correctness.

use std::io::Read;
use std::path::{Path, PathBuf};

/// The default cache folder (see the module documentation); None where caching is off or there is no home.
pub fn default_dir() -> Option<PathBuf> {
    if let Some(v) = std::env::var_os("DIFFRACT_CACHE") {
        let dir = PathBuf::from(&v);
        // A file, a device (`/dev/null`) or a pipe is no folder to cache in: said once, and nothing is cached.
        if dir.exists() && !dir.is_dir() {
            static SAID: std::sync::Once = std::sync::Once::new();
            SAID.call_once(|| {
                log::warn!(
                    "DIFFRACT_CACHE={} is not a folder: nothing is cached (name a folder, or off)",
                    dir.display()
                )
            });
            return None;
        }
        return (!(v.is_empty() || v == "off")).then_some(dir);
    }
    std::env::var_os("XDG_CACHE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .map(|d| d.join("diffract"))
}

const ENTRY_MAGIC: &[u8; 8] = b"DFRCACHE";
/// The layout of an entry's header (bumped if the header itself changes).
const ENTRY_FORMAT: u32 = 1;
/// The version of diffract written into every entry.
pub const PRODUCER: &str = concat!("diffract ", env!("CARGO_PKG_VERSION"));

/// What an entry is: its kind (also its file name's prefix), the version of the kind's definition, and its plan.
pub struct Stamp {
    pub kind: &'static str,
    /// What the entry is, for the note a rejected entry prints ("baked table", …).
    pub what: &'static str,
    pub version: u64,
    pub plan: Vec<u8>,
}

impl Stamp {
    /// The entry's file under `dir`: the kind and a hash of the version and plan.
    pub fn file(&self, dir: &Path) -> PathBuf {
        let mut h = KeyHash::default();
        h.u64(self.version);
        h.bytes(&self.plan);
        dir.join(format!("{}-{:016x}.bin", self.kind, h.finish()))
    }

    /// The header of this stamp's entry for a payload of `len` bytes, without the checksum.
    fn header(&self, len: u64) -> Vec<u8> {
        let mut out = Vec::with_capacity(64 + self.plan.len());
        out.extend_from_slice(ENTRY_MAGIC);
        out.extend_from_slice(&ENTRY_FORMAT.to_le_bytes());
        for field in [self.kind.as_bytes(), PRODUCER.as_bytes()] {
            out.extend_from_slice(&(field.len() as u64).to_le_bytes());
            out.extend_from_slice(field);
        }
        out.extend_from_slice(&self.version.to_le_bytes());
        out.extend_from_slice(&(self.plan.len() as u64).to_le_bytes());
        out.extend_from_slice(&self.plan);
        out.extend_from_slice(&len.to_le_bytes());
        out
    }
}

/// Bytes of everything a cached result depends on, in a fixed order (what [`Stamp::plan`] holds).
#[derive(Default)]
pub struct PlanBytes(pub Vec<u8>);

impl PlanBytes {
    pub fn u64(&mut self, v: u64) -> &mut Self {
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }

    pub fn f64(&mut self, v: f64) -> &mut Self {
        self.u64(v.to_bits())
    }
}

/// Writes `payload` as the entry `stamp` names under `dir` (atomically: [`crate::io::output::write_atomic`]).
pub fn store(dir: &Path, stamp: &Stamp, payload: &[u8]) -> std::io::Result<()> {
    let mut bytes = stamp.header(payload.len() as u64);
    let mut crc = crc32fast::Hasher::new();
    crc.update(&bytes);
    crc.update(payload);
    bytes.extend_from_slice(&crc.finalize().to_le_bytes());
    bytes.extend_from_slice(payload);
    crate::io::output::write_atomic(&stamp.file(dir), &bytes)
}

/// The payload of the entry `stamp` names under `dir`, if there is one that checks out and is at most
/// `max_payload` bytes; a file that is there but does not check out is reported in one line (and left for the
/// caller's new entry to replace).
pub fn load(dir: &Path, stamp: &Stamp, max_payload: u64) -> Option<Vec<u8>> {
    let file = stamp.file(dir);
    match read_entry(&file, stamp, max_payload) {
        Ok(payload) => Some(payload),
        Err(Some(reason)) => {
            log::info!("the cached {} {} {reason}; computing it again", stamp.what, file.display());
            None
        }
        Err(None) => None,
    }
}

/// Err(None): no entry; Err(Some(reason)): an entry that does not check out.
fn read_entry(file: &Path, stamp: &Stamp, max_payload: u64) -> std::result::Result<Vec<u8>, Option<String>> {
    use std::os::unix::fs::OpenOptionsExt;
    let mut f = match std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK).open(file) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(None),
        Err(e) => return Err(Some(format!("cannot be opened ({e})"))),
    };
    let meta = f.metadata().map_err(|e| Some(format!("cannot be read ({e})")))?;
    if !meta.is_file() {
        return Err(Some("is not a regular file".into()));
    }
    let expected = stamp.header(0);
    let header_len = expected.len() as u64 + 4;
    if meta.len() < header_len {
        return Err(Some(format!("is {} bytes, shorter than its header", meta.len())));
    }
    let mut header = vec![0u8; header_len as usize];
    f.read_exact(&mut header).map_err(|e| Some(format!("cannot be read ({e})")))?;
    let fixed = expected.len() - 8;
    if header[..fixed] != expected[..fixed] {
        return Err(Some(mismatch(&header, stamp)));
    }
    let len = u64::from_le_bytes(header[fixed..fixed + 8].try_into().expect("8 bytes"));
    if len > max_payload {
        return Err(Some(format!("says it holds {len} bytes, more than the {max_payload} its plan can need")));
    }
    if meta.len() != header_len + len {
        return Err(Some(format!("is {} bytes where its header says {}", meta.len(), header_len + len)));
    }
    let mut payload = vec![0u8; len as usize];
    f.read_exact(&mut payload).map_err(|e| Some(format!("cannot be read ({e})")))?;
    let mut crc = crc32fast::Hasher::new();
    crc.update(&header[..header.len() - 4]);
    crc.update(&payload);
    let stored = u32::from_le_bytes(header[header.len() - 4..].try_into().expect("4 bytes"));
    if crc.finalize() != stored {
        return Err(Some("fails its checksum (changed or damaged since it was written)".into()));
    }
    Ok(payload)
}

/// Why a header that differs from the expected one does: another program, version, kind or plan.
fn mismatch(header: &[u8], stamp: &Stamp) -> String {
    let mut r = Reader::new(header);
    if r.take(8) != Some(ENTRY_MAGIC.as_slice()) || r.u32() != Some(ENTRY_FORMAT) {
        return "is not a diffract cache entry of this format".into();
    }
    let (kind, producer) = (r.string(), r.string());
    if kind.as_deref() != Some(stamp.kind) {
        return "holds another kind of result".into();
    }
    match producer {
        Some(p) if p != PRODUCER => format!("was written by {p}, not {PRODUCER}"),
        _ if r.u64() != Some(stamp.version) => "was written under another definition of its result".into(),
        _ => "was computed for another plan".into(),
    }
}

/// A stable 64-bit hash (XXH3 from `xxhash-rust`: the same across builds and platforms, unlike std's hasher): the
/// name of a cached result, and the key of what it depends on.
pub struct KeyHash(xxhash_rust::xxh3::Xxh3);

impl Default for KeyHash {
    fn default() -> Self {
        Self(xxhash_rust::xxh3::Xxh3::new())
    }
}

impl KeyHash {
    pub fn bytes(&mut self, bytes: &[u8]) {
        self.0.update(bytes);
    }

    pub fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }

    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }

    /// The hash of everything fed so far.
    pub fn finish(&self) -> u64 {
        self.0.digest()
    }
}

/// A little-endian reader over a cached file's bytes: every read is bounds-checked (None past the end).
pub struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }

    pub fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let s = self.bytes.get(self.at..self.at.checked_add(n)?)?;
        self.at += n;
        Some(s)
    }

    pub fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }

    pub fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }

    pub fn f64(&mut self) -> Option<f64> {
        Some(f64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }

    pub fn string(&mut self) -> Option<String> {
        let len = usize::try_from(self.u64()?).ok()?;
        String::from_utf8(self.take(len)?.to_vec()).ok()
    }

    /// Whether every byte was read.
    pub fn finished(&self) -> bool {
        self.at == self.bytes.len()
    }
}

#[cfg(test)]
mod tests {
    use super::KeyHash;

    #[test]
    fn key_hash_is_xxh3_and_stable() {
        // XXH3-64 of no input, as the reference implementation publishes it: cache names must not drift.
        assert_eq!(KeyHash::default().finish(), 0x2d06_8005_38d3_94c2);
        let key = |v: f64| {
            let mut h = KeyHash::default();
            h.u64(7);
            h.f64(v);
            h.finish()
        };
        assert_eq!(key(0.5), key(0.5));
        assert_ne!(key(0.5), key(0.25));
    }
}
