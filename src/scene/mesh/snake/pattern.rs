//! The corn snake's pattern over the body — saddles with dark borders, flank blotches, a cream belly, the head's
//! stripes and spear point — as tints of the material's pigment.

use crate::scene::mesh::snake::{Pattern, Random, CORN_BELLY, CORN_BORDER, CORN_GROUND, CORN_SADDLE, HEAD_START};
use crate::scene::mesh::UNTINTED;

/// The skin's pattern over the body: per scale, a tint of [`CORN_GROUND`].
pub(super) struct PatternField {
    pattern: Pattern,
    /// Saddle centres along the body and their sideways wobble (radians).
    saddles: Vec<(f32, f32)>,
}

/// Saddles on the body and tail (a corn snake has some 30–45 on a body of ~230 scale rows; this body has fewer
/// rows, and a saddle must span several of them to read as one).
const SADDLES: usize = 24;
/// Where the saddles run along the body (t).
const SADDLE_SPAN: (f32, f32) = (0.06, 0.9);

impl PatternField {
    pub(super) fn new(pattern: Pattern, seed: u64) -> Self {
        let mut random = Random::new(seed ^ 0x5ADD1E);
        let spacing = (SADDLE_SPAN.1 - SADDLE_SPAN.0) / SADDLES as f32;
        let saddles = (0..SADDLES)
            .map(|k| (SADDLE_SPAN.0 + (k as f32 + 0.5 + 0.15 * random.next()) * spacing, 0.12 * random.next()))
            .collect();
        Self { pattern, saddles }
    }

    /// The tints of an eye's pupil and iris (none for the plain pattern).
    pub(super) fn eye_tints(&self) -> ([f32; 3], [f32; 3]) {
        if self.pattern == Pattern::Plain {
            return (UNTINTED, UNTINTED);
        }
        (relative_to_ground(CORN_BORDER), relative_to_ground(CORN_SADDLE))
    }

    /// The tint at t along the body and angle a around it.
    pub(super) fn tint(&self, t: f32, a: f32) -> [f32; 3] {
        if self.pattern == Pattern::Plain {
            return UNTINTED;
        }
        relative_to_ground(self.colour(t, a))
    }

    fn colour(&self, t: f32, a: f32) -> [f32; 3] {
        // Angle from the middle of the back, −π..π.
        let from_top = (a - std::f32::consts::FRAC_PI_2 + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU)
            - std::f32::consts::PI;
        if from_top.abs() > 2.3 {
            return CORN_BELLY;
        }
        // (The eyes are geometry: `eye`.) A dark-edged stripe from each eye back to the jaw, and the spear point on the crown, pointing at the snout.
        let stripe = ((t - 0.952) / 0.02).powi(2) + ((from_top.abs() - 1.2) / 0.14).powi(2);
        if stripe < 1.0 {
            return if stripe < 0.45 { CORN_SADDLE } else { CORN_BORDER };
        }
        if (HEAD_START - 0.01..0.975).contains(&t) {
            let half = 0.7 * (0.975 - t) / (0.975 - HEAD_START);
            match from_top.abs() / half {
                d if d < 0.8 => return CORN_SADDLE,
                d if d < 1.0 => return CORN_BORDER,
                _ => {}
            }
        }
        let spacing = (SADDLE_SPAN.1 - SADDLE_SPAN.0) / SADDLES as f32;
        // The nearest saddle on the back, and the nearest blotch on the flanks (between two saddles).
        let mut nearest = f32::INFINITY;
        for &(centre, wobble) in &self.saddles {
            let dorsal = ((t - centre) / (0.3 * spacing)).powi(2) + ((from_top - wobble) / 0.85).powi(2);
            let lateral =
                ((t - centre - 0.5 * spacing) / (0.18 * spacing)).powi(2) + ((from_top.abs() - 1.65) / 0.3).powi(2);
            nearest = nearest.min(dorsal).min(lateral);
        }
        match nearest.sqrt() {
            d if d < 1.0 => CORN_SADDLE,
            d if d < 1.3 => CORN_BORDER,
            _ => CORN_GROUND,
        }
    }
}

/// A pattern colour as a tint of the material's pigment, the corn snake's ground colour.
pub(super) fn relative_to_ground(colour: [f32; 3]) -> [f32; 3] {
    [colour[0] / CORN_GROUND[0], colour[1] / CORN_GROUND[1], colour[2] / CORN_GROUND[2]]
}
