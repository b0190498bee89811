//! `diffract view`: a scene in a window (winit + a Vulkan swapchain), with an orbit camera, light control and
//! the speed/accuracy settings changed live; the title shows the approach, its settings, the GPU time per frame
//! (timestamp queries) and the frame rate. `--frames N --screenshot FILE` renders N frames, writes the last and
//! exits, for tests and demos.

mod controls;

use std::path::{Path, PathBuf};
use std::time::Instant;

use ash::vk;
use glam::{DVec3, Vec3};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

pub use controls::BINDINGS;
use controls::{Input, Live, Request};

use crate::display::tone::encode;
use crate::error::{Error, Result};
use crate::gpu::vk::swapchain;
use crate::gpu::vk::FrameTimes;
use crate::gpu::vk::{Context, ContextDesc, Guard, Owned};
use crate::material::{Approach, SettingsPatch};
use crate::material::{Material, Reach};
use crate::render::capture::{material_inputs, prepare_materials, scene_objects};
use crate::render::diffraction::{light_params, PatchResources};
use crate::render::map::MapPass;
use crate::render::surface::{RendererSetup, SceneRenderer};
use crate::render::window::{WindowFrame, WindowTarget};
use crate::render::Instruments;
use crate::render::SceneView;
use crate::scene::Scene;

/// What `diffract view` was asked for.
pub struct ViewOptions {
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    pub vsync: bool,
    pub context: ContextDesc,
    pub overrides: SettingsPatch,
    /// None: measured from the first frame of the prepared materials (not the stand-in), as `render` does.
    pub exposure_ev: Option<f64>,
    /// The tone curve the window shows light through.
    pub tone: crate::display::Tone,
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

/// Why the viewer does not multisample on a CPU implementation unless asked: multisampled, lavapipe runs the
/// fragment shader also where a nearer surface hides the fragment (the snake's overlapping scales, ~2.4 layers
/// per visible pixel), so 4× multisampling costs about 3× the frame (`diffract profile --width 800 --sweep
/// samples=1,4 --no-reference` on the default scene: 41.5 → 135 ms; docs/performance.md).
pub const CPU_MSAA_NOTE: &str = "is a CPU implementation, where multisampling costs about 3× the frame time (it \
                                 also shades what nearer surfaces hide): edges are not anti-aliased (--samples 4 \
                                 turns it on)";

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
        Error::Window(format!("cannot open a window ({e}); `diffract view` needs a desktop (DISPLAY or WAYLAND_DISPLAY) — use `diffract render` for headless images"))
    })?;
    let mut app = App { options, state: None, error: None, log: None };
    event_loop.run_app(&mut app).map_err(|e| Error::Window(format!("the window's event loop failed: {e}")))?;
    if let Some(e) = app.error {
        return Err(e);
    }
    Ok(app.log.map_or(0, |l| l.count()))
}

struct App {
    options: ViewOptions,
    state: Option<State>,
    error: Option<Error>,
    log: Option<std::sync::Arc<crate::gpu::vk::ValidationLog>>,
}

/// What the window draws with: the materials prepared for the live settings and the passes built for them.
struct Gpu {
    materials: Vec<Material>,
    renderer: SceneRenderer,
    map: MapPass,
    map_patch: PatchResources,
}

/// The viewer's frame counts and timings.
struct Timing {
    /// Frames presented.
    frame: u32,
    /// The GPU times of the last frame measured, pass by pass.
    last: Option<FrameTimes>,
    /// The passes' GPU times of every frame after the first (the first includes the driver's shader compilation).
    frame_times: Vec<FrameTimes>,
    /// When the scripted frames started (after the first).
    timed_since: Option<Instant>,
    /// The title's frame rate: when it was last shown, frames since, and its value.
    last_title: Instant,
    fps_frames: u32,
    fps: f64,
}

/// The scene's materials being prepared on another thread (a baked table that is not in the cache takes seconds)
/// while the window shows a stand-in; installed by the first frame drawn after they are ready.
struct Pending {
    /// The settings they are prepared for (a key that changes them drops the job).
    overrides: SettingsPatch,
    done: std::sync::mpsc::Receiver<Result<Vec<Material>>>,
    since: Instant,
}

/// How long the window waits for the materials before it shows a stand-in instead (a cached table is ready well
/// within it), unless `DIFFRACT_VIEW_WAIT_MS` says otherwise.
const FIRST_FRAME_WAIT_MS: u64 = 700;

/// [`FIRST_FRAME_WAIT_MS`], or `DIFFRACT_VIEW_WAIT_MS` where that is set to a number of milliseconds.
fn first_frame_wait() -> std::time::Duration {
    let ms = std::env::var("DIFFRACT_VIEW_WAIT_MS").ok().and_then(|v| v.trim().parse().ok());
    std::time::Duration::from_millis(ms.unwrap_or(FIRST_FRAME_WAIT_MS))
}

/// The approach of the stand-in: analytic, no table to build.
const STAND_IN: Approach = Approach::Gem;
/// How often the stand-in is drawn (it would otherwise take the cores the bake needs).
const STAND_IN_PERIOD: std::time::Duration = std::time::Duration::from_millis(250);

struct State {
    /// Dropped after the target (its surface), which [`State::destroy`] destroys first.
    window: Window,
    /// Materials still being prepared, while `gpu` draws a stand-in.
    pending: Option<Pending>,
    /// When the last frame was drawn, and when the window was asked for (the first frame's latency is printed).
    last_drawn: Instant,
    opened: Instant,
    /// The window was asked to shrink (`--resize-after`).
    resized: bool,
    ctx: Context,
    target: WindowTarget,
    gpu: Gpu,
    live: Live,
    input: Input,
    timing: Timing,
    screenshots_taken: u32,
    soak: Soak,
    /// The exposure is still to be measured (the scene and the command line set none).
    measure_exposure: bool,
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
                outln!("{BINDINGS}");
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
                state.target.mark_stale();
                Ok(())
            }
            WindowEvent::ModifiersChanged(m) => {
                state.input.modifiers = m.state();
                Ok(())
            }
            WindowEvent::KeyboardInput { event, .. } => state.key(event_loop, &event, &self.options),
            WindowEvent::MouseInput { state: pressed, button, .. } => {
                state.input.dragging = (pressed == ElementState::Pressed).then_some(button);
                Ok(())
            }
            WindowEvent::CursorMoved { position, .. } => {
                state.input.drag(&mut state.live, position.x, position.y);
                Ok(())
            }
            WindowEvent::MouseWheel { delta, .. } => {
                state.live.zoom(delta);
                Ok(())
            }
            WindowEvent::RedrawRequested => state.draw(event_loop, &self.options),
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.fail(event_loop, e);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(state) = &self.state else { return };
        // While the materials are prepared, the stand-in is drawn a few times a second: the cores are the bake's.
        let due = state.pending.as_ref().map(|_| state.last_drawn + STAND_IN_PERIOD);
        match due.filter(|&due| due > Instant::now()) {
            Some(due) => event_loop.set_control_flow(ControlFlow::WaitUntil(due)),
            None => {
                event_loop.set_control_flow(ControlFlow::Poll);
                state.window.request_redraw();
            }
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(state) = self.state.take() {
            let live = state.destroy();
            if self.options.soak {
                outln!("soak: {} GPU allocations live at teardown", live.len());
            }
            if !live.is_empty() && self.error.is_none() {
                self.error = Some(Error::Window(format!(
                    "a bug in diffract: {} GPU allocations still live when the window closed ({})",
                    live.len(),
                    live.join(", ")
                )));
            }
        }
    }
}

/// The first materials and passes: prepared on another thread and waited for up to [`first_frame_wait`]; where
/// that is not enough (a baked table not yet in the cache), the job goes on while [`STAND_IN`] is drawn.
fn first_gpu(ctx: &Context, scene: &Scene, live: &Live, target: &WindowTarget) -> Result<(Gpu, Option<Pending>)> {
    use std::sync::mpsc::RecvTimeoutError;
    let (send, done) = std::sync::mpsc::channel();
    let (job, overrides, since) = (scene.clone(), live.overrides, Instant::now());
    std::thread::Builder::new()
        .name("materials".into())
        .spawn(move || {
            // The receiver is gone only when the window closed first: nothing is waiting then.
            let _ = send.send(prepare_materials(&job, &overrides, &[Reach::ANY]));
        })
        .map_err(|e| Error::Window(format!("cannot start a thread to prepare the materials: {e}")))?;
    match done.recv_timeout(first_frame_wait()) {
        Ok(materials) => Ok((Gpu::with_materials(ctx, scene, live, target, materials?)?, None)),
        Err(RecvTimeoutError::Timeout) => {
            let stand_in = SettingsPatch { approach: Some(STAND_IN), ..overrides };
            let materials = crate::render::capture::prepare_stand_ins(scene, &stand_in)?;
            outln!(
                "view: preparing the materials (a baked table that is not in the cache yet takes a while); {} stands \
                 in until they are ready",
                STAND_IN.name()
            );
            let gpu = Gpu::with_materials(ctx, scene, live, target, materials)?;
            Ok((gpu, Some(Pending { overrides, done, since })))
        }
        Err(RecvTimeoutError::Disconnected) => {
            Err(Error::Window("the thread preparing the materials stopped (a bug in diffract)".into()))
        }
    }
}

impl Gpu {
    /// Prepares the scene's materials for the live settings and builds the passes for the window's target.
    fn new(ctx: &Context, scene: &Scene, live: &Live, target: &WindowTarget) -> Result<Self> {
        let materials = prepare_materials(scene, &live.overrides, &[Reach::ANY])?;
        Self::with_materials(ctx, scene, live, target, materials)
    }

    /// The passes for prepared `materials`.
    fn with_materials(
        ctx: &Context,
        scene: &Scene,
        live: &Live,
        target: &WindowTarget,
        mut materials: Vec<Material>,
    ) -> Result<Self> {
        for m in &mut materials {
            m.set_display(live.exposure_ev, live.tone);
        }
        let (inputs, objects) = (material_inputs(scene, &materials), scene_objects(scene));
        let (format, samples) = (target.format(), target.samples());
        let setup = RendererSetup::forward(format, true, samples);
        let first = SceneView::lit(scene, live.camera(&scene.camera), live.light());
        let renderer = SceneRenderer::new(ctx, (&inputs, &objects), setup, (&first, target.extent()))?;
        let renderer = Guard::new(ctx, renderer);
        let first = &materials[scene.objects[0].material];
        let map = Guard::new(ctx, MapPass::new(ctx, first, format, true, false)?);
        let map_patch = PatchResources::new(ctx, first)?;
        Ok(Self { renderer: renderer.keep(), map: map.keep(), map_patch, materials })
    }

    /// # Safety
    /// No pending work may use the passes.
    unsafe fn destroy(self, ctx: &Context) {
        self.renderer.destroy(ctx);
        self.map.destroy(ctx);
        self.map_patch.destroy(ctx);
    }
}

crate::impl_destroy!(Gpu);

impl Timing {
    fn new() -> Self {
        Self {
            frame: 0,
            last: None,
            frame_times: Vec::new(),
            timed_since: None,
            last_title: Instant::now(),
            fps_frames: 0,
            fps: 0.0,
        }
    }

    /// Notes the GPU times of the frame before the one begun now.
    fn measured(&mut self, previous: Option<FrameTimes>) {
        let Some(times) = previous else { return };
        self.last = Some(times.clone());
        if self.frame > 1 {
            self.frame_times.push(times);
        } else {
            self.timed_since = Some(Instant::now());
        }
    }

    /// Counts a presented frame; true when the title's frame rate is due for an update (every half second).
    fn presented(&mut self) -> bool {
        self.frame += 1;
        self.fps_frames += 1;
        let elapsed = self.last_title.elapsed().as_secs_f64();
        if elapsed < 0.5 && self.frame > 1 {
            return false;
        }
        self.fps = f64::from(self.fps_frames) / elapsed.max(1e-9);
        self.fps_frames = 0;
        self.last_title = Instant::now();
        true
    }
}

impl State {
    fn new(event_loop: &ActiveEventLoop, options: &ViewOptions) -> Result<Self> {
        let opened = Instant::now();
        let attributes = Window::default_attributes()
            .with_title("diffract")
            .with_inner_size(PhysicalSize::new(options.width, options.height));
        let window =
            event_loop.create_window(attributes).map_err(|e| Error::Window(format!("cannot open a window: {e}")))?;
        let display = window.display_handle().map_err(|e| Error::Window(format!("no display handle: {e}")))?.as_raw();
        let handle = window.window_handle().map_err(|e| Error::Window(format!("no window handle: {e}")))?.as_raw();
        let extensions = swapchain::required_instance_extensions(display)?;
        let desc = ContextDesc { window: true, ..options.context.clone() };
        let ctx = Context::with_instance_extensions(&desc, &extensions)?;
        let samples = options.samples.unwrap_or_else(|| {
            let wanted = options.scene.render.samples;
            if ctx.info.kind == vk::PhysicalDeviceType::CPU && wanted > 1 {
                errln!("view: {} {CPU_MSAA_NOTE}", ctx.info.name);
                1
            } else {
                wanted
            }
        });
        let size = window.inner_size();
        let target = WindowTarget::new(&ctx, (display, handle), (size.width, size.height), options.vsync, samples)?;
        let target = Guard::new(&ctx, target);
        let mut live = Live::from_scene(&options.scene, options.overrides, options.exposure_ev.unwrap_or(0.0));
        live.tone = options.tone;
        let (gpu, pending) = first_gpu(&ctx, &options.scene, &live, &target)?;
        let target = target.keep();
        let mut state = Self {
            window,
            pending,
            last_drawn: Instant::now(),
            opened,
            resized: false,
            ctx,
            target,
            gpu,
            live,
            input: Input::default(),
            timing: Timing::new(),
            screenshots_taken: 0,
            soak: Soak::default(),
            measure_exposure: options.exposure_ev.is_none(),
        };
        if state.pending.is_none() {
            state.measure_exposure(options)?;
        }
        Ok(state)
    }

    /// Where the exposure is still to be measured: from a small offscreen frame of the prepared materials at the
    /// live camera and light (the stand-in's colours are not the scene's), as `render` measures its first frame.
    fn measure_exposure(&mut self, options: &ViewOptions) -> Result<()> {
        if !self.measure_exposure {
            return Ok(());
        }
        self.measure_exposure = false;
        let scene = &options.scene;
        let (w, h) = (128, (128 * options.height / options.width.max(1)).clamp(16, 512));
        let one = ash::vk::SampleCountFlags::TYPE_1;
        let capture = crate::render::capture::SceneCapture::new(&self.ctx, scene, &self.gpu.materials, w, h, one)?;
        let mut capture = Owned::new(&self.ctx, capture);
        let view = SceneView::lit(scene, self.live.camera(&scene.camera), self.live.light());
        let frame = capture.render(&self.ctx, &view)?;
        let (ev, line) = capture.meter(&self.ctx, &view, frame.linear().unwrap_or_default(), self.live.tone)?;
        outln!("view: {line}");
        self.live.exposure_ev = ev;
        self.gpu.renderer.set_display(ev, self.live.tone)?;
        Ok(())
    }

    /// Re-prepares the materials and passes for the live settings (the old ones stay if that fails).
    fn rebuild(&mut self, options: &ViewOptions) -> Result<()> {
        let gpu = Gpu::new(&self.ctx, &options.scene, &self.live, &self.target)?;
        self.pending = None;
        self.install(gpu)
    }

    /// Draws with `gpu` from the next frame on.
    fn install(&mut self, gpu: Gpu) -> Result<()> {
        // The frame in flight must finish before the old resources go.
        self.ctx.wait_idle()?;
        let old = std::mem::replace(&mut self.gpu, gpu);
        // SAFETY: the device is idle.
        unsafe { old.destroy(&self.ctx) };
        Ok(())
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent, options: &ViewOptions) -> Result<()> {
        if event.state != ElementState::Pressed {
            return Ok(());
        }
        let before = self.live.overrides;
        let shift = self.input.modifiers.shift_key();
        match self.live.key(&event.logical_key, shift, &self.gpu.materials[0]) {
            Request::Nothing => {}
            Request::Quit => event_loop.exit(),
            Request::Help => outln!("{BINDINGS}"),
            Request::Screenshot => {
                self.screenshots_taken += 1;
                let path = PathBuf::from(format!("diffract-{:04}.png", self.screenshots_taken));
                return self.draw_and_save(options, &path);
            }
        }
        if self.live.overrides != before {
            // Accept f32 trouble while exploring: the title says when the plan refused it.
            self.live.overrides.accept_f32_error = true;
            self.rebuild(options)?;
        } else {
            self.gpu.renderer.set_display(self.live.exposure_ev, self.live.tone)?;
        }
        Ok(())
    }

    fn draw_and_save(&mut self, options: &ViewOptions, path: &Path) -> Result<()> {
        self.render(options, true)?;
        self.save_screenshot(path)
    }

    /// Installs the materials prepared on another thread once they are ready; the scripted frames and their
    /// timings start again with them.
    fn poll_pending(&mut self, options: &ViewOptions) -> Result<()> {
        let Some(pending) = &self.pending else { return Ok(()) };
        let materials = match pending.done.try_recv() {
            Err(std::sync::mpsc::TryRecvError::Empty) => return Ok(()),
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                return Err(Error::Window("the thread preparing the materials stopped (a bug in diffract)".into()))
            }
            Ok(materials) => materials?,
        };
        let seconds = pending.since.elapsed().as_secs_f64();
        self.pending = None;
        let gpu = Gpu::with_materials(&self.ctx, &options.scene, &self.live, &self.target, materials)?;
        self.install(gpu)?;
        outln!("view: the materials are ready after {seconds:.1} s; drawing them from now on");
        self.measure_exposure(options)?;
        self.timing = Timing::new();
        Ok(())
    }

    fn draw(&mut self, event_loop: &ActiveEventLoop, options: &ViewOptions) -> Result<()> {
        self.poll_pending(options)?;
        // Scripted frames count only once the asked-for materials are drawn.
        let last = self.pending.is_none() && options.frames.is_some_and(|n| self.timing.frame + 1 >= n);
        self.render(options, last && options.screenshot.is_some())?;
        // Once: the frame count starts again when prepared materials replace a stand-in.
        if let Some(n) = options.resize_after.filter(|_| !self.resized) {
            if self.timing.frame == n {
                self.resized = true;
                let size = self.window.inner_size();
                let _ = self.window.request_inner_size(PhysicalSize::new(size.width * 3 / 4, size.height * 3 / 4));
            }
        }
        if options.soak && self.pending.is_none() {
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
        let frame = self.timing.frame;
        if frame == 1 {
            self.soak.rss_first = resident_mib();
        }
        if frame == SOAK_PERIOD * (approaches + 1) {
            self.soak.rss_round = resident_mib();
        }
        if last {
            let mib = |m: Option<f64>| m.map_or("n/a".to_string(), |m| format!("{m:.1} MiB"));
            outln!(
                "soak: {frame} frames, {} resizes, {} approach switches; resident memory {} after the first frame, \
                 {} after the first round of approaches, {} at the end",
                self.soak.resizes,
                self.soak.switches,
                mib(self.soak.rss_first),
                mib(self.soak.rss_round),
                mib(resident_mib())
            );
            return Ok(());
        }
        if frame % SOAK_PERIOD != 0 || frame == self.soak.stepped_at {
            return Ok(());
        }
        self.soak.stepped_at = frame;
        let (num, den) = SOAK_SIZES[(frame / SOAK_PERIOD - 1) as usize % SOAK_SIZES.len()];
        let size = PhysicalSize::new((options.width * num / den).max(16), (options.height * num / den).max(16));
        let _ = self.window.request_inner_size(size);
        self.soak.resizes += 1;
        let current = self.gpu.materials[0].settings.approach;
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
        let t = &self.timing;
        let totals: Vec<f64> = t.frame_times.iter().map(FrameTimes::total_ms).collect();
        let Some(spread) = crate::io::stats::Spread::of(&totals) else { return };
        let fps = t.timed_since.map(|since| (t.frame_times.len() + 1) as f64 / since.elapsed().as_secs_f64());
        outln!(
            "{} frames at {}×{} after the first: GPU {:.1} ms per frame (median; p10 {:.1}, p90 {:.1}){}",
            t.frame_times.len(),
            size.width,
            size.height,
            spread.median,
            spread.p10,
            spread.p90,
            fps.map(|f| format!(", {f:.1} fps in the window")).unwrap_or_default()
        );
        if let Some(passes) = crate::render::pass_medians(&t.frame_times) {
            outln!("GPU ms per pass (median): {passes}");
        }
    }

    /// Draws one frame (if the window can show one now); with `copy`, also copies it for a screenshot.
    fn render(&mut self, options: &ViewOptions, copy: bool) -> Result<()> {
        let size = self.window.inner_size();
        let Some(frame) = self.target.begin_frame(&self.ctx, (size.width, size.height))? else {
            return Ok(());
        };
        self.timing.measured(frame.previous.clone());
        self.record(options, &frame)?;
        self.target.end_frame(&self.ctx, frame, copy)?;
        self.last_drawn = Instant::now();
        if self.timing.frame == 0 && self.pending.is_some() {
            outln!("view: first frame (the stand-in) after {:.1} s", self.opened.elapsed().as_secs_f64());
        }
        if self.timing.presented() {
            self.update_title();
        }
        Ok(())
    }

    /// Updates the uniforms for the live camera and light and records the frame's pass: the scene, or the first
    /// object's BRDF map.
    fn record(&mut self, options: &ViewOptions, frame: &WindowFrame) -> Result<()> {
        let (ctx, gpu, scene) = (&self.ctx, &mut self.gpu, &options.scene);
        let laps = self.target.laps(ctx);
        let light = self.live.light();
        let view = SceneView::lit(scene, self.live.camera(&scene.camera), light);
        let extent = frame.extent();
        gpu.renderer.update(ctx, &view, extent.width as f32 / extent.height as f32)?;
        let exposure = self.live.exposure_scale();
        if self.live.map_mode {
            // The map shows the first object's material as a horizontal patch with its x axis along the world's x:
            // patch (x, y, z) = world (x, −z, y).
            let map_light = Vec3::new(light.x, -light.z, light.y);
            let mut params = light_params(&gpu.materials[scene.objects[0].material], map_light.as_dvec3());
            params.display = crate::display::tone::display_uniform(self.live.exposure_ev, self.live.tone);
            gpu.map_patch.update(&params)?;
            gpu.map.record(ctx, frame.cmd, &gpu.map_patch, &frame.flat(), None, None);
            laps.lap(frame.cmd, crate::render::pass::SHADING);
        } else {
            // Cleared to the code values the shaders give the background colour (the images are UNORM).
            let [r, g, b] = scene.render.background.map(f64::from);
            let [r, g, b] = encode(DVec3::new(r, g, b), exposure, self.live.tone).map(|c| f32::from(c) / 255.0);
            let instruments = Instruments { laps, ..Instruments::default() };
            gpu.renderer.record_with(ctx, frame.cmd, &frame.scene(), [r, g, b, 1.0], instruments);
        }
        Ok(())
    }

    fn save_screenshot(&self, path: &Path) -> Result<()> {
        self.target.save_screenshot(&self.ctx, path)?;
        outln!("wrote {}", path.display());
        Ok(())
    }

    /// The title: the approach and what its accuracy is made of, the exposure and tone curve, the mode, the GPU
    /// time and the frame rate.
    fn update_title(&self) {
        let m = &self.gpu.materials[0];
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
        let gpu_ms = self.timing.last.as_ref().map_or_else(|| "GPU –".into(), |t| format!("GPU {}", t.describe()));
        let waiting = self.pending.as_ref().map_or(String::new(), |p| {
            let asked = p.overrides.approach.map_or("the scene's approach", Approach::name);
            format!(" (standing in while {asked} is prepared, {:.0} s)", p.since.elapsed().as_secs_f64())
        });
        self.window.set_title(&format!(
            "diffract — {}{waiting} {settings} EV={:+.1} {} — {} — {gpu_ms} — {:.1} fps — H: help",
            m.settings.approach.name(),
            self.live.exposure_ev,
            self.live.tone.name(),
            if self.live.map_mode { "BRDF map" } else { "geometry" },
            self.timing.fps
        ));
    }

    /// Destroys everything the window made; returns the names of allocations still live after it (none
    /// unless something leaked).
    fn destroy(self) -> Vec<String> {
        let Self { window, ctx, target, gpu, .. } = self;
        let _ = ctx.wait_idle();
        // SAFETY: the device is idle; everything is destroyed once, children before their parents, the surface
        // (in the target) before the window.
        unsafe {
            gpu.destroy(&ctx);
            target.destroy(&ctx);
        }
        let live = ctx.live_allocations();
        drop(ctx);
        drop(window);
        live
    }
}
