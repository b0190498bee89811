//! Exposure measured from a frame, for a scene or command that sets none, and the one-line verdict on a frame
//! that came out almost all black or all white.
//!
//! Auto exposure: the 99.5th percentile of the luminance of the frame's lit pixels (Y > 0 of linear sRGB, so a
//! black background does not count) is mapped to [`AUTO_TARGET`] before the sRGB transfer function: the
//! brightest half percent (glints) may clip, the rest of the image keeps its ratios. A sequence measures its
//! first frame and keeps that exposure for every frame, so that brightness changes between frames stay visible.

use crate::display::tone::{encode, Tone};
use crate::physics::spectrum::luminance;

/// The quantile of the lit pixels' luminance that auto exposure places at [`AUTO_TARGET`].
pub const AUTO_QUANTILE: f64 = 0.995;
/// Where the quantile lands, linear (before the sRGB transfer function; 1 is display white).
pub const AUTO_TARGET: f64 = 0.9;
/// The most stops an exposure may be set to either way (a flag, a scene's `exposure_ev`): 2^100 takes any radiance
/// f32 holds from black to white.
pub const MAX_EXPOSURE_EV: f64 = 100.0;
/// The auto exposure stays within ±this many stops (a frame lit at 2^-40 is a bug, not a dark scene).
pub const AUTO_LIMIT_EV: f64 = 40.0;
/// A pixel counts as black when no channel of its 8-bit sRGB value exceeds this (5 %: linear 0.004).
pub const BLACK_CODE: u8 = 12;
/// A frame is "almost all black" when at least this fraction of its pixels are.
pub const BLACK_FRACTION: f64 = 0.99;
/// A frame is "mostly white" when at least this fraction of its lit pixels clip (a channel at 254 or 255).
pub const WHITE_FRACTION: f64 = 0.5;

/// An exposure measured from a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoExposure {
    /// The exposure in stops.
    pub ev: f64,
    /// The luminance at the quantile, linear (Y of a white mirror under the light is 1).
    pub luminance: f64,
    /// How many pixels were lit (Y > 0).
    pub lit: usize,
}

impl AutoExposure {
    /// Measures linear RGBA (rows of pixels, 4 floats each); None where no pixel is lit or finite.
    pub fn of(rgba: &[f32]) -> Option<Self> {
        Self::of_luminance(rgba.chunks_exact(4).map(|p| luminance([p[0], p[1], p[2]])))
    }

    /// Measures pixels' luminances (Y; the profiler's exact reference gives XYZ); None where none is lit.
    pub fn of_luminance(values: impl Iterator<Item = f64>) -> Option<Self> {
        let mut lit: Vec<f64> = values.filter(|y| y.is_finite() && *y > 0.0).collect();
        let count = lit.len();
        let luminance = crate::io::stats::percentile(&mut lit, AUTO_QUANTILE);
        if count == 0 || luminance.is_nan() || luminance <= 0.0 {
            return None;
        }
        let ev = (AUTO_TARGET / luminance).log2().clamp(-AUTO_LIMIT_EV, AUTO_LIMIT_EV);
        Some(Self { ev, luminance, lit: count })
    }

    /// One line for the user: the exposure and where it came from.
    pub fn describe(&self) -> String {
        format!(
            "exposure {:+.2} EV, measured (the 99.5th percentile of the lit pixels' luminance, {:.4e}, shown at {}; \
             --exposure EV or [render] exposure_ev sets one)",
            self.ev, self.luminance, AUTO_TARGET
        )
    }
}

/// The exposure of `rgba` (linear RGBA) measured, or 0 EV where nothing in it is lit, with the line that tells
/// the user which (`what` names the frame: "the first frame", "the map").
pub fn measure(rgba: &[f32], what: &str) -> (f64, String) {
    match AutoExposure::of(rgba) {
        Some(auto) => (auto.ev, auto.describe()),
        None => (0.0, format!("warning: nothing in {what} is lit, so no exposure can be measured: 0 EV")),
    }
}

/// Whether a frame shown at `exposure_ev` through `tone` is almost all black (its pixels, background included) or mostly white
/// (its lit pixels: a black background does not make a blown-out object well exposed): the warning line, or None.
pub fn verdict(rgba: &[f32], exposure_ev: f64, tone: Tone) -> Option<String> {
    let scale = exposure_ev.exp2();
    let (mut black, mut white, mut lit, mut total) = (0usize, 0usize, 0usize, 0usize);
    for p in rgba.chunks_exact(4) {
        let rgb = glam::DVec3::new(p[0].into(), p[1].into(), p[2].into());
        let shown = encode(rgb, scale, tone);
        total += 1;
        if shown.iter().all(|&c| c <= BLACK_CODE) {
            black += 1;
        }
        if luminance([p[0], p[1], p[2]]) > 0.0 {
            lit += 1;
            // Clipped: a channel at the top (spectral colours are out of gamut, so one channel clips first).
            if shown.iter().any(|&c| c >= 254) {
                white += 1;
            }
        }
    }
    let share = |n: usize, of: usize| n as f64 / of.max(1) as f64;
    if total > 0 && share(black, total) >= BLACK_FRACTION {
        Some(format!(
            "warning: the frame is almost all black at {exposure_ev:+.2} EV ({:.1} % of pixels); raise --exposure, \
             or leave it out to have it measured",
            100.0 * share(black, total)
        ))
    } else if lit > 0 && share(white, lit) >= WHITE_FRACTION {
        Some(format!(
            "warning: the frame is mostly white at {exposure_ev:+.2} EV ({:.1} % of the lit pixels clip); lower \
             --exposure, or leave it out to have it measured",
            100.0 * share(white, lit)
        ))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(values: &[f32]) -> Vec<f32> {
        values.iter().flat_map(|&v| [v, v, v, 1.0]).collect()
    }

    #[test]
    fn the_quantile_of_the_lit_pixels_lands_at_the_target() {
        // 1000 lit pixels of 0.01 and 1 glint of 5, among 9000 black ones.
        let mut values = vec![0.0; 9000];
        values.extend(std::iter::repeat_n(0.01, 1000));
        values.push(5.0);
        let auto = AutoExposure::of(&frame(&values)).unwrap();
        assert_eq!(auto.lit, 1001, "black pixels are not lit");
        assert!((auto.luminance - 0.01).abs() < 1e-9, "the glint is above the quantile: {}", auto.luminance);
        assert!((auto.ev - (0.9f64 / 0.01).log2()).abs() < 1e-6);
        let verdict = verdict(&frame(&values), auto.ev, Tone::Clip);
        assert!(verdict.is_none(), "an auto-exposed frame is neither black nor white");
    }

    #[test]
    fn nothing_lit_has_no_exposure_and_extremes_are_named() {
        assert_eq!(AutoExposure::of(&frame(&[0.0; 100])), None);
        assert_eq!(AutoExposure::of(&frame(&[f32::NAN; 4])), None);
        let (ev, line) = measure(&frame(&[0.0; 100]), "the map");
        assert!(ev == 0.0 && line.starts_with("warning: nothing in the map is lit"), "{ev} {line}");
        assert!(measure(&frame(&[0.01; 4]), "the map").1.contains("measured"));
        let dim = frame(&[0.001; 100]);
        assert!(verdict(&dim, 0.0, Tone::Clip).unwrap().contains("almost all black"));
        assert!(verdict(&dim, 20.0, Tone::Clip).unwrap().contains("mostly white"));
        assert!(verdict(&dim, AutoExposure::of(&dim).unwrap().ev, Tone::Clip).is_none());
        // A blown-out object on a black background is white where it is lit.
        let mut spot = frame(&[0.0; 90]);
        spot.extend(frame(&[0.5; 10]));
        assert!(verdict(&spot, 8.0, Tone::Clip).unwrap().contains("mostly white"));
    }
}
