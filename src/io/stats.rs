//! The few statistics diffract reports, in one place: quantiles and the median/p10/p90 spread of timings, and the
//! count of pixels that are not finite numbers (the check every frame and map passes before it is written).

/// The `q`-quantile (0..=1) of `values` by linear interpolation between order statistics (sorts `values`); NaN
/// for no values.
pub fn percentile(values: &mut [f64], q: f64) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(f64::total_cmp);
    let at = q.clamp(0.0, 1.0) * (values.len() - 1) as f64;
    let (lo, hi) = (at.floor() as usize, at.ceil() as usize);
    values[lo] + (values[hi] - values[lo]) * (at - lo as f64)
}

/// The median of `values` (the mean of the middle two for an even count); None for no values.
pub fn median(values: &[f64]) -> Option<f64> {
    (!values.is_empty()).then(|| percentile(&mut values.to_vec(), 0.5))
}

/// Median, 10th and 90th percentiles of a set of frame times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    pub median: f64,
    pub p10: f64,
    pub p90: f64,
}

impl Spread {
    pub fn of(values: &[f64]) -> Option<Self> {
        if values.is_empty() {
            return None;
        }
        let mut v = values.to_vec();
        Some(Self { median: percentile(&mut v, 0.5), p10: percentile(&mut v, 0.1), p90: percentile(&mut v, 0.9) })
    }
}

/// Pixels of an RGBA float image (4 values each) with a channel that is not a finite number.
pub fn non_finite_pixels(rgba: &[f32]) -> usize {
    rgba.chunks(4).filter(|p| p.iter().any(|c| !c.is_finite())).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate() {
        let mut v = vec![4.0, 1.0, 3.0, 2.0, 5.0];
        assert_eq!(percentile(&mut v, 0.5), 3.0);
        assert_eq!(percentile(&mut v, 0.0), 1.0);
        assert!((percentile(&mut v, 0.1) - 1.4).abs() < 1e-12);
        let s = Spread::of(&[2.0, 1.0, 3.0]).unwrap();
        assert_eq!((s.median, s.p10, s.p90), (2.0, 1.2, 2.8));
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&[]), None);
    }

    #[test]
    fn non_finite_pixels_are_counted_once_each() {
        let rgba = [0.0, 1.0, 2.0, 1.0, f32::NAN, f32::INFINITY, 0.0, 1.0, 0.5, 0.5, 0.5, f32::NEG_INFINITY];
        assert_eq!(non_finite_pixels(&rgba), 2);
    }
}
