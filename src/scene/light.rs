//! What lights a scene besides its sun: the clear sky around it ([`SkyLight`]) or an HDR map ([`MapLight`], with
//! the sun found in it or not: [`MapSun`]), and what the renderer asks of either ([`Environment`]): its irradiance
//! on the pigment, its map in the frame's units, the sun's luminance that is the frame's unit.

use std::path::PathBuf;

use glam::Vec3;

use crate::error::Result;

/// The clear sky around a scene's sun ([`crate::physics::sky`]), over a ground of [`SKY_GROUND_ALBEDO`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyLight {
    pub turbidity: f64,
    pub model: crate::physics::sky::SkyModel,
}

/// What lights a scene besides its sun.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The clear-sky model around the sun.
    Sky(SkyLight),
    /// An HDR map of the sky around the sun, from a file.
    Map(std::sync::Arc<MapLight>),
}

/// An equirectangular HDR map (`[light] environment = "FILE.exr"`): linear RGB radiance in its own units (cd/m²
/// from `diffract gen sky`, relative from a camera), times `intensity`, turned by `rotation_deg` about the up axis.
/// Where it holds a sun ([`crate::light::sun`]), the sun is taken out of it and becomes the scene's light, in the
/// map's units; otherwise the scene's sun is `[light] direction` with the clear-sky model's radiance, or there is
/// none and the map lights the scene alone. The frame is in units of the sun's radiance (the map's own units
/// where it has no sun).
#[derive(Clone, Debug, PartialEq)]
pub struct MapLight {
    pub path: PathBuf,
    /// The map, its sun (if it held one) taken out.
    pub map: crate::light::environment::EnvironmentMap,
    pub rotation_deg: f64,
    pub intensity: f64,
    /// The map's irradiance (E/π in its units, scaled and turned; without its sun).
    pub irradiance: crate::physics::sh::Irradiance,
    pub sun: MapSun,
    /// The texels the sun was taken out of, as the file had them (index, radiance): drawn behind the scene.
    pub sun_texels: Vec<(usize, [f32; 3])>,
}

/// Where the sun of a scene under a map comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapSun {
    /// The map's own, found in it (in the map's frame: [`MapLight::rotation_deg`] turns it).
    Found(crate::light::sun::FoundSun),
    /// `[light] direction`, with the clear-sky model's sun (a map without one, in cd/m²).
    Model,
    /// None: the map lights the scene alone.
    Alone,
}

impl Environment {
    /// Its irradiance on the pigment for the sun towards `light_dir`: nine SH coefficients of E/π in units of the
    /// sun's radiance (zero while the sun is below the horizon, where that unit is not defined).
    pub fn irradiance(&self, light_dir: Vec3) -> [[f32; 4]; 9] {
        match self {
            Environment::Sky(sky) => sky.irradiance(light_dir),
            Environment::Map(m) => match self.sun_luminance(light_dir) {
                Some(sun) => {
                    crate::physics::sh::Irradiance { coefficients: m.irradiance.coefficients.map(|c| c / sun) }
                        .to_vec4s()
                }
                None => [[0.0; 4]; 9],
            },
        }
    }

    /// The map the environment is, with the sun towards `light_dir` in it (`with_sun`, what is drawn behind a
    /// scene) or without it (what its diffraction reads at the mirror direction: the sun diffracts as the scene's
    /// light), the factor from its texels to the frame's units and its turn about +y (radians); None while the sun
    /// is below the horizon. The clear sky is rendered at `sky_width` texels across.
    pub fn panorama(
        &self,
        light_dir: Vec3,
        with_sun: bool,
        sky_width: u32,
    ) -> Result<Option<(std::borrow::Cow<'_, crate::light::environment::EnvironmentMap>, f64, f64)>> {
        let Some((scale, rotation)) = self.panorama_units(light_dir) else { return Ok(None) };
        let map = match self {
            // Behind the scene the map's sun is drawn as the file has it; the light it gives is the directional one.
            Environment::Map(m) if with_sun && !m.sun_texels.is_empty() => {
                let mut map = m.map.clone();
                for &(i, rgb) in &m.sun_texels {
                    map.rgb[i] = rgb;
                }
                std::borrow::Cow::Owned(map)
            }
            Environment::Map(m) => std::borrow::Cow::Borrowed(&m.map),
            Environment::Sky(sky) => {
                let model = sky.sky(light_dir)?;
                std::borrow::Cow::Owned(if with_sun {
                    crate::light::environment::EnvironmentMap::of_sky_and_sun(&model, sky_width, SKY_GROUND_ALBEDO)?
                } else {
                    crate::light::environment::EnvironmentMap::of_sky(&model, sky_width, SKY_GROUND_ALBEDO)?
                })
            }
        };
        Ok(Some((map, scale, rotation)))
    }

    /// [`Self::panorama`]'s factor from the map's texels to the frame's units and its turn (radians), without the
    /// map; None while the sun is below the horizon.
    pub fn panorama_units(&self, light_dir: Vec3) -> Option<(f64, f64)> {
        let sun = self.sun_luminance(light_dir)?;
        Some(match self {
            Environment::Map(m) => (m.intensity / sun, m.rotation_deg.to_radians()),
            Environment::Sky(_) => (1.0 / sun, 0.0),
        })
    }

    /// The sun's luminance, the frame's unit, which an environment's radiance is divided by: the model's sun
    /// towards `light_dir` through [`Self::turbidity`] (cd/m²; None while it is below the horizon), a map's own sun
    /// as a disc of the sun's solid angle (in the map's units, times its intensity), or 1 (the map's own units) for
    /// a map that lights the scene alone.
    pub fn sun_luminance(&self, light_dir: Vec3) -> Option<f64> {
        if let Environment::Map(m) = self {
            match m.sun {
                MapSun::Found(sun) => {
                    return Some(sun.illuminance() * m.intensity / crate::physics::optics::SUN_SOLID_ANGLE)
                }
                MapSun::Alone => return Some(1.0),
                MapSun::Model => {}
            }
        }
        crate::physics::sky::Sky::new(self.turbidity(), light_dir.as_dvec3()).ok().map(|s| s.sun_xyz().y)
    }

    /// One line for the user: what the environment does in a frame and what it does not (yet).
    pub fn describe(&self) -> String {
        let what = match self {
            Environment::Sky(sky) => {
                format!("the clear sky ({}, turbidity {})", sky.model.citation(), crate::error::number(sky.turbidity))
            }
            Environment::Map(m) => format!(
                "{} ({}×{} texels, intensity {}, turned {}°; {})",
                m.path.display(),
                m.map.width,
                m.map.height,
                crate::error::number(m.intensity),
                crate::error::number(m.rotation_deg),
                match m.sun {
                    MapSun::Found(_) => "its own sun is the light; the frame in units of that sun's radiance",
                    MapSun::Model => "the sun is [light] direction's; the frame in units of its radiance",
                    MapSun::Alone => "no sun; the frame in the map's own units",
                }
            ),
        };
        format!(
            "environment: {what} lights the pigment (nine SH coefficients) and diffracts, by the BRDF's moments \
             against its l ≤ 2 radiance (the sun diffracts as the directional light)"
        )
    }

    /// The turbidity the sun's spectrum is seen through: the sky's, or the model's default under a map.
    pub fn turbidity(&self) -> f64 {
        match self {
            Environment::Sky(sky) => sky.turbidity,
            Environment::Map(_) => crate::physics::illuminant::SUN_TURBIDITY,
        }
    }
}

/// The albedo of the ground below a scene's sky (grass and soil, about 0.2).
pub const SKY_GROUND_ALBEDO: f64 = crate::physics::sky::GROUND_ALBEDO;

impl SkyLight {
    /// The sky model around the sun towards `light_dir`, over a ground of [`SKY_GROUND_ALBEDO`].
    pub fn sky(&self, light_dir: Vec3) -> Result<crate::physics::sky::Sky> {
        crate::physics::sky::Sky::of_model(self.model, self.turbidity, light_dir.as_dvec3(), SKY_GROUND_ALBEDO)
    }

    /// The sky's irradiance on the pigment for the sun towards `light_dir` (nine SH coefficients of E/π in units
    /// of the sun's radiance: `environment::sky_irradiance`); zero while the sun is below the horizon (night: the
    /// model is for daylight). The last result is kept: a viewer asks every frame, for the same light.
    pub fn irradiance(&self, light_dir: Vec3) -> [[f32; 4]; 9] {
        type Memo = Option<((u64, crate::physics::sky::SkyModel, [u32; 3]), [[f32; 4]; 9])>;
        static LAST: std::sync::Mutex<Memo> = std::sync::Mutex::new(None);
        let key = (self.turbidity.to_bits(), self.model, light_dir.to_array().map(f32::to_bits));
        let mut last = LAST.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((k, sh)) = *last {
            if k == key {
                return sh;
            }
        }
        let sh = match self.sky(light_dir) {
            Ok(sky) => crate::light::environment::sky_irradiance(&sky, SKY_GROUND_ALBEDO).to_vec4s(),
            Err(_) => [[0.0; 4]; 9],
        };
        *last = Some((key, sh));
        sh
    }
}
