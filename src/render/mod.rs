//! Frames: offscreen targets, the passes that draw into them, and readback to CPU images.
//!
//! Offscreen capture and the window share everything but the final target: a pass records into a
//! [`TargetView`], which either an [`OffscreenTarget`] or a swapchain image provides.

pub mod preview;

use ash::vk;

use crate::error::Result;
use crate::vk::{Context, Image, ImageDesc, ImageState};

/// The format of offscreen colour targets: 8-bit sRGB, so the store applies the sRGB transfer function and the
/// bytes read back are what a PNG holds.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The largest edge a frame may have (a sanity bound for user input; far above any display).
pub const MAX_EDGE: u32 = 16384;

/// What a pass draws into.
#[derive(Clone, Copy, Debug)]
pub struct TargetView {
    pub color: vk::ImageView,
    pub depth: vk::ImageView,
    pub extent: vk::Extent2D,
}

/// A colour and a depth image for headless rendering.
pub struct OffscreenTarget {
    pub color: Image,
    pub depth: Image,
}

impl OffscreenTarget {
    pub fn new(ctx: &Context, width: u32, height: u32) -> Result<Self> {
        let color = ctx.create_image(ImageDesc::render_target(width, height, COLOR_FORMAT), "offscreen colour")?;
        match ctx.create_image(ImageDesc::depth(width, height), "offscreen depth") {
            Ok(depth) => Ok(Self { color, depth }),
            Err(e) => {
                // SAFETY: never used.
                unsafe { color.destroy(ctx) };
                Err(e)
            }
        }
    }

    pub fn view(&self) -> TargetView {
        TargetView { color: self.color.view, depth: self.depth.view, extent: self.color.extent() }
    }

    /// Puts both images into attachment layouts (their contents are discarded).
    pub fn begin(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        ctx.barrier_image(cmd, &self.color, ImageState::UNDEFINED, ImageState::COLOR_ATTACHMENT);
        ctx.barrier_image(cmd, &self.depth, ImageState::UNDEFINED, ImageState::DEPTH_ATTACHMENT);
    }

    /// Reads the colour image back as tightly packed RGBA8 (sRGB-encoded) rows, top row first.
    pub fn read_rgba8(&self, ctx: &Context) -> Result<Vec<u8>> {
        ctx.read_image(&self.color, ImageState::COLOR_ATTACHMENT)
    }

    /// # Safety
    /// The GPU must be done with both images.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.color.destroy(ctx);
        self.depth.destroy(ctx);
    }
}

/// Begins dynamic rendering into `target`, clearing colour to `clear` and depth to 1, and sets a full viewport.
pub fn begin_rendering(ctx: &Context, cmd: vk::CommandBuffer, target: &TargetView, clear: [f32; 4]) {
    let color = [vk::RenderingAttachmentInfo::default()
        .image_view(target.color)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: clear } })];
    let depth = vk::RenderingAttachmentInfo::default()
        .image_view(target.depth)
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } });
    let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: target.extent };
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&color)
        .depth_attachment(&depth);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: target.extent.width as f32,
        height: target.extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: cmd is recording and the target's images are in attachment layouts.
    unsafe {
        ctx.device().cmd_begin_rendering(cmd, &info);
        ctx.device().cmd_set_viewport(cmd, 0, &[viewport]);
        ctx.device().cmd_set_scissor(cmd, 0, &[area]);
    }
}

pub fn end_rendering(ctx: &Context, cmd: vk::CommandBuffer) {
    // SAFETY: paired with begin_rendering.
    unsafe { ctx.device().cmd_end_rendering(cmd) };
}
