//! Gwyddion Simple Field (`.gsf`), the plain format AFM users export from Gwyddion:
//! the line `Gwyddion Simple Field 1.0`, then `Key = Value` lines (`XRes`, `YRes` required; `XReal`, `YReal`
//! in `XYUnits`, default 1 m; `XOffset`, `YOffset`, `XYUnits`, `ZUnits`, `Title` optional), then 1–4 NUL bytes
//! so the data starts at a multiple of 4, then `XRes·YRes` little-endian f32 heights (in `ZUnits`, default m),
//! row by row.
//!
//! Every size is checked against the file's length before anything is allocated.

use std::path::Path;

use crate::error::{Error, Result};
use crate::physics::heightfield::{check_dims, HeightField, MAX_PIXELS};

const MAGIC: &str = "Gwyddion Simple Field 1.0";
/// A header longer than this is not a GSF header (real ones are a few hundred bytes).
const MAX_HEADER: usize = 64 * 1024;
const KNOWN_KEYS: &[&str] = &["XRes", "YRes", "XReal", "YReal", "XOffset", "YOffset", "XYUnits", "ZUnits", "Title"];

/// Micrometres per unit, for the SI length units a GSF may name.
fn um_per_unit(unit: &str) -> Option<f64> {
    Some(match unit.trim() {
        "" | "m" => 1e6,
        "mm" => 1e3,
        "um" | "µm" | "μm" => 1.0,
        "nm" => 1e-3,
        "pm" => 1e-6,
        _ => return None,
    })
}

/// Reads a `.gsf` height field; heights and pixel size come out in µm.
pub fn read(path: &Path) -> Result<HeightField> {
    let limit = MAX_HEADER as u64 + 4 * MAX_PIXELS;
    let bytes = crate::io::input::read(path, limit, "GSF")?;
    parse(path, &bytes)
}

/// Parses the bytes of a `.gsf` file (`path` names it in messages).
pub fn parse(path: &Path, bytes: &[u8]) -> Result<HeightField> {
    let bad = |m: String| Error::input(path, m);
    let file_len = bytes.len() as u64;
    let header = &bytes[..bytes.len().min(MAX_HEADER)];
    if !header.starts_with(MAGIC.as_bytes()) {
        return Err(bad(format!("not a Gwyddion Simple Field (the first line must be {MAGIC:?})")));
    }
    let text_end = header
        .iter()
        .position(|&b| b == 0)
        .ok_or_else(|| bad("the header has no NUL terminator (truncated or not a GSF file)".into()))?;
    let padding = 4 - text_end % 4;
    let data_start = text_end + padding;
    if header.len() < data_start || header[text_end..data_start].iter().any(|&b| b != 0) {
        return Err(bad(format!("the header must end with {padding} NUL byte(s) so data starts at a multiple of 4")));
    }
    let text = std::str::from_utf8(&header[..text_end]).map_err(|_| bad("the header is not UTF-8 text".into()))?;
    let keys = header_keys(path, text)?;
    let res = |key: &str| -> Result<u64> {
        let (line, v) = keys.get(key).ok_or_else(|| bad(format!("the header lacks the required key {key}")))?;
        v.parse::<u64>()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| bad(format!("header line {line}: {key} = {v:?} is not a positive integer")))
    };
    let (nx, ny) = (res("XRes")?, res("YRes")?);
    check_dims(nx, ny).map_err(|e| bad(e.to_string()))?;
    let unit = |key: &str| -> Result<f64> {
        let v = keys.get(key).map(|(_, v)| v.as_str()).unwrap_or("m");
        um_per_unit(v)
            .ok_or_else(|| bad(format!("{key} = {v:?} is not a length unit diffract knows (m, mm, um, nm, pm)")))
    };
    let (xy_um, z_um) = (unit("XYUnits")?, unit("ZUnits")?);
    let real = |key: &str| -> Result<f64> {
        match keys.get(key) {
            None => Ok(1.0),
            Some((line, v)) => v
                .parse::<f64>()
                .ok()
                .filter(|r| r.is_finite() && *r > 0.0)
                .ok_or_else(|| bad(format!("header line {line}: {key} = {v:?} is not a positive length"))),
        }
    };
    let (x_real, y_real) = (real("XReal")?, real("YReal")?);
    let expected = data_start as u64 + 4 * nx * ny;
    if file_len != expected {
        return Err(bad(format!(
            "{nx}×{ny} heights need {} data bytes after the header, the file has {} (truncated or wrong XRes/YRes)",
            4 * nx * ny,
            file_len.saturating_sub(data_start as u64)
        )));
    }
    let heights: Vec<f64> = bytes[data_start..]
        .chunks_exact(4)
        .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])) * z_um)
        .collect();
    let (nx, ny) = (nx as usize, ny as usize);
    if let Some(i) = heights.iter().position(|h| !h.is_finite()) {
        return Err(bad(format!("the height at column {}, row {} is not a finite number", i % nx, i / nx)));
    }
    HeightField::new(nx, ny, x_real * xy_um / nx as f64, y_real * xy_um / ny as f64, heights)
        .map_err(|e| bad(e.to_string()))
}

/// The header's known keys (`KNOWN_KEYS`), each with its line and value; refused: a line that is not `Key =
/// Value`, a key given twice.
fn header_keys(path: &Path, text: &str) -> Result<std::collections::HashMap<String, (usize, String)>> {
    let bad = |m: String| Error::input(path, m);
    let mut keys = std::collections::HashMap::new();
    let mut seen = std::collections::HashMap::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let (k, v) =
            line.split_once('=').ok_or_else(|| bad(format!("header line {}: expected `Key = Value`", i + 1)))?;
        let k = k.trim();
        // A key given twice is ambiguous (which XReal is the scan's?): Gwyddion writes each once.
        if let Some(first) = seen.insert(k.to_string(), i + 1) {
            return Err(bad(format!("header line {}: {k} is given a second time (first on line {first})", i + 1)));
        }
        if !KNOWN_KEYS.contains(&k) {
            // Gwyddion allows further keys (metadata); they are kept out of the physics.
            continue;
        }
        keys.insert(k.to_string(), (i + 1, v.trim().to_string()));
    }
    Ok(keys)
}

/// Writes a height field as `.gsf` with metres as units (what Gwyddion writes).
pub fn write(path: &Path, hf: &HeightField, title: &str) -> Result<()> {
    let (lx, ly) = hf.size_um();
    let mut header = format!(
        "{MAGIC}\nXRes = {}\nYRes = {}\nXReal = {:e}\nYReal = {:e}\nXYUnits = m\nZUnits = m\nTitle = {}\n",
        hf.nx,
        hf.ny,
        lx * 1e-6,
        ly * 1e-6,
        title.replace('\n', " ")
    )
    .into_bytes();
    let padding = 4 - header.len() % 4;
    header.extend(std::iter::repeat_n(0u8, padding));
    header.reserve(hf.heights_um.len() * 4);
    for h in &hf.heights_um {
        header.extend_from_slice(&((h * 1e-6) as f32).to_le_bytes());
    }
    crate::io::output::write_file(path, &header)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("diffract-gsf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    fn sample() -> HeightField {
        HeightField::new(3, 2, 0.05, 0.05, vec![0.0, 0.1, 0.2, 0.3, 0.25, 0.125]).unwrap()
    }

    #[test]
    fn round_trip_keeps_units() {
        let p = scratch("rt.gsf");
        write(&p, &sample(), "test").unwrap();
        let back = read(&p).unwrap();
        assert_eq!((back.nx, back.ny), (3, 2));
        assert!((back.dx_um - 0.05).abs() < 1e-12 && (back.dy_um - 0.05).abs() < 1e-12);
        for (a, b) in back.heights_um.iter().zip(&sample().heights_um) {
            assert!((a - b).abs() < 1e-7, "{a} vs {b}");
        }
    }

    fn expect_err(bytes: &[u8], needle: &str) {
        let p = scratch(&format!("bad-{}.gsf", needle.len()));
        std::fs::write(&p, bytes).unwrap();
        let e = read(&p).unwrap_err().to_string();
        assert!(e.contains(needle), "{e:?} should mention {needle:?}");
        assert_eq!(e.lines().count(), 1);
    }

    fn header(body: &str) -> Vec<u8> {
        let mut h = format!("{MAGIC}\n{body}").into_bytes();
        let pad = 4 - h.len() % 4;
        h.extend(std::iter::repeat_n(0, pad));
        h
    }

    #[test]
    fn hostile_files_are_refused() {
        expect_err(b"Gwyddion Simple Field 2.0\nXRes = 1\n\0\0", "not a Gwyddion");
        expect_err(format!("{MAGIC}\nXRes = 2\nYRes = 2\n").as_bytes(), "NUL");
        expect_err(&header("XRes = 2\n"), "YRes");
        expect_err(&header("XRes = -2\nYRes = 2\n"), "positive integer");
        let mut truncated = header("XRes = 2\nYRes = 2\n");
        truncated.extend_from_slice(&[0; 12]);
        expect_err(&truncated, "truncated");
        // Absurd dimensions are refused before any allocation.
        expect_err(&header("XRes = 4000000000\nYRes = 4000000000\n"), "more than diffract handles");
        let mut nan = header("XRes = 1\nYRes = 1\n");
        nan.extend_from_slice(&f32::NAN.to_le_bytes());
        expect_err(&nan, "not a finite number");
        let mut units = header("XRes = 1\nYRes = 1\nZUnits = furlong\n");
        units.extend_from_slice(&0f32.to_le_bytes());
        expect_err(&units, "furlong");
        let mut twice = header("XRes = 1\nYRes = 1\nXReal = 1e-6\nXReal = 1e-3\n");
        twice.extend_from_slice(&0f32.to_le_bytes());
        expect_err(&twice, "XReal is given a second time (first on line 4)");
    }
}
