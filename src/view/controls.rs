//! The viewer's controls: the live settings the keys and the mouse change ([`Live`]), the pointer's state
//! ([`Input`]) and what each key and drag does. Nothing here touches the GPU, so every binding is unit-tested.

use glam::Vec3;
use winit::event::{MouseButton, MouseScrollDelta};
use winit::keyboard::{Key, ModifiersState, NamedKey};

use crate::material::Material;
use crate::material::{Approach, SettingsPatch, MAX_WINDOW_RADIUS};
use crate::scene::camera::Camera;
use crate::scene::Scene;

/// The key bindings, as `H` prints them and docs/usage.md lists them.
pub const BINDINGS: &str = "\
mouse: left drag orbit · right drag (or shift + left drag) pan · wheel zoom · ctrl + left drag move the light
keys:  1 … 5     approach flss / nmm / pq / gem / baked
       T / shift+T   Taylor order + / −        L / shift+L   wavelength step + / − (nm)
       R / shift+R   window radius + / −       + / −         exposure ± 0.5 EV
       arrows        light azimuth / elevation M             BRDF map ↔ geometry
       C             tone curve filmic ↔ clip  P             screenshot (diffract-NNNN.png)
       H             this help                 Esc           quit";

/// Radians of orbit (and of light movement) per pixel dragged.
const RADIANS_PER_PIXEL: f32 = 0.01;
/// The camera's pitch stays inside ±this (radians; just short of the poles, where the orbit's yaw degenerates).
const MAX_PITCH: f32 = 1.5;
/// The light's elevation stays inside ±this (radians, about 88.8°: short of grazing, where the window's
/// footprint and the Fresnel term have no meaning left).
const MAX_LIGHT_ELEVATION: f32 = 1.55;
/// Panning moves the target by this fraction of the camera's distance per pixel dragged.
const PAN_PER_PIXEL: f32 = 0.002;
/// Each wheel line multiplies the camera's distance by this (zooming in).
const ZOOM_PER_LINE: f32 = 0.9;
/// Pixels of a touchpad's scroll that count as one wheel line.
const PIXELS_PER_LINE: f32 = 40.0;
/// The camera's distance stays inside this range (scene units).
const DISTANCE_RANGE: (f32, f32) = (0.01, 1000.0);
/// Degrees the light turns per arrow key press.
const LIGHT_STEP_DEGREES: f32 = 5.0;
/// Exposure change per `+`/`−` press (EV).
const EXPOSURE_STEP_EV: f64 = 0.5;

/// The live settings the keys and the mouse change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Live {
    pub overrides: SettingsPatch,
    pub exposure_ev: f64,
    /// The tone curve the window shows light through (`--tone`).
    pub tone: crate::display::Tone,
    /// Show the first object's BRDF as a map instead of the geometry.
    pub map_mode: bool,
    /// Camera orbit about the target: yaw and pitch (radians) and distance.
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
    pub target: Vec3,
    /// Light direction as azimuth and elevation (radians).
    pub light_azimuth: f32,
    pub light_elevation: f32,
}

/// What a key asks of the viewer beyond changing [`Live`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Request {
    Nothing,
    Quit,
    Help,
    Screenshot,
}

/// The pointer: where it is, which button drags, which modifiers are held.
#[derive(Default)]
pub struct Input {
    pub cursor: (f64, f64),
    pub dragging: Option<MouseButton>,
    pub modifiers: ModifiersState,
}

impl Live {
    /// The scene's camera and light, with the viewer's settings.
    pub fn from_scene(scene: &Scene, overrides: SettingsPatch, exposure_ev: f64) -> Self {
        let offset = scene.camera.position - scene.camera.target;
        let distance = offset.length();
        let light = scene.light_dir;
        Self {
            overrides,
            exposure_ev,
            tone: crate::display::Tone::default(),
            map_mode: false,
            yaw: offset.x.atan2(offset.z),
            pitch: (offset.y / distance).clamp(-1.0, 1.0).asin(),
            distance,
            target: scene.camera.target,
            light_azimuth: light.x.atan2(light.z),
            light_elevation: light.y.clamp(-1.0, 1.0).asin(),
        }
    }

    /// Unit vector from the target towards the camera.
    pub fn eye_direction(&self) -> Vec3 {
        direction(self.yaw, self.pitch)
    }

    /// `base` (its lens) moved to the orbit's position.
    pub fn camera(&self, base: &Camera) -> Camera {
        Camera { position: self.target + self.eye_direction() * self.distance, target: self.target, ..*base }
    }

    /// Unit vector towards the light.
    pub fn light(&self) -> Vec3 {
        direction(self.light_azimuth, self.light_elevation)
    }

    /// The linear scale the exposure applies.
    pub fn exposure_scale(&self) -> f64 {
        self.exposure_ev.exp2()
    }

    /// Applies a key press. `current` is the first material as it is prepared now: the Taylor order, wavelength
    /// step and window radius keys step from its values (which the approach may have chosen itself).
    pub fn key(&mut self, key: &Key, shift: bool, current: &Material) -> Request {
        let step = LIGHT_STEP_DEGREES.to_radians();
        let o = &mut self.overrides;
        match key {
            Key::Named(NamedKey::Escape) => return Request::Quit,
            Key::Named(NamedKey::ArrowLeft) => self.light_azimuth -= step,
            Key::Named(NamedKey::ArrowRight) => self.light_azimuth += step,
            Key::Named(NamedKey::ArrowUp) => {
                self.light_elevation = (self.light_elevation + step).min(MAX_LIGHT_ELEVATION)
            }
            Key::Named(NamedKey::ArrowDown) => {
                self.light_elevation = (self.light_elevation - step).max(-MAX_LIGHT_ELEVATION)
            }
            Key::Character(c) => match c.to_lowercase().as_str() {
                "1" => o.approach = Some(Approach::Flss),
                "2" => o.approach = Some(Approach::Nmm),
                "3" => o.approach = Some(Approach::Pq),
                "4" => o.approach = Some(Approach::Gem),
                "5" => o.approach = Some(Approach::Baked),
                "t" => {
                    let n = current.plan.map_or(10, |p| p.order);
                    o.order = Some(if shift { n.saturating_sub(1) } else { n + 1 });
                }
                "l" => {
                    let s = current.sampling.step_nm;
                    o.lambda_step_nm = Some(if shift { (s - 1.0).max(1.0) } else { s + 1.0 });
                }
                "r" => {
                    let r = current.window.radius_x as u32;
                    o.window_radius = Some(if shift { r.saturating_sub(1) } else { (r + 1).min(MAX_WINDOW_RADIUS) });
                }
                "+" | "=" => self.exposure_ev += EXPOSURE_STEP_EV,
                "-" | "_" => self.exposure_ev -= EXPOSURE_STEP_EV,
                "m" => self.map_mode = !self.map_mode,
                "c" => {
                    use crate::display::Tone;
                    self.tone = if self.tone == Tone::Filmic { Tone::Clip } else { Tone::Filmic };
                }
                "h" => return Request::Help,
                "p" => return Request::Screenshot,
                _ => {}
            },
            _ => {}
        }
        Request::Nothing
    }

    /// Zooms by a wheel's (or touchpad's) scroll.
    pub fn zoom(&mut self, delta: MouseScrollDelta) {
        let lines = match delta {
            MouseScrollDelta::LineDelta(_, y) => y,
            MouseScrollDelta::PixelDelta(p) => p.y as f32 / PIXELS_PER_LINE,
        };
        self.distance = (self.distance * ZOOM_PER_LINE.powf(lines)).clamp(DISTANCE_RANGE.0, DISTANCE_RANGE.1);
    }
}

/// The unit vector at `azimuth` about +y (0 along +z, π/2 along +x) and `elevation` above the x–z plane
/// (radians): the camera's orbit and the light use the same angles.
fn direction(azimuth: f32, elevation: f32) -> Vec3 {
    Vec3::new(elevation.cos() * azimuth.sin(), elevation.sin(), elevation.cos() * azimuth.cos())
}

impl Input {
    /// Moves the pointer to (x, y) pixels; a drag orbits the camera (left), pans it (right, or shift + left) or
    /// moves the light (ctrl + left).
    pub fn drag(&mut self, live: &mut Live, x: f64, y: f64) {
        let (dx, dy) = ((x - self.cursor.0) as f32, (y - self.cursor.1) as f32);
        self.cursor = (x, y);
        let pan = self.dragging == Some(MouseButton::Right)
            || (self.dragging == Some(MouseButton::Left) && self.modifiers.shift_key());
        match self.dragging {
            Some(MouseButton::Left) if self.modifiers.control_key() => {
                live.light_azimuth += dx * RADIANS_PER_PIXEL;
                live.light_elevation =
                    (live.light_elevation - dy * RADIANS_PER_PIXEL).clamp(-MAX_LIGHT_ELEVATION, MAX_LIGHT_ELEVATION);
            }
            _ if pan => {
                let forward = -live.eye_direction();
                let right = forward.cross(Vec3::Y).normalize_or_zero();
                let up = right.cross(forward);
                live.target += (-right * dx + up * dy) * live.distance * PAN_PER_PIXEL;
            }
            Some(MouseButton::Left) => {
                live.yaw -= dx * RADIANS_PER_PIXEL;
                live.pitch = (live.pitch + dy * RADIANS_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use winit::dpi::PhysicalPosition;

    use super::*;
    use crate::material::Reach;
    use crate::material::Settings;
    use crate::physics::heightfield::HeightField;

    /// A small grating, prepared as the viewer would for its first material.
    fn material(settings: Settings) -> Material {
        let h = (0..32 * 32).map(|i| 0.05 * (std::f64::consts::TAU * (i % 32) as f64 / 8.0).sin()).collect();
        let hf = HeightField::new(32, 32, 0.1, 0.1, h).unwrap();
        Material::prepare(&hf, settings, &Reach::ANY).unwrap()
    }

    fn live() -> Live {
        Live {
            overrides: SettingsPatch::default(),
            exposure_ev: 0.0,
            tone: crate::display::Tone::default(),
            map_mode: false,
            yaw: 0.0,
            pitch: 0.0,
            distance: 2.0,
            target: Vec3::ZERO,
            light_azimuth: 0.0,
            light_elevation: 0.5,
        }
    }

    fn char_key(c: &str) -> Key {
        Key::Character(c.into())
    }

    #[test]
    fn the_scene_camera_and_light_come_back_from_the_orbit() {
        let scene = Scene::default_scene().unwrap();
        let live = Live::from_scene(&scene, SettingsPatch::default(), 0.0);
        let camera = live.camera(&scene.camera);
        assert!((camera.position - scene.camera.position).length() < 1e-4, "{camera:?} vs {:?}", scene.camera);
        assert!((live.light() - scene.light_dir.normalize()).length() < 1e-5);
    }

    #[test]
    fn settings_keys_step_from_the_material_as_prepared() {
        let current = material(Settings { order: Some(4), window_radius: Some(3), ..Settings::default() });
        let order = current.plan.expect("flss has a Taylor plan").order;
        let step = current.sampling.step_nm;
        let mut live = live();
        assert_eq!(live.key(&char_key("t"), false, &current), Request::Nothing);
        assert_eq!(live.overrides.order, Some(order + 1));
        live.key(&char_key("T"), true, &current);
        assert_eq!(live.overrides.order, Some(order - 1), "shift steps down, from the material's order");
        live.key(&char_key("l"), false, &current);
        assert_eq!(live.overrides.lambda_step_nm, Some(step + 1.0));
        live.key(&char_key("r"), false, &current);
        assert_eq!(live.overrides.window_radius, Some(4));
        live.key(&char_key("5"), false, &current);
        assert_eq!(live.overrides.approach, Some(Approach::Baked));
        let widest = material(Settings { window_radius: Some(MAX_WINDOW_RADIUS), ..Settings::default() });
        live.key(&char_key("r"), false, &widest);
        assert_eq!(live.overrides.window_radius, Some(MAX_WINDOW_RADIUS), "the radius stops at its bound");
        let before = live.overrides;
        live.key(&char_key("+"), false, &current);
        live.key(&char_key("m"), false, &current);
        assert_eq!((live.exposure_ev, live.map_mode, live.overrides), (EXPOSURE_STEP_EV, true, before));
        use crate::display::Tone;
        live.tone = Tone::Filmic;
        live.key(&char_key("c"), false, &current);
        assert_eq!(live.tone, Tone::Clip);
        live.key(&char_key("C"), true, &current);
        assert_eq!((live.tone, live.overrides), (Tone::Filmic, before), "the curve alone changes");
    }

    #[test]
    fn requests_and_the_light_keys() {
        let current = material(Settings::default());
        let mut live = live();
        assert_eq!(live.key(&Key::Named(NamedKey::Escape), false, &current), Request::Quit);
        assert_eq!(live.key(&char_key("p"), false, &current), Request::Screenshot);
        assert_eq!(live.key(&char_key("H"), true, &current), Request::Help);
        for _ in 0..40 {
            live.key(&Key::Named(NamedKey::ArrowUp), false, &current);
        }
        assert_eq!(live.light_elevation, MAX_LIGHT_ELEVATION, "the light stops short of the zenith's far side");
        live.key(&Key::Named(NamedKey::ArrowLeft), false, &current);
        assert!((live.light_azimuth + LIGHT_STEP_DEGREES.to_radians()).abs() < 1e-6);
    }

    #[test]
    fn drags_orbit_pan_and_move_the_light() {
        let mut live = live();
        let mut input = Input { dragging: Some(MouseButton::Left), ..Input::default() };
        input.drag(&mut live, 10.0, 1000.0);
        assert!((live.yaw + 10.0 * RADIANS_PER_PIXEL).abs() < 1e-6);
        assert_eq!(live.pitch, MAX_PITCH, "the orbit stops short of the pole");

        let mut live = self::live();
        let mut input = Input { dragging: Some(MouseButton::Right), ..Input::default() };
        input.drag(&mut live, 10.0, 0.0);
        let moved = live.target;
        assert!((moved.length() - 10.0 * PAN_PER_PIXEL * live.distance).abs() < 1e-6, "{moved}");
        assert!(moved.dot(live.eye_direction()).abs() < 1e-6, "a pan moves across the view, not along it");
        let shift = Input { dragging: Some(MouseButton::Left), modifiers: ModifiersState::SHIFT, ..Input::default() };
        let mut shifted = self::live();
        let mut input = shift;
        input.drag(&mut shifted, 10.0, 0.0);
        assert_eq!(shifted.target, moved, "shift + left pans as right does");

        let mut live = self::live();
        let mut input =
            Input { dragging: Some(MouseButton::Left), modifiers: ModifiersState::CONTROL, ..Input::default() };
        input.drag(&mut live, 0.0, -1000.0);
        assert_eq!((live.yaw, live.light_elevation), (0.0, MAX_LIGHT_ELEVATION), "ctrl moves the light only");
    }

    #[test]
    fn the_wheel_zooms_within_bounds() {
        let mut live = live();
        live.zoom(MouseScrollDelta::LineDelta(0.0, 1.0));
        assert!((live.distance - 2.0 * ZOOM_PER_LINE).abs() < 1e-6);
        live.zoom(MouseScrollDelta::PixelDelta(PhysicalPosition::new(0.0, -f64::from(PIXELS_PER_LINE))));
        assert!((live.distance - 2.0).abs() < 1e-5, "{PIXELS_PER_LINE} pixels are one line");
        live.zoom(MouseScrollDelta::LineDelta(0.0, 1e4));
        assert_eq!(live.distance, DISTANCE_RANGE.0);
    }
}
