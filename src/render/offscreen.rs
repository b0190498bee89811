//! Offscreen frames of a scene: the colour target a [`SceneRenderer`] draws into (linear floats, or the window's
//! display-encoded bytes, [`FrameTarget`]), read back in the frame's own submission.

use ash::vk;

use crate::error::Result;
use crate::gpu::vk::{Buffer, Context, Guard, ImageState};
use crate::material::Material;
use crate::render::surface::{orientation, MaterialInput, RendererSetup, SceneRenderer, SurfaceMaterial};
use crate::render::{pass, Frame, Instruments, OffscreenTarget, Pixels, SceneView, LINEAR_FORMAT};
use crate::scene::mesh::Mesh;

/// What a scene's frames are drawn into: what `render` reads back, or what `view` presents. The profiler times
/// either (`--sweep target=linear,display`), so that a machine without a display measures the window's frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FrameTarget {
    #[default]
    /// Linear RGB in 32-bit floats, exposure and display encoding left to the CPU (`render`, the profiler's
    /// default): 16 bytes per sample.
    Linear,
    /// Exposure-scaled sRGB in 8 bits per channel, encoded by the shaders (the viewer's window): 4 bytes per
    /// sample. On an NVIDIA H100 the default scene's frame at 1920×1080 with 4 samples took 2.26 ms so, against
    /// 4.76 linear (docs/performance.md, "The window's frames on the H100").
    Display,
}

impl FrameTarget {
    pub const NAMES: [&'static str; 2] = ["linear", "display"];

    pub fn name(self) -> &'static str {
        match self {
            Self::Linear => "linear",
            Self::Display => "display",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "linear" => Some(Self::Linear),
            "display" => Some(Self::Display),
            _ => None,
        }
    }

    /// Whether the shaders apply the exposure and the sRGB encoding.
    pub fn display_output(self) -> bool {
        self == Self::Display
    }

    /// The colour format of the target (and of the [`SceneRenderer`] drawing into it).
    pub fn format(self) -> vk::Format {
        OffscreenFrames::format(self.display_output())
    }
}

/// An offscreen target for a [`SceneRenderer`]: renders frames and reads them back.
pub struct OffscreenFrames {
    target: OffscreenTarget,
    /// Where each frame's pixels are copied, in the frame's own submission.
    readback: Buffer,
    display_output: bool,
}

impl OffscreenFrames {
    /// Frames of `samples` per pixel, averaged into each pixel (multisample anti-aliasing).
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        display_output: bool,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        let format = Self::format(display_output);
        let target = Guard::new(ctx, OffscreenTarget::multisampled(ctx, width, height, format, true, samples)?);
        let readback = ctx.create_readback(&target.color)?;
        Ok(Self { target: target.keep(), readback, display_output })
    }

    /// Readies the target for a renderer drawing through a visibility buffer
    /// ([`OffscreenTarget::for_visibility_buffer`]); no submitted work may
    /// still use it.
    pub fn for_visibility_buffer(&mut self, ctx: &Context) -> Result<()> {
        // SAFETY: the caller promises the GPU is done with the target.
        unsafe { self.target.for_visibility_buffer(ctx) }
    }

    /// The colour format a [`SceneRenderer`] drawing into these frames must use.
    pub fn format(display_output: bool) -> vk::Format {
        if display_output {
            vk::Format::R8G8B8A8_UNORM
        } else {
            LINEAR_FORMAT
        }
    }

    /// Draws one frame (uniforms already updated) and copies it back in the same submission; its passes are
    /// timed (the renderer's, then [`pass::COPY`]).
    pub fn render(&self, ctx: &Context, renderer: &SceneRenderer, background: [f32; 4]) -> Result<Frame> {
        let times = ctx.one_shot_laps(SceneRenderer::NAME, |cmd, laps| {
            self.target.begin(ctx, cmd);
            let instruments = Instruments { laps, ..Instruments::default() };
            renderer.record_with(ctx, cmd, &self.target.view(), background, instruments);
            ctx.record_readback(cmd, &self.target.color, ImageState::COLOR_ATTACHMENT, &self.readback);
            laps.lap(cmd, pass::COPY);
        })?;
        let bytes = self.readback.mapped().map(<[u8]>::to_vec).unwrap_or_default();
        let extent = self.target.color.extent();
        let pixels = if self.display_output {
            Pixels::Rgba8(bytes)
        } else {
            Pixels::Linear(bytemuck::pod_collect_to_vec(&bytes))
        };
        Ok(Frame { width: extent.width, height: extent.height, pixels, times })
    }

    /// # Safety
    /// The GPU must be done with the target.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.target.destroy(ctx);
        self.readback.destroy(ctx);
    }
}

/// Renders `mesh` with `material` under `view` (its first model) headless, one sample per pixel: linear float
/// RGB, or (with `display_output`) 8-bit sRGB from the shader's own exposure and transfer function.
pub fn render_surface(
    ctx: &Context,
    material: &Material,
    mesh: &Mesh,
    view: &SceneView,
    width: u32,
    height: u32,
    display_output: bool,
) -> Result<Frame> {
    let format = OffscreenFrames::format(display_output);
    let surface = SurfaceMaterial { orientation: orientation(0.0), pigment: [0.0; 3], matte: false };
    let inputs = [MaterialInput { material, surface }];
    let one = vk::SampleCountFlags::TYPE_1;
    let setup = RendererSetup::forward(format, display_output, one);
    let first = (view, vk::Extent2D { width, height });
    let renderer = Guard::new(ctx, SceneRenderer::new(ctx, (&inputs, &[(mesh, 0)]), setup, first)?);
    let frames = Guard::new(ctx, OffscreenFrames::new(ctx, width, height, display_output, one)?);
    frames.render(ctx, &renderer, view.background)
}

crate::impl_destroy!(OffscreenFrames);
