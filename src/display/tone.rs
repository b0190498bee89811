//! The tone curve: how linear light, after the exposure, becomes a display's code values (8-bit PNGs and a
//! window; EXR stays linear and scene-referred). Twin of `glsl/include/display.glsl` (same names, same constants).
//!
//! - [`Tone::Clip`]: the sRGB transfer function on each channel, clipped at 1: linear light shown as it is up to
//!   display white, every stop above it white.
//! - [`Tone::Filmic`]: AgX (T. Sobotka's, the base look of Blender 4's "AgX" view): the light is inset towards the
//!   achromatic axis (so that saturated colours — a grating's spectral ones — desaturate towards white as they
//!   brighten instead of clipping one channel first), encoded in log₂ over 16.5 stops (from 12.47 below linear 1
//!   to 4.03 above), passed through AgX's sigmoid, and outset again. Middle grey (0.18) shows
//!   at 0.50, display white (1) at 0.78, and 16 at 0.98: four stops of highlights that clipping would lose. The
//!   sigmoid is a 7th-order polynomial fit to AgX's curve and the matrices are AgX's, both as published by
//!   B. Wrensch, "Minimal AgX implementation" (2023, MIT licence), from Sobotka's OCIO configuration.

use glam::{DMat3, DVec3};

/// How linear light becomes display values. The library's default is the transfer function alone (`Clip`); the
/// commands `render` and `view` show `Filmic` unless told otherwise, `map` (a plot of the BRDF) `Clip`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Tone {
    /// The sRGB transfer function, clipped at display white.
    #[default]
    Clip,
    /// AgX's filmic curve: highlights roll off over four stops, saturated colours desaturate as they brighten.
    Filmic,
}

impl Tone {
    pub const ALL: [Tone; 2] = [Tone::Filmic, Tone::Clip];

    pub fn name(self) -> &'static str {
        match self {
            Tone::Clip => "clip",
            Tone::Filmic => "filmic",
        }
    }

    /// The shaders' value of it (`params.display.y`, `background.display.y`: display.glsl's `tone`).
    pub fn gpu(self) -> f32 {
        match self {
            Tone::Clip => 0.0,
            Tone::Filmic => 1.0,
        }
    }

    /// Display values in [0, 1] (sRGB-encoded) of linear RGB already scaled by the exposure.
    pub fn encode(self, linear: DVec3) -> DVec3 {
        match self {
            Tone::Clip => linear.to_array().map(crate::physics::spectrum::srgb_oetf).into(),
            Tone::Filmic => agx(linear),
        }
    }
}

impl std::str::FromStr for Tone {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Tone::ALL
            .into_iter()
            .find(|t| t.name() == text)
            .ok_or_else(|| format!("unknown tone {text:?}: the choices are filmic and clip"))
    }
}

/// AgX's inset: linear sRGB towards the achromatic axis (columns as in display.glsl's `AGX_INSET`).
const AGX_INSET: [[f64; 3]; 3] = [
    [0.842479062253094, 0.0423282422610123, 0.0423756549057051],
    [0.0784335999999992, 0.878468636469772, 0.0784336],
    [0.0792237451477643, 0.0791661274605434, 0.879142973793104],
];
/// AgX's outset (the inset's inverse), columns.
const AGX_OUTSET: [[f64; 3]; 3] = [
    [1.19687900512017, -0.0528968517574562, -0.0529716355144438],
    [-0.0980208811401368, 1.15190312990417, -0.0980434501171241],
    [-0.0990297440797205, -0.0989611768448433, 1.15107367264116],
];
/// The stops AgX's log encoding spans, about linear 1.
pub const AGX_MIN_EV: f64 = -12.47393;
pub const AGX_MAX_EV: f64 = 4.026069;
/// AgX's sigmoid on the encoded value x ∈ [0, 1], highest power first (x⁷ … x⁰).
const AGX_SIGMOID: [f64; 8] = [-17.86, 78.01, -126.7, 92.06, -28.72, 4.361, -0.1718, 0.002857];

/// AgX's display values (sRGB-encoded, in [0, 1]) of linear sRGB `linear` (after the exposure).
pub fn agx(linear: DVec3) -> DVec3 {
    let inset = DMat3::from_cols_array_2d(&AGX_INSET) * linear;
    let encoded = inset.to_array().map(|c| {
        let x = (c.max(1e-10).log2().clamp(AGX_MIN_EV, AGX_MAX_EV) - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV);
        AGX_SIGMOID.iter().fold(0.0, |sum, a| sum * x + a)
    });
    (DMat3::from_cols_array_2d(&AGX_OUTSET) * DVec3::from(encoded)).clamp(DVec3::ZERO, DVec3::ONE)
}

/// The shaders' display uniform (`params.display`, `background.display`): 2^EV, the tone curve
/// ([`Tone::gpu`]), 0, 0.
pub fn display_uniform(exposure_ev: f64, tone: Tone) -> [f32; 4] {
    [exposure_ev.exp2() as f32, tone.gpu(), 0.0, 0.0]
}

/// 8-bit sRGB of linear RGB after `exposure_scale` (2^EV) and the tone curve.
pub fn encode(linear: DVec3, exposure_scale: f64, tone: Tone) -> [u8; 3] {
    tone.encode(linear * exposure_scale).to_array().map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// Linear scene-referred RGBA floats → display-referred 8-bit sRGB RGBA after `exposure_ev` stops and `tone`.
pub fn to_rgba8(rgba: &[f32], exposure_ev: f64, tone: Tone) -> Vec<u8> {
    let scale = exposure_ev.exp2();
    rgba.chunks(4)
        .flat_map(|p| {
            let [r, g, b] = encode(DVec3::new(p[0].into(), p[1].into(), p[2].into()), scale, tone);
            [r, g, b, 255]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// AgX's anchors: middle grey 0.18 at about 0.50 (its log encoding puts 0.18 at 0.606, where the curve's
    /// pivot lies), display white 1 at about 0.78, black at 0, 16 (four stops over) within 2 % of white;
    /// a grey stays grey (the matrices' rows sum to 1) and the curve rises everywhere.
    #[test]
    fn agx_keeps_grey_grey_and_rolls_highlights_off() {
        let grey = |v: f64| agx(DVec3::splat(v));
        assert!((grey(0.18).x - 0.497).abs() < 0.01, "{}", grey(0.18));
        assert!((grey(1.0).x - 0.783).abs() < 0.01, "{}", grey(1.0));
        assert!(grey(0.0).max_element() < 0.003, "{}", grey(0.0));
        assert!(grey(16.0).min_element() > 0.98, "{}", grey(16.0));
        for v in [0.001, 0.05, 0.18, 1.0, 5.0] {
            let g = grey(v);
            assert!((g.x - g.y).abs() < 1e-3 && (g.y - g.z).abs() < 1e-3, "{v}: {g}");
        }
        // It rises from 2⁻¹² up (below, the fit dips by 0.002 of the range, half a code value, to its minimum at
        // 2⁻¹²·¹: a fit's wiggle near black, not AgX's).
        let mut last = -1.0;
        for k in -120..=50 {
            let y = grey(2f64.powf(f64::from(k) / 10.0)).y;
            assert!(y >= last - 1e-9, "falls at 2^{}: {y} after {last}", f64::from(k) / 10.0);
            last = y;
        }
        // The inset and outset are each other's inverse.
        let m = DMat3::from_cols_array_2d(&AGX_INSET) * DMat3::from_cols_array_2d(&AGX_OUTSET);
        assert!(m.abs_diff_eq(DMat3::IDENTITY, 1e-9), "{m}");
    }

    /// A saturated colour brightened past white: clipping loses it (here to white, every channel at 255), AgX
    /// desaturates it towards white while keeping its hue's order of channels.
    #[test]
    fn agx_desaturates_bright_spectral_colours_and_clip_clips_them() {
        let blue = DVec3::new(0.02, 0.1, 1.0);
        let dim = agx(blue * 0.1);
        let bright = agx(blue * 64.0);
        let saturation = |c: DVec3| (c.max_element() - c.min_element()) / c.max_element();
        assert!(saturation(bright) < 0.5 * saturation(dim), "{dim} → {bright}");
        assert!(bright.z >= bright.y && bright.y >= bright.x, "{bright}");
        assert_eq!(encode(blue * 64.0, 1.0, Tone::Clip), [255, 255, 255]);
        assert_eq!(encode(DVec3::splat(0.5), 1.0, Tone::Clip), [188; 3], "clip is the sRGB transfer function");
        assert_eq!(encode(DVec3::splat(0.5), 2.0, Tone::Clip), [255; 3], "after the exposure");
        assert_eq!(encode(DVec3::new(f64::NAN, 0.0, 0.0), 1.0, Tone::Clip)[0], 0, "a NaN channel shows black");
        assert_eq!("filmic".parse::<Tone>(), Ok(Tone::Filmic));
        assert!("aces".parse::<Tone>().unwrap_err().contains("filmic and clip"));
    }
}
