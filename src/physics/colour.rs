//! Colour differences for measuring image error: CIE XYZ → CIELAB (D65 white) and the CIEDE2000 difference
//! ΔE₀₀ (CIE 142-2001), both from the `palette` crate. Its CIEDE2000 reproduces the published test pairs of
//! Sharma, Wu & Dalal (*The CIEDE2000 color-difference formula*, 2005) to their four decimals (tested below).

use glam::DVec3;
use palette::color_difference::Ciede2000;
use palette::white_point::D65;
use palette::{IntoColor, Lab, Xyz};

/// The D65 white point of the 2° observer (X, Y, Z with Y = 1), the white of [`xyz_to_lab`].
pub const D65_WHITE: DVec3 = DVec3::new(0.95047, 1.0, 1.08883);

/// CIELAB (L*, a*, b*) of `xyz` (on the scale where the D65 white has Y = 1) relative to [`D65_WHITE`].
pub fn xyz_to_lab(xyz: DVec3) -> DVec3 {
    let lab: Lab<D65, f64> = Xyz::<D65, f64>::new(xyz.x, xyz.y, xyz.z).into_color();
    DVec3::new(lab.l, lab.a, lab.b)
}

/// ΔE₀₀ between two CIELAB colours (kL = kC = kH = 1).
pub fn ciede2000(lab1: DVec3, lab2: DVec3) -> f64 {
    let lab = |v: DVec3| Lab::<D65, f64>::new(v.x, v.y, v.z);
    lab(lab1).difference(lab(lab2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pairs from the test data of Sharma, Wu & Dalal (2005), Table 1: (Lab1, Lab2, ΔE00).
    const SHARMA: [([f64; 3], [f64; 3], f64); 10] = [
        ([50.0, 2.6772, -79.7751], [50.0, 0.0, -82.7485], 2.0425),
        ([50.0, 3.1571, -77.2803], [50.0, 0.0, -82.7485], 2.8615),
        ([50.0, 2.8361, -74.0200], [50.0, 0.0, -82.7485], 3.4412),
        ([50.0, -1.3802, -84.2814], [50.0, 0.0, -82.7485], 1.0000),
        ([50.0, 0.0, 0.0], [50.0, -1.0, 2.0], 2.3669),
        ([50.0, 2.5, 0.0], [50.0, 0.0, -2.5], 4.3065),
        ([50.0, 2.5, 0.0], [73.0, 25.0, -18.0], 27.1492),
        ([50.0, 2.5, 0.0], [56.0, -27.0, -3.0], 31.9030),
        ([60.2574, -34.0099, 36.2677], [60.4626, -34.1751, 39.4387], 1.2644),
        ([22.7233, 20.0904, -46.6940], [23.0331, 14.9730, -42.5619], 2.0373),
    ];

    #[test]
    fn ciede2000_reproduces_the_published_test_pairs() {
        for (a, b, expected) in SHARMA {
            let d = ciede2000(DVec3::from(a), DVec3::from(b));
            assert!((d - expected).abs() < 1e-4, "{a:?} vs {b:?}: {d} instead of {expected}");
            assert!((ciede2000(DVec3::from(b), DVec3::from(a)) - d).abs() < 1e-12, "symmetric");
        }
    }

    #[test]
    fn lab_of_the_white_point_and_of_black() {
        let white = xyz_to_lab(D65_WHITE);
        assert!((white - DVec3::new(100.0, 0.0, 0.0)).length() < 1e-12, "{white}");
        assert_eq!(xyz_to_lab(DVec3::ZERO), DVec3::ZERO);
        // 18 % grey has L* = 49.5 (the CIE formula).
        assert!((xyz_to_lab(D65_WHITE * 0.18).x - 49.496).abs() < 1e-3);
        // Below ε = 216/24389 the CIE formula is linear: L* = κ·Y with κ = 24389/27.
        let dark = xyz_to_lab(D65_WHITE * 0.001).x;
        assert!((dark - 24389.0 / 27.0 * 0.001).abs() < 1e-9, "{dark}");
    }
}
