//! Colour differences for measuring image error: CIE XYZ → CIELAB (D65 white) and the CIEDE2000 difference
//! ΔE₀₀ (CIE 142-2001, as written out by Sharma, Wu & Dalal, *The CIEDE2000 color-difference formula*, 2005).

use glam::DVec3;

/// The D65 white point of the 2° observer (X, Y, Z with Y = 1).
pub const D65_WHITE: DVec3 = DVec3::new(0.95047, 1.0, 1.08883);

/// CIELAB (L*, a*, b*) of `xyz` relative to `white` (both with the white's Y = 1).
pub fn xyz_to_lab(xyz: DVec3, white: DVec3) -> DVec3 {
    const EPSILON: f64 = 216.0 / 24389.0;
    const KAPPA: f64 = 24389.0 / 27.0;
    let f = |t: f64| if t > EPSILON { t.cbrt() } else { (KAPPA * t + 16.0) / 116.0 };
    let (fx, fy, fz) = (f(xyz.x / white.x), f(xyz.y / white.y), f(xyz.z / white.z));
    DVec3::new(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz))
}

/// ΔE₀₀ between two CIELAB colours (kL = kC = kH = 1).
pub fn ciede2000(lab1: DVec3, lab2: DVec3) -> f64 {
    let (l1, a1, b1) = (lab1.x, lab1.y, lab1.z);
    let (l2, a2, b2) = (lab2.x, lab2.y, lab2.z);
    let c1 = a1.hypot(b1);
    let c2 = a2.hypot(b2);
    let c_mean = 0.5 * (c1 + c2);
    let c7 = c_mean.powi(7);
    let g = 0.5 * (1.0 - (c7 / (c7 + 25f64.powi(7))).sqrt());
    let (a1p, a2p) = ((1.0 + g) * a1, (1.0 + g) * a2);
    let (c1p, c2p) = (a1p.hypot(b1), a2p.hypot(b2));
    let hue = |b: f64, a: f64| if a == 0.0 && b == 0.0 { 0.0 } else { b.atan2(a).to_degrees().rem_euclid(360.0) };
    let (h1p, h2p) = (hue(b1, a1p), hue(b2, a2p));
    let dl = l2 - l1;
    let dc = c2p - c1p;
    let dh_angle = if c1p * c2p == 0.0 {
        0.0
    } else {
        let d = h2p - h1p;
        if d > 180.0 {
            d - 360.0
        } else if d < -180.0 {
            d + 360.0
        } else {
            d
        }
    };
    let dh = 2.0 * (c1p * c2p).sqrt() * (0.5 * dh_angle).to_radians().sin();
    let l_mean = 0.5 * (l1 + l2);
    let cp_mean = 0.5 * (c1p + c2p);
    let h_mean = if c1p * c2p == 0.0 {
        h1p + h2p
    } else if (h1p - h2p).abs() <= 180.0 {
        0.5 * (h1p + h2p)
    } else if h1p + h2p < 360.0 {
        0.5 * (h1p + h2p + 360.0)
    } else {
        0.5 * (h1p + h2p - 360.0)
    };
    let t = 1.0 - 0.17 * (h_mean - 30.0).to_radians().cos()
        + 0.24 * (2.0 * h_mean).to_radians().cos()
        + 0.32 * (3.0 * h_mean + 6.0).to_radians().cos()
        - 0.20 * (4.0 * h_mean - 63.0).to_radians().cos();
    let d_theta = 30.0 * (-((h_mean - 275.0) / 25.0).powi(2)).exp();
    let cp7 = cp_mean.powi(7);
    let rc = 2.0 * (cp7 / (cp7 + 25f64.powi(7))).sqrt();
    let l50 = (l_mean - 50.0).powi(2);
    let sl = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let sc = 1.0 + 0.045 * cp_mean;
    let sh = 1.0 + 0.015 * cp_mean * t;
    let rt = -(2.0 * d_theta).to_radians().sin() * rc;
    let (tl, tc, th) = (dl / sl, dc / sc, dh / sh);
    (tl * tl + tc * tc + th * th + rt * tc * th).sqrt()
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
        let white = xyz_to_lab(D65_WHITE, D65_WHITE);
        assert!((white - DVec3::new(100.0, 0.0, 0.0)).length() < 1e-12);
        assert_eq!(xyz_to_lab(DVec3::ZERO, D65_WHITE), DVec3::ZERO);
        // 18 % grey has L* = 49.5 (the CIE formula).
        assert!((xyz_to_lab(D65_WHITE * 0.18, D65_WHITE).x - 49.496).abs() < 1e-3);
    }
}
