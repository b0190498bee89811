//! The CIE tables at 1 nm from 380 to 780 nm (`TABLE_ROWS` rows): the CIE 1931 2° colour-matching functions x̄,
//! ȳ, z̄ and the relative spectral power of CIE standard illuminant D65 (100 at 560 nm), as the `colorimetry`
//! crate holds them (the CIE's data tables: CIE 018:2019 for the observer, CIE S 014-2/ISO 11664-2 for D65).
//! They are read once into plain arrays, which the spectral sums index; `physics::spectrum` checks the D65 white
//! point they give against the published one.

use std::sync::OnceLock;

use crate::gpu::interface::{TABLE_LAMBDA_MIN_NM, TABLE_ROWS};

/// (x̄, ȳ, z̄) of the CIE 1931 2° standard observer at 380, 381, …, 780 nm.
pub fn cie1931_xyz() -> &'static [[f64; 3]; TABLE_ROWS] {
    static TABLE: OnceLock<[[f64; 3]; TABLE_ROWS]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|k| {
            let nm = TABLE_LAMBDA_MIN_NM as usize + k;
            let xyz = colorimetry::observer::Observer::Cie1931.xyz_at_wavelength(nm);
            xyz.expect("colorimetry tabulates the observer from 380 to 780 nm").to_array()
        })
    })
}

/// CIE standard illuminant D65 at 380, 381, …, 780 nm, 100 at 560 nm.
pub fn d65() -> &'static [f64; TABLE_ROWS] {
    static TABLE: OnceLock<[f64; TABLE_ROWS]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let spectrum: &colorimetry::spectrum::Spectrum = colorimetry::illuminant::D65.as_ref();
        *spectrum.as_array()
    })
}

#[cfg(test)]
mod tests {
    /// Points of the CIE's own tables: the observer's ends and peak, D65's normalisation.
    #[test]
    fn the_tables_hold_the_cie_values() {
        let (xyz, d65) = (super::cie1931_xyz(), super::d65());
        assert_eq!(xyz[0], [0.001368, 0.000039, 0.006450001]);
        assert_eq!(xyz[555 - 380][1], 1.0);
        assert_eq!(d65[560 - 380], 100.0);
        assert!((d65[0] - 49.9755).abs() < 1e-9, "{}", d65[0]);
    }
}
