//! Height fields in physical units: tiling, and the checks that keep hostile files from reaching an allocation or
//! a NaN (the files themselves are read in [`crate::physics::formats`], which builds on this module, not the reverse).
//!
//! Frame: pixel (column c, row r) sits at x = c·dx, y = r·dy in the patch frame (x along image columns, left to
//! right; y along rows, top to bottom; z the surface normal). Heights are in µm.

use crate::error::{Error, Result};

/// The most pixels a height field may have after tiling (a 8192² patch; its Taylor terms alone would need
/// 8192²·16 B = 1 GiB per term in f64, so anything larger is certainly a mistake or a hostile file).
pub const MAX_PIXELS: u64 = 8192 * 8192;
/// The longest edge a height field may have.
pub const MAX_EDGE: u32 = 65536;
/// The pixel sizes accepted, µm: 0.1 nm (an atom) to 100 µm (beyond it no visible wavelength sees structure;
/// the AFM scans have 0.065 µm). Anything outside is a unit mistake (metres for µm) or a hostile header.
pub const PIXEL_UM_RANGE: (f64, f64) = (1e-4, 100.0);
/// The largest height deviation |h − mean| accepted, µm: a height field of nanostructures 1 mm deep is a unit
/// mistake, and the phase k·w·h (10⁴ rad at 1 mm) leaves the scalar model's domain long before.
pub const MAX_DEVIATION_UM: f64 = 1000.0;

/// A measured or generated surface: heights in µm on a regular grid.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightField {
    /// Columns (x).
    pub nx: usize,
    /// Rows (y).
    pub ny: usize,
    /// Pixel size along x and y in µm.
    pub dx_um: f64,
    pub dy_um: f64,
    /// Row-major heights in µm: `heights_um[r * nx + c]`.
    pub heights_um: Vec<f64>,
}

impl HeightField {
    /// Builds a height field, checking sizes and values.
    pub fn new(nx: usize, ny: usize, dx_um: f64, dy_um: f64, heights_um: Vec<f64>) -> Result<Self> {
        check_dims(nx as u64, ny as u64)?;
        if heights_um.len() != nx * ny {
            return Err(Error::HeightField(format!("{} heights given for {nx}×{ny} pixels", heights_um.len())));
        }
        let (lo, hi) = PIXEL_UM_RANGE;
        for (name, d) in [("x", dx_um), ("y", dy_um)] {
            if !(lo..=hi).contains(&d) {
                return Err(Error::HeightField(format!(
                    "the pixel size along {name} is {} µm; diffract accepts {lo:e} to {hi} µm",
                    crate::error::number(d)
                )));
            }
        }
        if let Some(i) = heights_um.iter().position(|h| !h.is_finite()) {
            return Err(Error::HeightField(format!(
                "height at column {}, row {} is {}",
                i % nx,
                i / nx,
                heights_um[i]
            )));
        }
        let hf = Self { nx, ny, dx_um, dy_um, heights_um };
        let deviation = hf.max_deviation();
        if deviation.is_nan() || deviation > MAX_DEVIATION_UM {
            return Err(Error::HeightField(format!(
                "heights vary by up to {deviation:.3e} µm about their mean; diffract models nanostructures up to \
                 {MAX_DEVIATION_UM} µm deep (heights are in µm: were metres or nm given?)"
            )));
        }
        Ok(hf)
    }

    /// Feeds everything a height field's results depend on into a cache key: size, pixel size and every height.
    pub fn hash_into(&self, h: &mut crate::io::cache::KeyHash) {
        h.u64(self.nx as u64);
        h.u64(self.ny as u64);
        h.f64(self.dx_um);
        h.f64(self.dy_um);
        for &z in &self.heights_um {
            h.f64(z);
        }
    }

    /// Patch edge lengths in µm.
    pub fn size_um(&self) -> (f64, f64) {
        (self.nx as f64 * self.dx_um, self.ny as f64 * self.dy_um)
    }

    pub fn mean(&self) -> f64 {
        self.heights_um.iter().sum::<f64>() / self.heights_um.len() as f64
    }

    /// (min, max) height in µm.
    pub fn range(&self) -> (f64, f64) {
        self.heights_um.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| (lo.min(h), hi.max(h)))
    }

    /// The heights minus their mean: a constant offset changes only the phase of P, and centring halves the
    /// argument of the Taylor series (model.md §2.1 step 1).
    pub fn centred(&self) -> Vec<f64> {
        let mean = self.mean();
        self.heights_um.iter().map(|h| h - mean).collect()
    }

    /// The largest |h − mean| in µm.
    pub fn max_deviation(&self) -> f64 {
        let mean = self.mean();
        self.heights_um.iter().fold(0.0f64, |m, h| m.max((h - mean).abs()))
    }

    /// The smallest cell of which this field is an exact periodic tiling, as a height field (the field itself
    /// when it has none). Means over the patch — height moments, the dominant spacing — are the cell's, so a
    /// report on a 10×10 tiling does the work of one tile.
    pub fn tiling_cell(&self) -> std::borrow::Cow<'_, HeightField> {
        let (px, py) = self.period_cell();
        if (px, py) == (self.nx, self.ny) {
            return std::borrow::Cow::Borrowed(self);
        }
        std::borrow::Cow::Owned(self.corner(px, py))
    }

    /// The smallest cell (px, py) of which the height field is an exact periodic tiling (its own size if none).
    pub fn period_cell(&self) -> (usize, usize) {
        let h = &self.heights_um;
        let (nx, ny) = (self.nx, self.ny);
        let divisors = |n: usize| (1..=n).filter(move |p| n % p == 0);
        let px =
            divisors(nx).find(|&p| (0..ny).all(|r| (p..nx).all(|c| h[r * nx + c] == h[r * nx + c - p]))).unwrap_or(nx);
        let py = divisors(ny)
            .find(|&p| (p..ny).all(|r| (0..nx).all(|c| h[r * nx + c] == h[(r - p) * nx + c])))
            .unwrap_or(ny);
        (px, py)
    }

    /// The top-left `px`×`py` pixels as a height field of their own (at most the field's size).
    pub fn corner(&self, px: usize, py: usize) -> HeightField {
        let (px, py) = (px.min(self.nx), py.min(self.ny));
        let heights_um = (0..py).flat_map(|r| self.heights_um[r * self.nx..][..px].iter().copied()).collect();
        Self { nx: px, ny: py, dx_um: self.dx_um, dy_um: self.dy_um, heights_um }
    }

    /// Repeats the patch `tx` times along x and `ty` times along y (periodic tiling).
    pub fn tiled(&self, tx: usize, ty: usize) -> Result<Self> {
        if tx == 0 || ty == 0 {
            return Err(Error::setting("tile", "--tile counts must be at least 1".into()));
        }
        let (nx, ny) = (self.nx as u64 * tx as u64, self.ny as u64 * ty as u64);
        check_dims(nx, ny).map_err(|e| Error::HeightField(format!("tiling {tx}×{ty}: {e}")))?;
        let (nx, ny) = (nx as usize, ny as usize);
        let mut heights = Vec::with_capacity(nx * ny);
        for r in 0..ny {
            let row = &self.heights_um[(r % self.ny) * self.nx..][..self.nx];
            for _ in 0..tx {
                heights.extend_from_slice(row);
            }
        }
        Ok(Self { nx, ny, dx_um: self.dx_um, dy_um: self.dy_um, heights_um: heights })
    }
}

/// Refuses empty, absurd or memory-exhausting sizes before anything is allocated.
pub(crate) fn check_dims(nx: u64, ny: u64) -> Result<()> {
    if nx == 0 || ny == 0 {
        return Err(Error::HeightField(format!("a height field of {nx}×{ny} pixels is empty")));
    }
    if nx > u64::from(MAX_EDGE) || ny > u64::from(MAX_EDGE) || nx.saturating_mul(ny) > MAX_PIXELS {
        return Err(Error::HeightField(format!(
            "{nx}×{ny} pixels is more than diffract handles (at most {MAX_PIXELS} pixels)"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiling_repeats_rows_and_columns() {
        let hf = HeightField::new(2, 2, 0.1, 0.1, vec![1.0, 2.0, 3.0, 4.0]).unwrap();
        let t = hf.tiled(2, 3).unwrap();
        assert_eq!((t.nx, t.ny), (4, 6));
        assert_eq!(&t.heights_um[..8], &[1.0, 2.0, 1.0, 2.0, 3.0, 4.0, 3.0, 4.0]);
        assert_eq!(t.heights_um[16..24], [1.0, 2.0, 1.0, 2.0, 3.0, 4.0, 3.0, 4.0]);
    }

    #[test]
    fn absurd_sizes_and_bad_values_are_refused() {
        assert!(check_dims(0, 5).is_err());
        assert!(check_dims(1 << 20, 1 << 20).is_err());
        assert!(HeightField::new(1, 1, 0.1, 0.1, vec![f64::NAN]).is_err());
        assert!(HeightField::new(1, 1, 0.0, 0.1, vec![0.0]).is_err());
        let hf = HeightField::new(1, 1, 0.1, 0.1, vec![0.0]).unwrap();
        assert!(hf.tiled(1 << 16, 1 << 16).is_err());
    }

    #[test]
    fn a_tiling_is_found_and_a_random_patch_is_its_own_cell() {
        let cell: Vec<f64> = (0..12).map(|i| ((i * 7919) % 13) as f64 * 0.01).collect();
        let hf = HeightField::new(4, 3, 0.1, 0.1, cell).unwrap();
        assert_eq!(hf.period_cell(), (4, 3));
        assert_eq!(hf.tiled(5, 2).unwrap().period_cell(), (4, 3));
        let rows = HeightField::new(6, 5, 0.1, 0.1, (0..30).map(|i| (i % 6) as f64).collect()).unwrap();
        assert_eq!(rows.period_cell(), (6, 1), "constant along y: a cell one row tall");
    }

    #[test]
    fn centring_and_deviation() {
        let hf = HeightField::new(4, 1, 0.1, 0.1, vec![0.0, 0.1, 0.2, 0.5]).unwrap();
        assert!((hf.mean() - 0.2).abs() < 1e-15);
        assert!((hf.max_deviation() - 0.3).abs() < 1e-15);
        assert!(hf.centred().iter().sum::<f64>().abs() < 1e-15);
    }
}
