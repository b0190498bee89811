//! Exposure measured from a frame, for a scene or command that sets none, and the one-line verdict on a frame that
//! came out almost all black or all white. The meter reads the pixels that count (the subject's where the caller
//! knows which pixels show objects, else the lit ones) as the tone curve needs them:
//! - through clip, their luminance's 99.5th percentile goes to [`AUTO_TARGET`] (the brightest half percent, the
//!   glints, may clip);
//! - through the filmic curve, their median goes to middle grey ([`MIDDLE_GREY`]) unless that would put their
//!   99.5th percentile more than [`GLINT_HEADROOM_EV`] stops over white: a grating's colours stay on the curve's
//!   shoulder, where they keep most of their saturation, instead of its top, where AgX turns them white.
//!
//! A sequence measures its first frame and keeps that exposure, so that brightness changes between frames show.

use crate::display::tone::{encode, Tone};
use crate::physics::spectrum::luminance;

/// The quantile of the lit pixels' luminance that auto exposure places at [`AUTO_TARGET`].
pub const AUTO_QUANTILE: f64 = 0.995;
/// Where the quantile lands, linear (before the sRGB transfer function; 1 is display white).
pub const AUTO_TARGET: f64 = 0.9;
/// Where the filmic curve's metering puts the subject's median luminance (AgX shows it at half the code range).
pub const MIDDLE_GREY: f64 = 0.18;
/// The filmic metering's headroom: the 99.5th percentile of the metered pixels at most this many stops over
/// display white (AgX shows 4 at 0.93 of the code range; on the default snake, 2 stops kept 5.3 % of its pixels
/// in diffraction's colours where the median at middle grey alone, 1.8 stops brighter, kept 3.8 %).
pub const GLINT_HEADROOM_EV: f64 = 2.0;
/// The most stops an exposure may be set to either way (a flag, a scene's `exposure_ev`): 2^100 takes any radiance
/// f32 holds from black to white.
pub const MAX_EXPOSURE_EV: f64 = 100.0;
/// The auto exposure stays within ±this many stops (a frame lit at 2^-40 is a bug, not a dark scene).
pub const AUTO_LIMIT_EV: f64 = 40.0;
/// A pixel counts as black when no channel of its 8-bit sRGB value exceeds this (5 %: linear 0.004).
pub const BLACK_CODE: u8 = 12;
/// A frame is "almost all black" when at least this fraction of its pixels are.
pub const BLACK_FRACTION: f64 = 0.99;
/// A frame is "mostly white" when at least this fraction of its lit pixels clip (a channel within a code value of
/// the tone curve's top: 255 for clip, 250 for AgX, whose fit tops out at 0.982).
pub const WHITE_FRACTION: f64 = 0.5;

/// An exposure measured from a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoExposure {
    /// The exposure in stops.
    pub ev: f64,
    /// The value metered, linear (a white mirror under the light is 1): the 99.5th percentile of the pixels'
    /// brightest channel (clip: no more than half a percent of them clip a channel), or the median of their
    /// luminance (filmic).
    pub luminance: f64,
    /// How many pixels were metered (lit: Y > 0).
    pub lit: usize,
    /// The tone curve it was metered for.
    pub tone: Tone,
    /// Filmic: the median's exposure was lowered to keep the 99.5th percentile within the curve.
    pub held: bool,
    /// Which pixels were metered.
    pub metered: Metered,
}

/// The pixels an exposure was metered on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metered {
    /// Every lit pixel (no coverage was given).
    Lit,
    /// The objects' pixels (those the objects cover at least half of).
    Objects,
    /// No object is in view: the lit pixels, which are the sky's or the background's.
    Background,
}

impl AutoExposure {
    /// Measures linear RGBA (rows of pixels, 4 floats each) for the clip curve, on each lit pixel's brightest
    /// channel; None where no pixel is lit or finite.
    pub fn of(rgba: &[f32]) -> Option<Self> {
        Self::metered(rgba.chunks_exact(4).map(|p| metered_value(p, Tone::Clip)), Tone::Clip)
    }

    /// Measures pixels' luminances (Y; the profiler's exact reference gives XYZ) by the clip curve's rule; None
    /// where none is lit.
    pub fn of_luminance(values: impl Iterator<Item = f64>) -> Option<Self> {
        Self::metered(values, Tone::Clip)
    }

    /// Measures pixels' luminances as `tone` needs (see the module's note); None where none is lit.
    pub fn metered(values: impl Iterator<Item = f64>, tone: Tone) -> Option<Self> {
        let mut lit: Vec<f64> = values.filter(|y| y.is_finite() && *y > 0.0).collect();
        let count = lit.len();
        let top = crate::io::stats::percentile(&mut lit, AUTO_QUANTILE);
        if count == 0 || top.is_nan() || top <= 0.0 {
            return None;
        }
        let (ev, luminance, held) = match tone {
            Tone::Clip => ((AUTO_TARGET / top).log2(), top, false),
            Tone::Filmic => {
                let median = crate::io::stats::percentile(&mut lit, 0.5);
                let grey = (MIDDLE_GREY / median).log2();
                let ceiling = GLINT_HEADROOM_EV - top.log2();
                (grey.min(ceiling), median, ceiling < grey)
            }
        };
        let ev = ev.clamp(-AUTO_LIMIT_EV, AUTO_LIMIT_EV);
        Some(Self { ev, luminance, lit: count, tone, held, metered: Metered::Lit })
    }

    /// One line for the user: the exposure and where it came from.
    pub fn describe(&self) -> String {
        let pixels = match self.metered {
            Metered::Lit => "the lit pixels'",
            Metered::Objects => "the objects' pixels'",
            Metered::Background => "the lit pixels'",
        };
        let how = match (self.tone, self.held) {
            (Tone::Clip, _) => format!(
                "the 99.5th percentile of {pixels} brightest channel, {:.4e}, shown at {AUTO_TARGET}",
                self.luminance
            ),
            (Tone::Filmic, false) => {
                format!("the median of {pixels} luminance, {:.4e}, shown at middle grey {MIDDLE_GREY}", self.luminance)
            }
            (Tone::Filmic, true) => format!(
                "the median of {pixels} luminance, {:.4e}, below middle grey so that their 99.5th percentile stays \
                 within {GLINT_HEADROOM_EV} stops over white",
                self.luminance
            ),
        };
        let note = match self.metered {
            Metered::Background => "; no object is in view, so they are the sky's or the background's",
            _ => "",
        };
        format!("exposure {:+.2} EV, measured ({how}{note}; --exposure EV or [render] exposure_ev sets one)", self.ev)
    }
}

/// The exposure of `rgba` (linear RGBA) measured for `tone`, or 0 EV where nothing in it is lit, with the line
/// that tells the user which (`what` names the frame: "the first frame", "the map"). `coverage`: the share of each
/// pixel that objects cover (the alpha of the same view drawn without a background: `render::capture`), where the
/// caller has it; pixels at least half covered are the subject metered.
pub fn measure(rgba: &[f32], coverage: Option<&[f32]>, what: &str, tone: Tone) -> (f64, String) {
    let values = || rgba.chunks_exact(4).map(|p| metered_value(p, tone));
    let auto = match coverage {
        Some(alpha) => {
            let subject = values().zip(alpha.chunks_exact(4)).filter(|(_, a)| a[3] >= 0.5).map(|(y, _)| y);
            match AutoExposure::metered(subject, tone) {
                Some(a) => Some(AutoExposure { metered: Metered::Objects, ..a }),
                // No object in view (a camera looking at the sky): the sky or the background is the picture.
                None => {
                    AutoExposure::metered(values(), tone).map(|a| AutoExposure { metered: Metered::Background, ..a })
                }
            }
        }
        None => AutoExposure::metered(values(), tone),
    };
    match auto {
        Some(auto) => (auto.ev, auto.describe()),
        None => (0.0, format!("warning: nothing in {what} is lit, so no exposure can be measured: 0 EV")),
    }
}

/// What a pixel (linear RGBA) is metered by for `tone`: clip meters its brightest channel, so that the frame it
/// exposes clips no channel but in its brightest half percent (a saturated blue metered by its luminance would
/// clip its blue everywhere); the filmic curve meters its luminance, which it rolls off.
fn metered_value(p: &[f32], tone: Tone) -> f64 {
    match tone {
        Tone::Clip => f64::from(p[0].max(p[1]).max(p[2])),
        Tone::Filmic => luminance([p[0], p[1], p[2]]),
    }
}

/// Whether a frame shown at `exposure_ev` through `tone` is almost all black (its pixels, background included) or mostly white
/// (its lit pixels: a black background does not make a blown-out object well exposed): the warning line, or None.
pub fn verdict(rgba: &[f32], exposure_ev: f64, tone: Tone) -> Option<String> {
    let scale = exposure_ev.exp2();
    let (mut black, mut white, mut lit, mut total) = (0usize, 0usize, 0usize, 0usize);
    // The code a channel reaches under the brightest light, less one: at or above it, the channel is clipped.
    let top = encode(glam::DVec3::splat(1e30), 1.0, tone).into_iter().min().unwrap_or(255).saturating_sub(1);
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
            if shown.iter().any(|&c| c >= top) {
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

    /// Filmic metering: the subject's median at middle grey, unless its glints would pass the curve's top; only
    /// the covered pixels count where the coverage is given (a bright sky behind does not darken the subject).
    #[test]
    fn the_filmic_meter_puts_the_subject_at_middle_grey_and_keeps_its_glints() {
        // A subject of 0.02 with 0.4 % glints 20× brighter, behind it a sky of 1.0 over three times its area.
        let mut values = vec![0.02; 996];
        values.extend([0.4; 4]);
        let subject = values.len();
        values.extend(std::iter::repeat_n(1.0, 3000));
        let rgba = frame(&values);
        let coverage: Vec<f32> =
            (0..values.len()).flat_map(|i| [0.0, 0.0, 0.0, f32::from(u8::from(i < subject))]).collect();
        let (ev, line) = measure(&rgba, Some(&coverage), "the frame", Tone::Filmic);
        assert!((ev - (MIDDLE_GREY / 0.02).log2()).abs() < 1e-6, "{ev}: {line}");
        assert!(line.contains("median of the objects' pixels'") && line.contains("middle grey"), "{line}");
        // Without the coverage the sky is the median, and the subject comes out five stops darker.
        let (all, _) = measure(&rgba, None, "the frame", Tone::Filmic);
        assert!((all - (MIDDLE_GREY / 1.0).log2()).abs() < 1e-9, "{all}");
        // Glints 10⁴× the median: the exposure is held so that they stay on the curve's shoulder.
        let mut harsh = vec![0.02; 990];
        harsh.extend([200.0; 10]);
        let auto = AutoExposure::metered(harsh.iter().copied(), Tone::Filmic).unwrap();
        assert!(auto.held && (auto.ev - (GLINT_HEADROOM_EV - 200f64.log2())).abs() < 1e-9, "{auto:?}");
        assert!(auto.describe().contains("stays within 2 stops over white"), "{}", auto.describe());
    }

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
        let (ev, line) = measure(&frame(&[0.0; 100]), None, "the map", Tone::Clip);
        assert!(ev == 0.0 && line.starts_with("warning: nothing in the map is lit"), "{ev} {line}");
        assert!(measure(&frame(&[0.01; 4]), None, "the map", Tone::Clip).1.contains("measured"));
        let dim = frame(&[0.001; 100]);
        assert!(verdict(&dim, 0.0, Tone::Clip).unwrap().contains("almost all black"));
        assert!(verdict(&dim, 20.0, Tone::Clip).unwrap().contains("mostly white"));
        // AgX never reaches 255: its top (250) counts as clipped.
        assert!(verdict(&dim, 20.0, Tone::Filmic).unwrap().contains("mostly white"));
        assert!(verdict(&dim, 10.0, Tone::Filmic).is_none(), "0.001 at +10 EV is 1.02: on AgX's shoulder");
        assert!(verdict(&dim, AutoExposure::of(&dim).unwrap().ev, Tone::Clip).is_none());
        // A blown-out object on a black background is white where it is lit.
        let mut spot = frame(&[0.0; 90]);
        spot.extend(frame(&[0.5; 10]));
        assert!(verdict(&spot, 8.0, Tone::Clip).unwrap().contains("mostly white"));
    }

    #[test]
    fn a_frame_without_objects_is_metered_on_its_sky_and_clip_clips_no_colour() {
        // A camera that sees no object (looking up): the coverage is empty, and the sky it shows is the picture.
        let sky = frame(&[0.2; 100]);
        let nothing = vec![0.0f32; sky.len()];
        for tone in Tone::ALL {
            let (ev, line) = measure(&sky, Some(&nothing), "the first frame", tone);
            assert!(ev.is_finite() && line.contains("no object is in view"), "{tone:?}: {ev} {line}");
            assert!(verdict(&sky, ev, tone).is_none(), "{tone:?}: {ev}");
        }
        // Nothing lit at all is still nothing.
        let black = frame(&[0.0; 100]);
        assert!(measure(&black, Some(&nothing), "the first frame", Tone::Filmic)
            .1
            .contains("nothing in the first frame"));
        // A saturated blue frame: clip's meter and its verdict agree (metered by luminance, its blue clipped
        // everywhere and the verdict called it mostly white).
        let blue: Vec<f32> = (0..100).flat_map(|_| [0.0, 0.0, 0.3, 1.0]).collect();
        let (ev, line) = measure(&blue, None, "the map", Tone::Clip);
        assert!(verdict(&blue, ev, Tone::Clip).is_none(), "{ev}: {line}");
        assert!((ev - (AUTO_TARGET / 0.3).log2()).abs() < 1e-6 && line.contains("brightest channel"), "{ev} {line}");
    }
}
