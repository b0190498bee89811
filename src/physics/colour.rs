//! Colour differences for measuring image error: CIE XYZ → CIELAB (D65 white) and the CIEDE2000 difference
//! ΔE₀₀ (CIE 142-2001), as Sharma, Wu & Dalal state it (*The CIEDE2000 color-difference formula: implementation
//! notes, supplementary test data, and mathematical observations*, Color Res. Appl. 30, 2005), whose published
//! test pairs it reproduces to their four decimals (tested below).

use glam::DVec3;

use crate::gpu::interface::XYZ_TO_LINEAR_SRGB;

/// The D65 white point of the 2° observer (X, Y, Z with Y = 1), the white of [`xyz_to_lab`].
pub const D65_WHITE: DVec3 = DVec3::new(0.95047, 1.0, 1.08883);

/// The box every CIELAB colour is clamped to: L* in [0, 100], a* and b* in [−128, 127]. The `palette` crate's
/// conversion, which measured every ΔE00 diffract reported until 2026-11-28, clamps so; it is kept so that those
/// figures stay comparable. CIELAB itself has no bounds: a glint brighter than the reference white (L* > 100) and
/// spectral colours (a* beyond 127) are read at the box's edge.
pub const LAB_MIN: DVec3 = DVec3::new(0.0, -128.0, -128.0);
pub const LAB_MAX: DVec3 = DVec3::new(100.0, 127.0, 127.0);

/// CIELAB (L*, a*, b*) of `xyz` (on the scale where the D65 white has Y = 1) relative to [`D65_WHITE`], with the
/// CIE's exact constants ε = 216/24389 and κ = 24389/27.
pub fn xyz_to_lab(xyz: DVec3) -> DVec3 {
    const EPSILON: f64 = 216.0 / 24389.0;
    const KAPPA: f64 = 24389.0 / 27.0;
    let f = |t: f64| if t > EPSILON { t.cbrt() } else { (KAPPA * t + 16.0) / 116.0 };
    let r = xyz / D65_WHITE;
    let (fx, fy, fz) = (f(r.x), f(r.y), f(r.z));
    let lab = DVec3::new(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz));
    lab.clamp(LAB_MIN, LAB_MAX)
}

/// ΔE₀₀ between two CIELAB colours (kL = kC = kH = 1), in the steps of Sharma et al.'s equations (1)–(22).
pub fn ciede2000(lab1: DVec3, lab2: DVec3) -> f64 {
    let pow7 = |x: f64| x.powi(7);
    let twenty_five_7 = pow7(25.0);
    let c_bar = (lab1.y.hypot(lab1.z) + lab2.y.hypot(lab2.z)) / 2.0;
    let g = 0.5 * (1.0 - (pow7(c_bar) / (pow7(c_bar) + twenty_five_7)).sqrt());
    // a′, C′ and h′ (degrees in [0, 360); 0 where a′ = b = 0).
    let prime = |lab: DVec3| {
        let a = (1.0 + g) * lab.y;
        let c = a.hypot(lab.z);
        let h = if a == 0.0 && lab.z == 0.0 { 0.0 } else { lab.z.atan2(a).to_degrees().rem_euclid(360.0) };
        (c, h)
    };
    let ((c1, h1), (c2, h2)) = (prime(lab1), prime(lab2));
    let dl = lab2.x - lab1.x;
    let dc = c2 - c1;
    let dh = if c1 * c2 == 0.0 {
        0.0
    } else {
        let d = h2 - h1;
        if d > 180.0 {
            d - 360.0
        } else if d < -180.0 {
            d + 360.0
        } else {
            d
        }
    };
    let dh_big = 2.0 * (c1 * c2).sqrt() * (dh.to_radians() / 2.0).sin();
    let l_bar = (lab1.x + lab2.x) / 2.0;
    let c_bar_prime = (c1 + c2) / 2.0;
    let h_bar = if c1 * c2 == 0.0 {
        h1 + h2
    } else if (h1 - h2).abs() <= 180.0 {
        (h1 + h2) / 2.0
    } else if h1 + h2 < 360.0 {
        (h1 + h2 + 360.0) / 2.0
    } else {
        (h1 + h2 - 360.0) / 2.0
    };
    let cos = |deg: f64| deg.to_radians().cos();
    let t = 1.0 - 0.17 * cos(h_bar - 30.0) + 0.24 * cos(2.0 * h_bar) + 0.32 * cos(3.0 * h_bar + 6.0)
        - 0.20 * cos(4.0 * h_bar - 63.0);
    let d_theta = 30.0 * (-((h_bar - 275.0) / 25.0).powi(2)).exp();
    let r_c = 2.0 * (pow7(c_bar_prime) / (pow7(c_bar_prime) + twenty_five_7)).sqrt();
    let l50 = (l_bar - 50.0).powi(2);
    let s_l = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let s_c = 1.0 + 0.045 * c_bar_prime;
    let s_h = 1.0 + 0.015 * c_bar_prime * t;
    let r_t = -(2.0 * d_theta).to_radians().sin() * r_c;
    let (l, c, h) = (dl / s_l, dc / s_c, dh_big / s_h);
    (l * l + c * c + h * h + r_t * c * h).sqrt()
}

/// Relative luminance Y of linear sRGB (IEC 61966-2-1's second row of the RGB → XYZ matrix).
pub fn luminance(rgb: DVec3) -> f64 {
    0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z
}

/// CIE XYZ → linear sRGB (IEC 61966-2-1's matrix, one source with the shaders': `XYZ_TO_LINEAR_SRGB`).
pub fn xyz_to_linear_srgb(xyz: DVec3) -> DVec3 {
    let m = XYZ_TO_LINEAR_SRGB;
    DVec3::new(
        m[0][0] * xyz.x + m[0][1] * xyz.y + m[0][2] * xyz.z,
        m[1][0] * xyz.x + m[1][1] * xyz.y + m[1][2] * xyz.z,
        m[2][0] * xyz.x + m[2][1] * xyz.y + m[2][2] * xyz.z,
    )
}

/// `rgb` (linear sRGB) brought into the sRGB gamut at its own luminance: where a channel is negative (a colour
/// more saturated than the primaries reach: a sky's deep red at dusk, the sun's disc at the horizon), it is
/// desaturated towards the grey of the same luminance Y until its smallest channel is 0; where Y itself is not
/// positive, black. Colours inside the gamut are returned as they are. (Light cannot be negative: a map, a
/// lookup or an SH projection holding such a texel would subtract light.)
pub fn into_gamut(rgb: DVec3) -> DVec3 {
    let min = rgb.min_element();
    if min >= 0.0 {
        return rgb;
    }
    let y = luminance(rgb);
    if y.is_nan() || y <= 0.0 {
        return DVec3::ZERO;
    }
    let grey = DVec3::splat(y);
    (grey + (rgb - grey) * (y / (y - min))).max(DVec3::ZERO)
}

/// Linear sRGB → XYZ: the inverse of [`xyz_to_linear_srgb`] (reading the GPU's output back as colour).
pub fn linear_srgb_to_xyz(rgb: DVec3) -> DVec3 {
    static INVERSE: std::sync::LazyLock<glam::DMat3> = std::sync::LazyLock::new(|| {
        let m = XYZ_TO_LINEAR_SRGB;
        // glam is column-major: the rows of `m` are the columns of its transpose.
        glam::DMat3::from_cols(DVec3::from(m[0]), DVec3::from(m[1]), DVec3::from(m[2])).transpose().inverse()
    });
    *INVERSE * rgb
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn into_gamut_keeps_the_luminance_and_the_hue_side() {
        let dusk = DVec3::new(0.77, -0.0015, -0.18);
        let y = |c: DVec3| 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
        let g = into_gamut(dusk);
        assert!(g.min_element().abs() < 1e-15 && (y(g) - y(dusk)).abs() < 1e-12, "{g}");
        assert!(g.x > g.y && g.y > g.z, "{g}");
        assert_eq!(into_gamut(DVec3::new(0.1, 0.2, 0.3)), DVec3::new(0.1, 0.2, 0.3));
        assert_eq!(into_gamut(DVec3::new(-1.0, 0.01, 0.0)), DVec3::ZERO);
    }

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

    /// Pairs of nearly opposite hues, where the mean hue's branch matters, against colour-science 0.4.7's
    /// `delta_E(method="CIE 2000")` (which the `palette` crate, used until 2026-11-28, missed by up to 1.8e-4).
    #[test]
    fn ciede2000_agrees_with_colour_science_across_the_hue_branch() {
        let pairs = [
            (
                [33.23600994429265, 81.71759144100804, -67.75831169374533],
                [94.5707819124296, 66.35195363536204, 57.45386974757952],
                66.89539022420637,
            ),
            (
                [57.72942662237993, 6.890651261030129, -24.470397573021543],
                [71.3599262381937, 19.19001357831442, 85.5720982212348],
                48.35793172995629,
            ),
            (
                [23.422593704914004, 9.707869607110894, -13.749065352556116],
                [7.135887866300631, 69.0650619978419, 98.53085138342985],
                41.62528118964506,
            ),
        ];
        for (a, b, expected) in pairs {
            let d = ciede2000(DVec3::from(a), DVec3::from(b));
            assert!((d - expected).abs() < 1e-9, "{a:?} vs {b:?}: {d} instead of {expected}");
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
