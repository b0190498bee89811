//! Irradiance from light over the whole sphere in nine numbers per colour: the radiance projected on the real
//! spherical harmonics up to l = 2 and convolved with the clamped cosine (Ramamoorthi & Hanrahan, *An Efficient
//! Representation for Irradiance Environment Maps*, SIGGRAPH 2001): E(n) = Σ Â_l·L_lm·Y_lm(n) with Â_0 = π,
//! Â_1 = 2π/3, Â_2 = π/4. A Lambertian surface of albedo ρ then returns ρ·E(n)/π.
//!
//! [`Irradiance::coefficients`] hold L_lm·Â_l/π, so that [`Irradiance::over_pi`] is the plain sum Σ c·Y(n):
//! the surface shader (`sky_over_pi` in glsl/include/surface_shade.glsl) evaluates the same sum of the same nine numbers.
//! Where the light has detail beyond l = 2 (the horizon's edge, a bright circumsolar region) the sum is an
//! approximation of the irradiance: its error for the built-in sky is measured in the tests below.

use glam::DVec3;

use crate::gpu::interface::{SH_Y00, SH_Y1, SH_Y2, SH_Y20, SH_Y22};

/// The nine real spherical harmonics at the unit vector `n`, in the order of [`Irradiance::coefficients`] (their
/// constants are the shaders' too: `gpu::interface`).
pub fn basis(n: DVec3) -> [f64; 9] {
    let (x, y, z) = (n.x, n.y, n.z);
    [
        SH_Y00,
        SH_Y1 * y,
        SH_Y1 * z,
        SH_Y1 * x,
        SH_Y2 * x * y,
        SH_Y2 * y * z,
        SH_Y20 * (3.0 * z * z - 1.0),
        SH_Y2 * x * z,
        SH_Y22 * (x * x - y * y),
    ]
}

/// The midpoint rule over the whole sphere: `rings` rings of θ (from the zenith, +y) by 2·`rings` steps of φ, each
/// cell as (its centre's unit direction, its solid angle sin θ·Δθ·Δφ). The first `rings`/2 rings (for an even
/// `rings`) cover the upper hemisphere.
pub fn sphere_cells(rings: usize) -> impl Iterator<Item = (DVec3, f64)> {
    let step = std::f64::consts::PI / rings as f64;
    (0..rings).flat_map(move |i| {
        let theta = (i as f64 + 0.5) * step;
        (0..2 * rings).map(move |j| {
            let phi = (j as f64 + 0.5) * step;
            (DVec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()), theta.sin() * step * step)
        })
    })
}

/// The band l of each coefficient.
const BAND: [usize; 9] = [0, 1, 1, 1, 2, 2, 2, 2, 2];
/// Â_l/π: the clamped cosine's convolution weights over π.
const WEIGHT_OVER_PI: [f64; 3] = [1.0, 2.0 / 3.0, 0.25];

/// The irradiance of a light over the sphere, as nine RGB coefficients.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Irradiance {
    pub coefficients: [DVec3; 9],
}

impl Irradiance {
    /// Projects `radiance` (RGB, any unit) by the midpoint rule of [`sphere_cells`] with `rings` rings.
    pub fn of(radiance: impl Fn(DVec3) -> DVec3, rings: usize) -> Self {
        Self::of_cells(sphere_cells(rings).map(|(dir, solid_angle)| (dir, solid_angle, radiance(dir))))
    }

    /// Projects light given as cells of the sphere: (unit direction, solid angle, radiance RGB).
    pub fn of_cells(cells: impl Iterator<Item = (DVec3, f64, DVec3)>) -> Self {
        let mut coefficients = [DVec3::ZERO; 9];
        for (dir, solid_angle, radiance) in cells {
            let l = radiance * solid_angle;
            for (c, y) in coefficients.iter_mut().zip(basis(dir)) {
                *c += l * y;
            }
        }
        for (k, c) in coefficients.iter_mut().enumerate() {
            *c *= WEIGHT_OVER_PI[BAND[k]];
        }
        Self { coefficients }
    }

    /// E(n)/π at the unit normal `n` (what a white Lambertian surface returns), never negative.
    pub fn over_pi(&self, n: DVec3) -> DVec3 {
        self.coefficients.iter().zip(basis(n)).map(|(c, y)| *c * y).sum::<DVec3>().max(DVec3::ZERO)
    }

    /// The radiance's own coefficients L_lm: [`Self::coefficients`] without the clamped cosine's convolution.
    pub fn radiance_coefficients(&self) -> [DVec3; 9] {
        std::array::from_fn(|k| self.coefficients[k] / WEIGHT_OVER_PI[BAND[k]])
    }

    /// The coefficients as the shaders' `vec4`s (RGB, w = 0).
    pub fn to_vec4s(&self) -> [[f32; 4]; 9] {
        self.coefficients.map(|c| [c.x as f32, c.y as f32, c.z as f32, 0.0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed forms: a uniform radiance L gives E/π = L at every normal; L = a + b·(ω·d), all in l ≤ 1, gives
    /// E/π = a + (2/3)·b·(n·d) exactly; L = (ω·d)², all in l ≤ 2, gives E/π = 1/2 at n = d (∫ cos³θ dω over
    /// the hemisphere is π/2).
    #[test]
    fn irradiance_of_low_order_light_is_exact() {
        let d = DVec3::new(0.3, 0.8, -0.52).normalize();
        let normals = [DVec3::Y, DVec3::X, -DVec3::Z, d, DVec3::new(-0.6, 0.0, 0.8)];
        let uniform = Irradiance::of(|_| DVec3::new(1.0, 0.5, 0.25), 200);
        for n in normals {
            assert!((uniform.over_pi(n) - DVec3::new(1.0, 0.5, 0.25)).length() < 1e-4, "{n}");
        }
        let linear = Irradiance::of(|w| DVec3::splat(2.0 + w.dot(d)), 200);
        for n in normals {
            let expected = 2.0 + 2.0 / 3.0 * n.dot(d);
            assert!((linear.over_pi(n).x - expected).abs() < 1e-4, "{n}: {} vs {expected}", linear.over_pi(n).x);
        }
        let quadratic = Irradiance::of(|w| DVec3::splat(w.dot(d).powi(2)), 200);
        assert!((quadratic.over_pi(d).x - 0.5).abs() < 1e-4, "{}", quadratic.over_pi(d).x);
    }
}
