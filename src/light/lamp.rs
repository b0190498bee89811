//! Lamps: point and spot lights at a position (world units are metres), of a luminous intensity in candela with
//! the scene's illuminant as their spectrum, and a disc's radius (model.md §3.13; its size sets a coherence,
//! §1.13), packed for the surface pass ([`LampUniforms`]). Their GLSL twins, [`spot_factor`] and
//! [`Lamp::light_at`], are glsl/include/lamps.glsl's (same names).

use glam::DVec3;

use crate::physics::coherence::{DEFAULT_COHERENCE_UM, MIN_COHERENCE_UM};
use crate::physics::sky::sun_angular_radius;

/// Whether a material of coherence length `coherence_um` takes each light's own (model.md §3.13): one at sunlight's
/// default does; one set to another length (a structure's own, as the snakes') keeps it under every light.
pub fn follows_light(coherence_um: f64) -> bool {
    coherence_um == DEFAULT_COHERENCE_UM
}

/// The variance in (u, v) that widens a lobe of a material at `material_um` to the lobe of a light of the shorter
/// coherence `light_um` (µm; 0 where the light's is not shorter): the window's lobe has the per-axis standard
/// deviation √2·λ/(π·L) in direction cosines at λ (model.md §1.13), so the difference of the two squares at
/// `WIDENING_LAMBDA_UM`. A normalised blur keeps each lobe's energy, as the window's gain does.
pub fn widening_variance(light_um: f64, material_um: f64) -> f64 {
    let lambda = crate::gpu::interface::WIDENING_LAMBDA_UM;
    let scale = 2.0 * lambda * lambda / (std::f64::consts::PI * std::f64::consts::PI);
    (scale * (1.0 / (light_um * light_um) - 1.0 / (material_um * material_um))).max(0.0)
}

/// A pixel's footprint in (u, v) (its two steps, across and down: `footprint_steps` in glsl/include/footprint.glsl)
/// widened by an isotropic Gaussian of `variance`: the footprint along the principal axes of the pixel's uniform
/// spread (covariance (a·aᵀ + b·bᵀ)/12) plus the Gaussian's, each step √12 times its standard deviation.
pub fn widen_steps(steps: [f64; 4], variance: f64) -> [f64; 4] {
    if variance <= 0.0 {
        return steps;
    }
    let (a, b) = ([steps[0], steps[1]], [steps[2], steps[3]]);
    let p = a[0] * a[0] + b[0] * b[0] + 12.0 * variance;
    let q = a[0] * a[1] + b[0] * b[1];
    let r = a[1] * a[1] + b[1] * b[1] + 12.0 * variance;
    let (mean, half) = (0.5 * (p + r), (0.25 * (p - r) * (p - r) + q * q).sqrt());
    let (major, minor) = (mean + half, (mean - half).max(0.0));
    let e = if q.abs() > 1e-30 {
        let (x, y) = (major - r, q);
        let n = (x * x + y * y).sqrt();
        [x / n, y / n]
    } else if p >= r {
        [1.0, 0.0]
    } else {
        [0.0, 1.0]
    };
    let (s1, s2) = (major.sqrt(), minor.sqrt());
    [e[0] * s1, e[1] * s1, -e[1] * s2, e[0] * s2]
}

/// A spot's beam: where it points and how its edge falls off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    /// Unit vector from the lamp along the beam's axis.
    pub direction: DVec3,
    /// The beam's half-angle, degrees: no light beyond it.
    pub cone_deg: f64,
    /// The edge's width, degrees: the intensity falls from full at cone − soft to none at cone (a smoothstep).
    pub soft_deg: f64,
}

/// A lamp of a scene (`[[lamp]]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lamp {
    /// Where it is, world units (metres).
    pub position: DVec3,
    /// Its luminous intensity along its axis (a spot) or in every direction (a point), cd.
    pub intensity_cd: f64,
    /// The radius of its emitting disc, m: its angular size seen from a surface, hence the light's coherence there.
    /// The inverse-square law treats it as a point (a disc of radius r at distance d differs by r²/d²).
    pub radius_m: f64,
    /// A spot's beam; None for a point lamp, which lights every direction alike.
    pub spot: Option<Spot>,
}

/// The share of a spot's intensity at `angle_deg` from its axis: 1 inside cone − soft, 0 beyond the cone, a
/// smoothstep between (a hard edge where `soft_deg` is 0).
pub fn spot_factor(angle_deg: f64, cone_deg: f64, soft_deg: f64) -> f64 {
    let t = ((cone_deg - angle_deg) / soft_deg.max(1e-6)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

impl Lamp {
    /// Its intensity towards `to` (a unit vector from the lamp), cd.
    pub fn intensity_towards(&self, to: DVec3) -> f64 {
        match self.spot {
            None => self.intensity_cd,
            Some(s) => {
                let angle_deg = to.dot(s.direction).clamp(-1.0, 1.0).acos().to_degrees();
                self.intensity_cd * spot_factor(angle_deg, s.cone_deg, s.soft_deg)
            }
        }
    }

    /// Seen from `point`: the unit vector towards it and its illuminance there at normal incidence, lux:
    /// I/(d² + r²) — the inverse-square law, made finite at the disc (exact on the axis of a Lambertian disc of
    /// radius r).
    pub fn light_at(&self, point: DVec3) -> (DVec3, f64) {
        let to_lamp = self.position - point;
        let d2 = to_lamp.length_squared();
        let l = to_lamp / d2.sqrt();
        (l, self.intensity_towards(-l) / (d2 + self.radius_m * self.radius_m))
    }

    /// The illuminance it gives a surface at `point` facing `normal` (unit), lux: [`Self::light_at`]'s times
    /// cos θ, 0 from behind.
    pub fn illuminance(&self, point: DVec3, normal: DVec3) -> f64 {
        let (l, e) = self.light_at(point);
        e * l.dot(normal).max(0.0)
    }

    /// Its angular radius seen from `point`, radians.
    pub fn angular_radius_at(&self, point: DVec3) -> f64 {
        self.radius_m.atan2((self.position - point).length())
    }

    /// The coherence length its light has at `point`, µm: sunlight's [`DEFAULT_COHERENCE_UM`] times the sun's
    /// angular radius over its own there (`coherence::of_light`, model.md §1.13), at least [`MIN_COHERENCE_UM`].
    pub fn coherence_at(&self, point: DVec3) -> f64 {
        (DEFAULT_COHERENCE_UM * sun_angular_radius() / self.angular_radius_at(point)).max(MIN_COHERENCE_UM)
    }
}

/// The lamps as the surface pass reads them (`SurfaceUniforms::lamp_count` and `lamps`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LampUniforms {
    pub count: [f32; 4],
    pub lamps: [[f32; 4]; 24],
}

impl LampUniforms {
    /// No lamp.
    pub const NONE: Self = Self { count: [0.0; 4], lamps: [[0.0; 4]; 24] };

    /// `lamps` (at most `MAX_LAMPS`, which a scene is held to), their intensities divided by the frame's unit of
    /// luminance `unit_cd_m2` (`Scene::unit_luminance`): in m² of that unit, so that over d² they are the
    /// irradiance per unit of the frame's luminance, as the sun's Ω_sun·cos θ_i is.
    pub fn new(lamps: &[Lamp], unit_cd_m2: f64) -> Self {
        let mut out = Self::NONE;
        let stride = crate::gpu::interface::LAMP_VEC4S as usize;
        // L·α: a lamp's coherence length at any point is this over its angular radius there (`coherence_at`).
        let coherence_um_rad = DEFAULT_COHERENCE_UM * sun_angular_radius();
        for (k, lamp) in lamps.iter().take(crate::gpu::interface::MAX_LAMPS as usize).enumerate() {
            let (axis, cone_deg, soft_deg) = match lamp.spot {
                Some(s) => (s.direction, s.cone_deg, s.soft_deg),
                None => (DVec3::NEG_Y, 360.0, 0.0),
            };
            let p = lamp.position;
            out.lamps[stride * k] = [p.x as f32, p.y as f32, p.z as f32, (lamp.intensity_cd / unit_cd_m2) as f32];
            out.lamps[stride * k + 1] = [axis.x as f32, axis.y as f32, axis.z as f32, cone_deg as f32];
            out.lamps[stride * k + 2] = [
                soft_deg as f32,
                (lamp.radius_m * lamp.radius_m) as f32,
                coherence_um_rad as f32,
                lamp.radius_m as f32,
            ];
            out.count[0] = (k + 1) as f32;
        }
        out
    }
}

/// One line for the user: the lamps, and what the frame's units are beside them (`sun`: whether a sun lights the
/// scene too).
pub fn describe(lamps: &[Lamp], sun: bool) -> String {
    let each: Vec<String> = lamps
        .iter()
        .map(|l| {
            let p = l.position;
            let at = format!("at [{}] m", p.to_array().map(crate::error::number).join(", "));
            let disc = format!("{} cm across", crate::error::number(200.0 * l.radius_m));
            match l.spot {
                None => format!("a point lamp of {} cd {at}, {disc}", crate::error::number(l.intensity_cd)),
                Some(s) => format!(
                    "a spot of {} cd {at}, {disc}, its cone {}° (edge {}°)",
                    crate::error::number(l.intensity_cd),
                    crate::error::number(s.cone_deg),
                    crate::error::number(s.soft_deg)
                ),
            }
        })
        .collect();
    let units = match sun {
        true => "in the frame's units of the sun's luminance",
        false => "alone: the frame in cd/m²",
    };
    format!(
        "lamps ({units}): {}; their sizes set their coherence where a material keeps the default 65 µm (baked)",
        each.join("; ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_lamp_follows_the_inverse_square_and_cosine_laws() {
        let lamp = Lamp { position: DVec3::new(0.0, 1.0, 0.0), intensity_cd: 1.0, radius_m: 0.0, spot: None };
        assert!((lamp.illuminance(DVec3::ZERO, DVec3::Y) - 1.0).abs() < 1e-15, "1 cd at 1 m: 1 lx");
        let disc = Lamp { radius_m: 0.01, ..lamp };
        assert!((disc.illuminance(DVec3::ZERO, DVec3::Y) - 1.0 / 1.0001).abs() < 1e-15, "a disc 1 cm across");
        assert!((disc.illuminance(DVec3::new(0.0, 0.99, 0.0), DVec3::Y) - 5e3).abs() < 1e-6, "as far as it is wide");
        for theta_deg in [10.0, 30.0, 60.0f64] {
            let x = theta_deg.to_radians().tan();
            let e = lamp.illuminance(DVec3::new(x, 0.0, 0.0), DVec3::Y);
            assert!((e - theta_deg.to_radians().cos().powi(3)).abs() < 1e-12, "{theta_deg}°: {e}");
        }
        assert_eq!(lamp.illuminance(DVec3::ZERO, -DVec3::Y), 0.0, "lit from behind");
        assert!((disc.angular_radius_at(DVec3::ZERO).to_degrees() - 0.5729).abs() < 1e-4);
    }

    #[test]
    fn a_spots_edge_falls_from_full_to_none_across_its_soft_width() {
        let spot = Spot { direction: -DVec3::Y, cone_deg: 30.0, soft_deg: 10.0 };
        let lamp = Lamp { position: DVec3::Y, intensity_cd: 2.0, radius_m: 0.0, spot: Some(spot) };
        let towards = |deg: f64| DVec3::new(deg.to_radians().sin(), -deg.to_radians().cos(), 0.0);
        assert_eq!(lamp.intensity_towards(towards(0.0)), 2.0);
        assert_eq!(lamp.intensity_towards(towards(19.9)), 2.0);
        assert!((lamp.intensity_towards(towards(25.0)) - 1.0).abs() < 1e-9, "half way down the edge");
        assert_eq!(lamp.intensity_towards(towards(30.1)), 0.0);
        assert_eq!(spot_factor(29.0, 30.0, 0.0), 1.0, "a hard edge");
        assert_eq!(spot_factor(31.0, 30.0, 0.0), 0.0);
    }
}
