//! `diffract view`: a scene in a window (winit + a Vulkan swapchain), with an orbit camera, light control and
//! the speed/accuracy settings changed live; the title shows the approach, its settings, the GPU time per frame
//! (timestamp queries) and the frame rate. `--frames N --screenshot FILE` renders N frames, writes the last and
//! exits, for tests and demos.

use std::path::PathBuf;
use std::time::Instant;

use ash::vk;
use glam::Vec3;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::render::capture::{material_inputs, prepare_materials, scene_objects};
use crate::render::diffraction::{light_params, MapPass, PatchResources};
use crate::render::surface::SceneRenderer;
use crate::render::TargetView;
use crate::scene::Scene;
use crate::shading::{Approach, Material, Overrides};
use crate::vk::swapchain::{self, Acquired, FrameSync, Surface, Swapchain};
use crate::vk::{Buffer, BufferDesc, Context, ContextDesc, Guard, ImageState, TimestampRing};

/// The key bindings, as `H` prints them and the README lists them.
pub const BINDINGS: &str = "\
mouse: left drag orbit · right drag (or shift + left drag) pan · wheel zoom · ctrl + left drag move the light
keys:  1 … 5     approach flss / nmm / pq / gem / baked
       T / shift+T   Taylor order + / −        L / shift+L   wavelength step + / − (nm)
       R / shift+R   window radius + / −       + / −         exposure ± 0.5 EV
       arrows        light azimuth / elevation M             BRDF map ↔ geometry
       P             screenshot (diffract-NNNN.png)          H  this help        Esc  quit";

/// What `diffract view` was asked for.
pub struct ViewOptions {
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    pub vsync: bool,
    pub context: ContextDesc,
    pub overrides: Overrides,
    pub exposure_ev: f64,
    /// Render this many frames, write the last to `screenshot` and exit.
    pub frames: Option<u32>,
    pub screenshot: Option<PathBuf>,
    /// Ask the window to shrink after this many frames (tests that a resize is survived).
    pub resize_after: Option<u32>,
    /// Every [`SOAK_PERIOD`] frames: a new window size and the next approach; resident memory printed.
    pub soak: bool,
    /// Samples per pixel of the scene's frames (multisample anti-aliasing; 1: none); None: the scene's, except
    /// on a CPU implementation (see [`CPU_MSAA_NOTE`]).
    pub samples: Option<u32>,
}

/// Why the viewer does not multisample on a CPU implementation unless asked: lavapipe shades every sample, so
/// 4× multisampling costs about 4× the frame time there (`diffract render --samples 1|4` on the default scene:
/// 80–85 → 328–439 ms per 800² frame).
pub const CPU_MSAA_NOTE: &str = "is a CPU implementation, where multisampling costs about 4× the frame time: \
                                 edges are not anti-aliased (--samples 4 turns it on)";

/// Frames between the soak's resizes and approach switches.
pub const SOAK_PERIOD: u32 = 50;
/// The soak's window sizes, as fractions (numerator, denominator) of the requested size, in turn.
const SOAK_SIZES: [(u32, u32); 4] = [(3, 4), (1, 2), (5, 4), (1, 1)];

/// What the soak saw: resizes and switches made, resident memory (MiB) after the first frame, after the first
/// round of every approach, and at the end.
#[derive(Default)]
struct Soak {
    resizes: u32,
    switches: u32,
    rss_first: Option<f64>,
    rss_round: Option<f64>,
    /// The frame of the last step (a frame that is not presented, e.g. out of date, keeps the count).
    stepped_at: u32,
}

/// This process's resident memory in MiB (Linux: /proc/self/status), or None elsewhere.
fn resident_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let kib: f64 =
        status.lines().find_map(|l| l.strip_prefix("VmRSS:"))?.trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kib / 1024.0)
}

/// Opens the window and runs until it is closed (or the scripted frames are done); returns the number of
/// validation messages (0 without `--validation`).
pub fn run(options: ViewOptions) -> Result<usize> {
    let event_loop = EventLoop::new().map_err(|e| {
        Error::Invalid(format!("cannot open a window ({e}); `diffract view` needs a desktop (DISPLAY or WAYLAND_DISPLAY) — use `diffract render` for headless images"))
    })?;
    let mut app = App { options, state: None, error: None, log: None };
    event_loop.run_app(&mut app).map_err(|e| Error::Invalid(format!("the window's event loop failed: {e}")))?;
    if let Some(e) = app.error {
        return Err(e);
    }
    Ok(app.log.map_or(0, |l| l.count()))
}

struct App {
    options: ViewOptions,
    state: Option<State>,
    error: Option<Error>,
    log: Option<std::sync::Arc<crate::vk::ValidationLog>>,
}

/// The live settings the keys change.
#[derive(Clone, Copy)]
struct Live {
    overrides: Overrides,
    exposure_ev: f64,
    map_mode: bool,
    /// Camera orbit about the target: yaw and pitch (radians) and distance.
    yaw: f32,
    pitch: f32,
    distance: f32,
    target: Vec3,
    /// Light direction as azimuth and elevation (radians).
    light_azimuth: f32,
    light_elevation: f32,
}

struct Gpu {
    materials: Vec<Material>,
    renderer: SceneRenderer,
    map: MapPass,
    map_patch: PatchResources,
}

struct State {
    window: Window,
    ctx: Context,
    surface: Option<Surface>,
    swapchain: Option<Swapchain>,
    sync: Option<FrameSync>,
    ring: Option<TimestampRing>,
    gpu: Option<Gpu>,
    screenshot: Option<Buffer>,
    live: Live,
    needs_resize: bool,
    frame: u32,
    gpu_ms: Option<f64>,
    /// GPU ms of every frame after the first (the first includes the driver's shader compilation).
    frame_times: Vec<f64>,
    /// When the scripted frames started (after the first).
    timed_since: Option<Instant>,
    last_title: Instant,
    fps_frames: u32,
    fps: f64,
    cursor: (f64, f64),
    dragging: Option<MouseButton>,
    modifiers: winit::keyboard::ModifiersState,
    screenshots_taken: u32,
    soak: Soak,
    /// Samples per pixel of the scene's frames (the window's multisampled image and depth).
    samples: u32,
}

impl Live {
    fn from_scene(scene: &Scene, options: &ViewOptions) -> Self {
        let offset = scene.camera.position - scene.camera.target;
        let distance = offset.length();
        let light = scene.light_dir;
        Self {
            overrides: options.overrides,
            exposure_ev: options.exposure_ev,
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
    fn eye_direction(&self) -> Vec3 {
        Vec3::new(self.pitch.cos() * self.yaw.sin(), self.pitch.sin(), self.pitch.cos() * self.yaw.cos())
    }

    fn camera(&self, base: &Camera) -> Camera {
        Camera { position: self.target + self.eye_direction() * self.distance, target: self.target, ..*base }
    }

    fn light(&self) -> Vec3 {
        Vec3::new(
            self.light_elevation.cos() * self.light_azimuth.sin(),
            self.light_elevation.sin(),
            self.light_elevation.cos() * self.light_azimuth.cos(),
        )
    }
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        match State::new(event_loop, &self.options) {
            Ok(state) => {
                self.log = Some(state.ctx.validation());
                println!("{BINDINGS}");
                self.state = Some(state);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(state) = self.state.as_mut() else { return };
        let result = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::Resized(_) => {
                state.needs_resize = true;
                Ok(())
            }
            WindowEvent::ModifiersChanged(m) => {
                state.modifiers = m.state();
                Ok(())
            }
            WindowEvent::KeyboardInput { event, .. } => state.key(event_loop, &event, &self.options),
            WindowEvent::MouseInput { state: pressed, button, .. } => {
                state.dragging = (pressed == ElementState::Pressed).then_some(button);
                Ok(())
            }
            WindowEvent::CursorMoved { position, .. } => {
                state.drag(position.x, position.y);
                Ok(())
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                state.live.distance = (state.live.distance * 0.9f32.powf(lines)).clamp(0.01, 1000.0);
                Ok(())
            }
            WindowEvent::RedrawRequested => state.draw(event_loop, &self.options),
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.fail(event_loop, e);
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(state) = &self.state {
            state.window.request_redraw();
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(state) = self.state.take() {
            let live = state.destroy();
            if self.options.soak {
                println!("soak: {} GPU allocations live at teardown", live.len());
            }
            if !live.is_empty() && self.error.is_none() {
                self.error = Some(Error::Invalid(format!(
                    "a bug in diffract: {} GPU allocations still live when the window closed ({})",
                    live.len(),
                    live.join(", ")
                )));
            }
        }
    }
}

impl State {
    fn new(event_loop: &ActiveEventLoop, options: &ViewOptions) -> Result<Self> {
        let attributes = Window::default_attributes()
            .with_title("diffract")
            .with_inner_size(PhysicalSize::new(options.width, options.height));
        let window =
            event_loop.create_window(attributes).map_err(|e| Error::Invalid(format!("cannot open a window: {e}")))?;
        let display = window.display_handle().map_err(|e| Error::Invalid(format!("no display handle: {e}")))?.as_raw();
        let handle = window.window_handle().map_err(|e| Error::Invalid(format!("no window handle: {e}")))?.as_raw();
        let extensions = swapchain::required_instance_extensions(display)?;
        let desc = ContextDesc { window: true, ..options.context.clone() };
        let ctx = Context::with_instance_extensions(&desc, &extensions)?;
        let surface = ctx.create_surface(display, handle)?;
        let live = Live::from_scene(&options.scene, options);
        let samples = options.samples.unwrap_or_else(|| {
            let wanted = options.scene.render.samples;
            if ctx.info.kind == vk::PhysicalDeviceType::CPU && wanted > 1 {
                eprintln!("view: {} {CPU_MSAA_NOTE}", ctx.info.name);
                1
            } else {
                wanted
            }
        });
        let mut state = Self {
            window,
            ctx,
            surface: Some(surface),
            swapchain: None,
            sync: None,
            ring: None,
            gpu: None,
            screenshot: None,
            live,
            needs_resize: false,
            frame: 0,
            gpu_ms: None,
            frame_times: Vec::new(),
            timed_since: None,
            last_title: Instant::now(),
            fps_frames: 0,
            fps: 0.0,
            cursor: (0.0, 0.0),
            dragging: None,
            modifiers: Default::default(),
            screenshots_taken: 0,
            soak: Soak::default(),
            samples,
        };
        let built = (|| {
            state.sync = Some(state.ctx.create_frame_sync()?);
            state.ring = state.ctx.create_timestamp_ring(1, 1, "window timestamps")?;
            state.recreate_swapchain(options)?;
            state.rebuild(options)
        })();
        match built {
            Ok(()) => Ok(state),
            Err(e) => {
                let _ = state.destroy();
                Err(e)
            }
        }
    }

    /// (Re)prepares the materials and pipelines for the live settings.
    fn rebuild(&mut self, options: &ViewOptions) -> Result<()> {
        let (format, samples) = self
            .swapchain
            .as_ref()
            .map(|s| (s.format, s.samples))
            .ok_or_else(|| Error::Invalid("no swapchain".into()))?;
        // The frame in flight must finish before its resources go.
        let _ = self.ctx.wait_idle();
        if let Some(gpu) = self.gpu.take() {
            // SAFETY: the device is idle.
            unsafe {
                gpu.renderer.destroy(&self.ctx);
                gpu.map.destroy(&self.ctx);
                gpu.map_patch.destroy(&self.ctx);
            }
        }
        let scene = &options.scene;
        let mut materials = prepare_materials(scene, &self.live.overrides, &[crate::shading::Reach::ANY])?;
        for m in &mut materials {
            m.params.display[0] = self.live.exposure_ev.exp2() as f32;
        }
        let (inputs, objects) = (material_inputs(scene, &materials), scene_objects(scene));
        let renderer = Guard::new(&self.ctx, SceneRenderer::new(&self.ctx, &inputs, &objects, format, true, samples)?);
        let first = &materials[scene.objects[0].material];
        let map = Guard::new(&self.ctx, MapPass::new(&self.ctx, first, format, true, false)?);
        let map_patch = PatchResources::new(&self.ctx, first)?;
        let (renderer, map) = (renderer.keep(), map.keep());
        self.gpu = Some(Gpu { materials, renderer, map, map_patch });
        Ok(())
    }

    fn recreate_swapchain(&mut self, options: &ViewOptions) -> Result<()> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(()); // minimised: keep the old one until the window has an area again
        }
        let _ = self.ctx.wait_idle();
        let surface = self.surface.as_ref().ok_or_else(|| Error::Invalid("no surface".into()))?;
        let old = self.swapchain.take();
        let swapchain =
            self.ctx.create_swapchain(surface, (size.width, size.height), options.vsync, self.samples, old)?;
        if let Some(b) = self.screenshot.take() {
            // SAFETY: the device is idle.
            unsafe { b.destroy(&self.ctx) };
        }
        if swapchain.readable {
            let bytes = u64::from(swapchain.extent.width) * u64::from(swapchain.extent.height) * 4;
            self.screenshot = Some(self.ctx.create_buffer(BufferDesc::readback(bytes), "screenshot")?);
        }
        self.swapchain = Some(swapchain);
        self.needs_resize = false;
        Ok(())
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent, options: &ViewOptions) -> Result<()> {
        if event.state != ElementState::Pressed {
            return Ok(());
        }
        let shift = self.modifiers.shift_key();
        let live = &mut self.live;
        let before = live.overrides;
        let step = 5f32.to_radians();
        match &event.logical_key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Named(NamedKey::ArrowLeft) => live.light_azimuth -= step,
            Key::Named(NamedKey::ArrowRight) => live.light_azimuth += step,
            Key::Named(NamedKey::ArrowUp) => live.light_elevation = (live.light_elevation + step).min(1.55),
            Key::Named(NamedKey::ArrowDown) => live.light_elevation = (live.light_elevation - step).max(-1.55),
            Key::Character(c) => match c.to_lowercase().as_str() {
                "1" => live.overrides.approach = Some(Approach::Flss),
                "2" => live.overrides.approach = Some(Approach::Nmm),
                "3" => live.overrides.approach = Some(Approach::Pq),
                "4" => live.overrides.approach = Some(Approach::Gem),
                "5" => live.overrides.approach = Some(Approach::Baked),
                "t" => {
                    let n = self.gpu.as_ref().and_then(|g| g.materials[0].plan).map_or(10, |p| p.order);
                    live.overrides.order = Some(if shift { n.saturating_sub(1) } else { n + 1 });
                }
                "l" => {
                    let s = self.gpu.as_ref().map_or(5.0, |g| g.materials[0].sampling.step_nm);
                    live.overrides.lambda_step_nm = Some(if shift { (s - 1.0).max(1.0) } else { s + 1.0 });
                }
                "r" => {
                    let r = self.gpu.as_ref().map_or(1, |g| g.materials[0].window.radius_x as u32);
                    live.overrides.window_radius = Some(if shift { r.saturating_sub(1) } else { (r + 1).min(16) });
                }
                "+" | "=" => live.exposure_ev += 0.5,
                "-" | "_" => live.exposure_ev -= 0.5,
                "m" => live.map_mode = !live.map_mode,
                "h" => println!("{BINDINGS}"),
                "p" => {
                    self.screenshots_taken += 1;
                    let path = PathBuf::from(format!("diffract-{:04}.png", self.screenshots_taken));
                    return self.draw_and_save(options, &path);
                }
                _ => {}
            },
            _ => {}
        }
        if self.live.overrides != before {
            // Accept f32 trouble while exploring: the title says when the plan refused it.
            self.live.overrides.accept_f32_error = true;
            self.rebuild(options)?;
        } else if let Some(gpu) = self.gpu.as_mut() {
            gpu.renderer.set_exposure(self.live.exposure_ev)?;
        }
        Ok(())
    }

    fn drag(&mut self, x: f64, y: f64) {
        let (dx, dy) = ((x - self.cursor.0) as f32, (y - self.cursor.1) as f32);
        self.cursor = (x, y);
        let live = &mut self.live;
        match self.dragging {
            Some(MouseButton::Left) if self.modifiers.control_key() => {
                live.light_azimuth += dx * 0.01;
                live.light_elevation = (live.light_elevation - dy * 0.01).clamp(-1.55, 1.55);
            }
            Some(MouseButton::Right) | Some(MouseButton::Left)
                if self.dragging == Some(MouseButton::Right) || self.modifiers.shift_key() =>
            {
                let forward = -live.eye_direction();
                let right = forward.cross(Vec3::Y).normalize_or_zero();
                let up = right.cross(forward);
                live.target += (-right * dx + up * dy) * live.distance * 0.002;
            }
            Some(MouseButton::Left) => {
                live.yaw -= dx * 0.01;
                live.pitch = (live.pitch + dy * 0.01).clamp(-1.5, 1.5);
            }
            _ => {}
        }
    }

    fn draw_and_save(&mut self, options: &ViewOptions, path: &std::path::Path) -> Result<()> {
        self.render(options, true)?;
        self.save_screenshot(path)
    }

    fn draw(&mut self, event_loop: &ActiveEventLoop, options: &ViewOptions) -> Result<()> {
        let last = options.frames.is_some_and(|n| self.frame + 1 >= n);
        self.render(options, last && options.screenshot.is_some())?;
        if let Some(n) = options.resize_after {
            if self.frame == n {
                let size = self.window.inner_size();
                let _ = self.window.request_inner_size(PhysicalSize::new(size.width * 3 / 4, size.height * 3 / 4));
            }
        }
        if options.soak {
            self.soak_step(options, last)?;
        }
        if last {
            if let Some(path) = &options.screenshot {
                self.save_screenshot(path)?;
            }
            self.print_frame_times();
            event_loop.exit();
        }
        Ok(())
    }

    /// The soak: after every [`SOAK_PERIOD`] frames a new window size and the next approach (rebuilt as a key
    /// press would); resident memory noted after the first frame and after the first round of approaches, and
    /// printed with the end's on the last frame.
    fn soak_step(&mut self, options: &ViewOptions, last: bool) -> Result<()> {
        let approaches = Approach::ALL.len() as u32;
        if self.frame == 1 {
            self.soak.rss_first = resident_mib();
        }
        if self.frame == SOAK_PERIOD * (approaches + 1) {
            self.soak.rss_round = resident_mib();
        }
        if last {
            let mib = |m: Option<f64>| m.map_or("n/a".to_string(), |m| format!("{m:.1} MiB"));
            println!(
                "soak: {} frames, {} resizes, {} approach switches; resident memory {} after the first frame, {} \
                 after the first round of approaches, {} at the end",
                self.frame,
                self.soak.resizes,
                self.soak.switches,
                mib(self.soak.rss_first),
                mib(self.soak.rss_round),
                mib(resident_mib())
            );
            return Ok(());
        }
        if self.frame % SOAK_PERIOD != 0 || self.frame == self.soak.stepped_at {
            return Ok(());
        }
        self.soak.stepped_at = self.frame;
        let step = self.frame / SOAK_PERIOD;
        let (num, den) = SOAK_SIZES[(step as usize - 1) % SOAK_SIZES.len()];
        let size = PhysicalSize::new((options.width * num / den).max(16), (options.height * num / den).max(16));
        let _ = self.window.request_inner_size(size);
        self.soak.resizes += 1;
        let current = self.gpu.as_ref().map_or(Approach::Baked, |g| g.materials[0].settings.approach);
        let next = Approach::ALL.iter().position(|&a| a == current).map_or(0, |i| (i + 1) % Approach::ALL.len());
        self.live.overrides.approach = Some(Approach::ALL[next]);
        self.live.overrides.accept_f32_error = true;
        self.rebuild(options)?;
        self.soak.switches += 1;
        Ok(())
    }

    /// The scripted frames' cost, after the first: GPU ms (median, p10, p90) and the frame rate of the window.
    fn print_frame_times(&self) {
        let size = self.window.inner_size();
        let Some(spread) = crate::stats::Spread::of(&self.frame_times) else { return };
        let fps = self.timed_since.map(|t| (self.frame_times.len() + 1) as f64 / t.elapsed().as_secs_f64());
        println!(
            "{} frames at {}×{} after the first: GPU {:.1} ms per frame (median; p10 {:.1}, p90 {:.1}){}",
            self.frame_times.len(),
            size.width,
            size.height,
            spread.median,
            spread.p10,
            spread.p90,
            fps.map(|f| format!(", {f:.1} fps in the window")).unwrap_or_default()
        );
    }

    /// Draws one frame; with `copy`, also copies it into the screenshot buffer.
    fn render(&mut self, options: &ViewOptions, copy: bool) -> Result<()> {
        if self.needs_resize {
            self.recreate_swapchain(options)?;
        }
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(());
        }
        let (Some(sync), Some(gpu)) = (self.sync.as_ref(), self.gpu.as_mut()) else { return Ok(()) };
        let Some(swapchain) = self.swapchain.as_ref() else { return Ok(()) };
        sync.wait(&self.ctx)?;
        if self.frame > 0 {
            if let Some(r) = &self.ring {
                self.gpu_ms = r.read(&self.ctx, 0)?.first().map(|s| s.ms);
                if self.frame > 1 {
                    self.frame_times.extend(self.gpu_ms);
                } else {
                    self.timed_since = Some(Instant::now());
                }
            }
        }
        let index = match swapchain.acquire(sync.image_available)? {
            Acquired::Image { index, suboptimal } => {
                self.needs_resize |= suboptimal;
                index
            }
            Acquired::OutOfDate => {
                self.needs_resize = true;
                return Ok(());
            }
        };
        let camera = self.live.camera(&options.scene.camera);
        let light = self.live.light();
        let aspect = swapchain.extent.width as f32 / swapchain.extent.height as f32;
        let models: Vec<_> = options.scene.objects.iter().map(|o| o.model).collect();
        gpu.renderer.update(&camera, light, options.scene.ambient, &models, aspect)?;
        if self.live.map_mode {
            // The map shows the first object's material as a horizontal patch with its x axis along the world's x:
            // patch (x, y, z) = world (x, −z, y).
            let map_light = Vec3::new(light.x, -light.z, light.y);
            let mut params = light_params(&gpu.materials[options.scene.objects[0].material], map_light.as_dvec3());
            params.display[0] = self.live.exposure_ev.exp2() as f32;
            gpu.map_patch.update(&params)?;
        }
        sync.begin(&self.ctx)?;
        let cmd = sync.cmd;
        let image = swapchain.images[index as usize];
        let presented = swapchain.views[index as usize];
        // The scene is drawn into the multisampled image (if any) and resolved into the presented one; the map is
        // a full-screen pass drawn straight into it.
        let (color, resolve, samples, depth) = match (&swapchain.msaa, self.live.map_mode) {
            (Some(msaa), false) => (msaa.view, Some(presented), swapchain.samples, Some(swapchain.depth.view)),
            // The map has no depth; a multisampled depth buffer would not match its single-sampled target.
            (Some(_), true) => (presented, None, vk::SampleCountFlags::TYPE_1, None),
            (None, _) => (presented, None, vk::SampleCountFlags::TYPE_1, Some(swapchain.depth.view)),
        };
        let target = TargetView { color, resolve, depth, extent: swapchain.extent, samples };
        self.ctx.barrier_raw_image(
            cmd,
            image,
            Swapchain::color_range(),
            ImageState::UNDEFINED,
            ImageState::COLOR_ATTACHMENT,
        );
        swapchain.begin_attachments(&self.ctx, cmd);
        let mut ring = self.ring.take();
        let scope = ring.as_mut().map(|r| {
            r.begin_frame(&self.ctx, cmd, 0);
            r.begin_scope(&self.ctx, cmd, if self.live.map_mode { MapPass::NAME } else { SceneRenderer::NAME })
        });
        let bg = options.scene.render.background;
        if self.live.map_mode {
            gpu.map.record(&self.ctx, cmd, &gpu.map_patch, &target, None);
        } else {
            let bg =
                (glam::DVec3::new(bg[0].into(), bg[1].into(), bg[2].into()) * self.live.exposure_ev.exp2()).as_vec3();
            let encode = |c: f32| crate::physics::spectrum::srgb_oetf(f64::from(c)) as f32;
            gpu.renderer.record(&self.ctx, cmd, &target, [encode(bg.x), encode(bg.y), encode(bg.z), 1.0]);
        }
        if let (Some(r), Some(Ok(i))) = (ring.as_mut(), scope) {
            r.end_scope(&self.ctx, cmd, i);
        }
        self.ring = ring;
        match (copy, &self.screenshot) {
            (true, Some(buffer)) => swapchain.record_copy(&self.ctx, cmd, index, buffer),
            (true, None) => {
                return Err(Error::Invalid("this window's images cannot be copied for a screenshot".into()))
            }
            _ => self.ctx.barrier_raw_image(
                cmd,
                image,
                Swapchain::color_range(),
                ImageState::COLOR_ATTACHMENT,
                ImageState::PRESENT,
            ),
        }
        // SAFETY: the command buffer was begun above.
        unsafe { self.ctx.device().end_command_buffer(cmd) }
            .map_err(|result| Error::Vulkan { call: "vkEndCommandBuffer", result })?;
        self.ctx.submit_frame(sync, swapchain.render_finished[index as usize])?;
        if !swapchain.present(self.ctx.queue(), index)? {
            self.needs_resize = true;
        }
        self.frame += 1;
        self.update_title();
        Ok(())
    }

    fn save_screenshot(&self, path: &std::path::Path) -> Result<()> {
        let (Some(sync), Some(swapchain), Some(buffer)) = (&self.sync, &self.swapchain, &self.screenshot) else {
            return Err(Error::Invalid("no frame to save".into()));
        };
        sync.wait(&self.ctx)?;
        let bytes = self.ctx.read_buffer(buffer)?;
        let bgra = swapchain.format == ash::vk::Format::B8G8R8A8_UNORM;
        let rgba: Vec<u8> = bytes
            .chunks(4)
            .flat_map(|p| if bgra { [p[2], p[1], p[0], 255] } else { [p[0], p[1], p[2], 255] })
            .collect();
        crate::output::write_png_rgba8(path, swapchain.extent.width, swapchain.extent.height, &rgba)?;
        println!("wrote {}", path.display());
        Ok(())
    }

    fn update_title(&mut self) {
        self.fps_frames += 1;
        let elapsed = self.last_title.elapsed().as_secs_f64();
        if elapsed < 0.5 && self.frame > 1 {
            return;
        }
        self.fps = f64::from(self.fps_frames) / elapsed.max(1e-9);
        self.fps_frames = 0;
        self.last_title = Instant::now();
        let Some(gpu) = &self.gpu else { return };
        let m = &gpu.materials[0];
        // What the approach's accuracy is made of: the baked table's texels and terms in w, or the Taylor order,
        // wavelength step and window radius.
        let settings = match (&m.table, m.plan) {
            (Some(t), _) => format!("table {}×{} w:{}", t.grid.nu, t.grid.nv, t.terms),
            (None, plan) => format!(
                "{} Δλ={} nm r={}",
                plan.map_or("no terms".into(), |p| format!("N={}", p.order)),
                m.sampling.step_nm,
                m.window.radius_x
            ),
        };
        let gpu_ms = self.gpu_ms.map(|ms| format!("GPU {ms:.1} ms")).unwrap_or_else(|| "GPU –".into());
        self.window.set_title(&format!(
            "diffract — {} {settings} EV={:+.1} — {} — {gpu_ms} — {:.1} fps — H: help",
            m.settings.approach.name(),
            self.live.exposure_ev,
            if self.live.map_mode { "BRDF map" } else { "geometry" },
            self.fps
        ));
    }

    /// Destroys everything the window made; returns the names of allocations still live after it (none
    /// unless something leaked).
    fn destroy(mut self) -> Vec<String> {
        let _ = self.ctx.wait_idle();
        // SAFETY: the device is idle; everything is destroyed once, children before their parents, the surface
        // before the window (dropped last with `self`).
        unsafe {
            if let Some(gpu) = self.gpu.take() {
                gpu.renderer.destroy(&self.ctx);
                gpu.map.destroy(&self.ctx);
                gpu.map_patch.destroy(&self.ctx);
            }
            if let Some(b) = self.screenshot.take() {
                b.destroy(&self.ctx);
            }
            if let Some(r) = self.ring.take() {
                r.destroy(&self.ctx);
            }
            if let Some(s) = self.sync.take() {
                s.destroy(&self.ctx);
            }
            if let Some(s) = self.swapchain.take() {
                s.destroy(&self.ctx);
            }
            if let Some(s) = self.surface.take() {
                s.destroy();
            }
        }
        self.ctx.live_allocations()
    }
}
