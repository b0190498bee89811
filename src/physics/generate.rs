//! Nanostructure generators in physical units (µm), deterministic for a given seed: gratings with closed-form
//! spectra for tests and demonstrations, a CD-like track grating, and finger structures after the snake scales
//! the thesis measured (model.md §5.1: Elaphe ≈ 1.14 µm period, 0.375 µm high; Xenopeltis ≈ 1.55 µm, 0.44 µm).
//!
//! Orientation follows the AFM scans (`assets/afm/README.md`): gratings vary along x (their orders lie
//! along the BRDF map's x axis); Elaphe's ridges run along x and repeat along y; Xenopeltis's finger layers
//! repeat along x (1.55 µm) with fingers 0.65 µm apart along y.

use crate::error::{Error, Result};
use crate::physics::heightfield::{check_dims, HeightField};

/// The structures `diffract gen patch` makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum PatchKind {
    /// h = H/2·(1 + cos 2πx/d): a sinusoidal phase grating (orders of power J_m²)
    Sinusoidal,
    /// h = H·frac(x/d): a blazed (sawtooth) grating
    Blazed,
    /// Tracks 1.6 µm apart along y, each with pits of random length (a CD's data side)
    Cd,
    /// Overlapping fingers stacked along y, ≈1.14 µm apart, of random length along x (Elaphe guttata)
    Elaphe,
    /// Layers ≈1.55 µm apart along x of tapering fingers ≈0.65 µm apart along y, each layer shifted and slightly
    /// tilted (Xenopeltis unicolor)
    Xenopeltis,
    /// A flat mirror
    Flat,
}

impl PatchKind {
    /// (period µm, height µm) when the user gives none.
    pub fn defaults(self) -> (f64, f64) {
        match self {
            PatchKind::Sinusoidal => (2.0, 0.2),
            PatchKind::Blazed => (2.5, 0.25),
            PatchKind::Cd => (1.6, 0.12),
            PatchKind::Elaphe => (1.14, 0.375),
            PatchKind::Xenopeltis => (1.55, 0.44),
            PatchKind::Flat => (1.0, 0.0),
        }
    }
}

/// What to generate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchSpec {
    pub kind: PatchKind,
    /// Edge lengths in µm.
    pub width_um: f64,
    pub height_um_extent: f64,
    pub pixel_um: f64,
    pub period_um: f64,
    /// Peak-to-valley height in µm.
    pub depth_um: f64,
    pub seed: u64,
}

impl PatchSpec {
    /// A square patch of `size_um` with the kind's default period and height.
    pub fn new(kind: PatchKind, size_um: f64, pixel_um: f64) -> Self {
        let (period_um, depth_um) = kind.defaults();
        Self { kind, width_um: size_um, height_um_extent: size_um, pixel_um, period_um, depth_um, seed: 1 }
    }
}

/// A small deterministic generator (PCG-style LCG with an xorshift output).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let x = (self.0 ^ (self.0 >> 33)).wrapping_mul(0xff51afd7ed558ccd);
        (x >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Generates the patch.
pub fn generate(spec: &PatchSpec) -> Result<HeightField> {
    for (name, v) in [
        ("size", spec.width_um),
        ("size", spec.height_um_extent),
        ("pixel size", spec.pixel_um),
        ("period", spec.period_um),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::setting(
                "patch",
                format!("the {name} must be a positive number of µm, got {}", crate::error::number(v)),
            ));
        }
    }
    if !(spec.depth_um.is_finite() && spec.depth_um >= 0.0) {
        return Err(Error::setting(
            "height_um",
            format!("the height must be a non-negative number of µm, got {}", spec.depth_um),
        ));
    }
    let nx = (spec.width_um / spec.pixel_um).round().max(1.0);
    let ny = (spec.height_um_extent / spec.pixel_um).round().max(1.0);
    check_dims(nx as u64, ny as u64)?;
    if spec.period_um < 2.0 * spec.pixel_um && spec.kind != PatchKind::Flat {
        return Err(Error::setting(
            "period_um",
            format!(
                "a {} µm period is not resolved by {} µm pixels (at least two pixels per period)",
                crate::error::number(spec.period_um),
                crate::error::number(spec.pixel_um)
            ),
        ));
    }
    let (nx, ny) = (nx as usize, ny as usize);
    let (d, hgt, p) = (spec.period_um, spec.depth_um, spec.pixel_um);
    let mut rng = Rng(spec.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15).wrapping_add(0x2545_F491));
    let heights: Vec<f64> = match spec.kind {
        PatchKind::Flat => vec![0.0; nx * ny],
        PatchKind::Sinusoidal => {
            grid(nx, ny, |c, _| 0.5 * hgt * (1.0 + (std::f64::consts::TAU * c as f64 * p / d).cos()))
        }
        PatchKind::Blazed => grid(nx, ny, |c, _| hgt * (c as f64 * p / d).rem_euclid(1.0)),
        PatchKind::Cd => cd(nx, ny, p, d, hgt, &mut rng),
        PatchKind::Elaphe => fingers(nx, ny, p, d, hgt, &mut rng),
        PatchKind::Xenopeltis => layers(nx, ny, p, d, hgt, &mut rng),
    };
    HeightField::new(nx, ny, p, p, heights)
}

fn grid(nx: usize, ny: usize, f: impl Fn(usize, usize) -> f64) -> Vec<f64> {
    (0..nx * ny).map(|i| f(i % nx, i / nx)).collect()
}

/// CD data tracks: along y, `pitch` apart in x; pits of random length 0.83–3.05 µm (the CD standard's 3T–11T)
/// separated by lands of the same range, 0.5 µm wide, `depth` deep, smoothed edges.
fn cd(nx: usize, ny: usize, p: f64, pitch: f64, depth: f64, rng: &mut Rng) -> Vec<f64> {
    let (_, ly) = (nx as f64 * p, ny as f64 * p);
    let tracks = ((nx as f64 * p) / pitch).ceil() as usize + 1;
    let mut h = vec![0.0f64; nx * ny];
    for t in 0..tracks {
        let xc = (t as f64 + 0.5) * pitch;
        let mut y = rng.range(0.0, 2.0);
        while y < ly {
            let len = rng.range(0.83, 3.05);
            for r in 0..ny {
                let yy = r as f64 * p;
                if yy < y || yy > y + len {
                    continue;
                }
                for c in 0..nx {
                    let dx = (c as f64 * p - xc).abs();
                    // A pit 0.5 µm wide with 0.1 µm sloped walls.
                    let w = ((0.35 - dx) / 0.1).clamp(0.0, 1.0);
                    h[r * nx + c] = h[r * nx + c].max(depth * w);
                }
            }
            y += len + rng.range(0.83, 3.05);
        }
    }
    h
}

/// Rows of fingers stacked along y with period `d`: each finger is a segment along x of random length with a
/// small random offset across, and a profile across that rises steeply and falls slowly (overlapping scales).
fn fingers(nx: usize, ny: usize, p: f64, d: f64, hgt: f64, rng: &mut Rng) -> Vec<f64> {
    const LENGTH_UM: (f64, f64) = (2.0, 6.0);
    // The rows wander across by up to WANDER·d over a few µm, as the ridges of the AFM scan do: the local
    // orientation of the grating varies by several degrees, which spreads its orders along the ridges.
    const WANDER: f64 = 0.12;
    const WANDER_PERIOD_UM: (f64, f64) = (4.0, 9.0);
    let (lx, ly) = (nx as f64 * p, ny as f64 * p);
    let mut h = vec![0.0f64; nx * ny];
    let rows = (ly / d).ceil() as i64 + 2;
    for k in -1..rows {
        let (wander_period, wander_phase) = (rng.range(WANDER_PERIOD_UM.0, WANDER_PERIOD_UM.1), rng.range(0.0, 6.3));
        let mut x = -rng.range(0.0, LENGTH_UM.1);
        while x < lx {
            let len = rng.range(LENGTH_UM.0, LENGTH_UM.1);
            let y0 = k as f64 * d + rng.range(-0.08, 0.08) * d;
            let width = d;
            let (c0, c1) = (((x / p).floor().max(0.0)) as usize, (((x + len) / p).ceil().min(nx as f64)) as usize);
            for c in c0..c1 {
                let xx = c as f64 * p;
                // Round the finger's ends over 0.3 µm.
                let end = ((xx - x).min(x + len - xx) / 0.3).clamp(0.0, 1.0);
                let yc = y0 + WANDER * d * (std::f64::consts::TAU * xx / wander_period + wander_phase).sin();
                let (r0, r1) =
                    (((yc / p).floor().max(0.0)) as usize, (((yc + width) / p).ceil().min(ny as f64)) as usize);
                for r in r0..r1 {
                    let t = (r as f64 * p - yc) / width;
                    // Steep rise over the first 15 %, slow fall after it.
                    let profile = if t < 0.15 { t / 0.15 } else { (1.0 - t) / 0.85 };
                    let v = hgt * profile.clamp(0.0, 1.0) * end;
                    let i = r * nx + c;
                    h[i] = h[i].max(v);
                }
            }
            x += len + rng.range(0.1, 0.6);
        }
    }
    h
}

/// Xenopeltis: layers `d` apart along x, each a comb of fingers 0.42·d apart along y that taper from base (left)
/// to tip; every layer has its own offset along y and a tilt of up to ±4°, so sub-regions differ slightly in
/// orientation and period (the thesis's "two ridges", model.md §6.1).
fn layers(nx: usize, ny: usize, p: f64, d: f64, hgt: f64, rng: &mut Rng) -> Vec<f64> {
    let (lx, ly) = (nx as f64 * p, ny as f64 * p);
    let spacing = 0.42 * d;
    let mut h = vec![0.0f64; nx * ny];
    let count = (lx / d).ceil() as i64 + 1;
    for k in -1..count {
        let x0 = k as f64 * d + rng.range(-0.05, 0.05) * d;
        let offset = rng.range(0.0, spacing);
        let tilt = rng.range(-4.0, 4.0).to_radians().tan();
        let length = 0.85 * d;
        let (c0, c1) = (((x0 / p).floor().max(0.0)) as usize, (((x0 + length) / p).ceil().min(nx as f64)) as usize);
        for c in c0..c1 {
            let along = (c as f64 * p - x0) / length;
            if !(0.0..=1.0).contains(&along) {
                continue;
            }
            // Thick at the base, thin at the tip, and much lower there: the layers dominate the spectrum
            // along x as in the AFM scan (1.6 µm along x is its strongest frequency).
            let half_width = spacing * (0.48 - 0.18 * along);
            let top = hgt * (1.0 - 0.75 * along);
            for r in 0..ny {
                let y = r as f64 * p - offset - (c as f64 * p - x0) * tilt;
                let across = (y - (y / spacing).round() * spacing).abs();
                if across < half_width && r as f64 * p < ly {
                    let v = top * (0.5 + 0.5 * (std::f64::consts::PI * across / half_width).cos());
                    let i = r * nx + c;
                    h[i] = h[i].max(v);
                }
            }
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::dominant_grating;

    #[test]
    fn generators_are_deterministic_and_in_range() {
        for kind in [PatchKind::Sinusoidal, PatchKind::Blazed, PatchKind::Cd, PatchKind::Elaphe, PatchKind::Xenopeltis]
        {
            let spec = PatchSpec::new(kind, 13.0, 0.05);
            let a = generate(&spec).unwrap();
            assert_eq!(a, generate(&spec).unwrap(), "{kind:?} is deterministic");
            let (lo, hi) = a.range();
            assert!(lo >= 0.0 && hi <= spec.depth_um + 1e-12 && hi > 0.5 * spec.depth_um, "{kind:?}: {lo}..{hi}");
            let other = generate(&PatchSpec { seed: 2, ..spec }).unwrap();
            if matches!(kind, PatchKind::Cd | PatchKind::Elaphe | PatchKind::Xenopeltis) {
                assert_ne!(a, other, "{kind:?}: the seed matters");
            }
        }
    }

    #[test]
    fn dominant_periods_are_the_ones_asked_for() {
        for (kind, axis_x) in [
            (PatchKind::Blazed, true),
            (PatchKind::Cd, true),
            (PatchKind::Elaphe, false),
            (PatchKind::Xenopeltis, true),
        ] {
            let spec = PatchSpec::new(kind, 32.0, 0.05);
            let (gx, gy, d) = dominant_grating(&generate(&spec).unwrap());
            assert!((d / spec.period_um - 1.0).abs() < 0.06, "{kind:?}: period {d} vs {}", spec.period_um);
            assert!(if axis_x { gx.abs() > 0.95 } else { gy.abs() > 0.95 }, "{kind:?}: direction ({gx}, {gy})");
        }
    }

    #[test]
    fn bad_specs_are_refused() {
        let mut s = PatchSpec::new(PatchKind::Blazed, 10.0, 0.05);
        s.period_um = 0.05;
        assert!(generate(&s).is_err(), "unresolved period");
        s.period_um = -1.0;
        assert!(generate(&s).is_err());
        assert!(generate(&PatchSpec::new(PatchKind::Blazed, 1e6, 0.01)).is_err(), "absurd size");
    }
}
