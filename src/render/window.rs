//! [`WindowTarget`]: the window's counterpart of [`OffscreenTarget`](crate::render::OffscreenTarget). It owns what
//! presenting needs — the surface, the swapchain (with its depth and multisampled images), the one frame in
//! flight's command buffer and fences, the GPU timestamps and the screenshot buffer — and gives a frame as a
//! command buffer and a [`TargetView`] between [`WindowTarget::begin_frame`] and [`WindowTarget::end_frame`].
//! The passes record into that view exactly as they do into an offscreen one.

use std::path::Path;

use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::error::{Error, Result};
use crate::gpu::vk::swapchain::{Acquired, FrameSync, Surface, Swapchain};
use crate::gpu::vk::{Buffer, BufferDesc, Context, Destroy, FrameTimes, Guard, ImageState, Laps, TimestampRing};
use crate::render::TargetView;

/// A window's swapchain and everything one frame in flight needs.
pub struct WindowTarget {
    surface: Surface,
    swapchain: Swapchain,
    sync: FrameSync,
    /// The passes of the frame in flight, timed (None where the queue has no timestamps).
    ring: Option<TimestampRing>,
    /// The last frame copied for a screenshot (None where the window's images cannot be copied).
    screenshot: Option<Buffer>,
    vsync: bool,
    samples: u32,
    /// The swapchain no longer matches the window (resized, suboptimal or out of date): remade before the next
    /// frame.
    stale: bool,
    /// A submitted frame's timestamps have not been read yet.
    timing_pending: bool,
}

/// What a frame is drawn into, between [`WindowTarget::begin_frame`] and [`WindowTarget::end_frame`].
#[derive(Clone, Debug)]
pub struct WindowFrame {
    /// The frame's command buffer, recording.
    pub cmd: vk::CommandBuffer,
    /// The GPU times of the previous frame's passes (None for the first frame, or with no timestamps).
    pub previous: Option<FrameTimes>,
    index: u32,
    extent: vk::Extent2D,
    scene: TargetView,
    flat: TargetView,
}

impl WindowFrame {
    /// The target of the scene's passes: multisampled (resolved into the presented image) with depth.
    pub fn scene(&self) -> TargetView {
        self.scene
    }

    /// The target of a full-screen pass with no depth test (the BRDF map): the presented image itself, single
    /// sampled. (It carries the depth buffer only where that is single-sampled too, as the map pass needs none.)
    pub fn flat(&self) -> TargetView {
        self.flat
    }

    /// The frame's size in pixels.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }
}

impl WindowTarget {
    /// A surface on the window and a swapchain of about `size` pixels with `samples` per pixel; `vsync`: FIFO,
    /// otherwise MAILBOX or IMMEDIATE where offered. The window must outlive the target.
    pub fn new(
        ctx: &Context,
        (display, window): (RawDisplayHandle, RawWindowHandle),
        size: (u32, u32),
        vsync: bool,
        samples: u32,
    ) -> Result<Self> {
        let surface = Guard::new(ctx, ctx.create_surface(display, window)?);
        let sync = Guard::new(ctx, ctx.create_frame_sync()?);
        let ring = Guard::new(ctx, ctx.create_timestamp_ring(1, crate::gpu::vk::query::MAX_LAPS, "window timestamps")?);
        let swapchain = Guard::new(ctx, ctx.create_swapchain(&surface, size, vsync, samples, None)?);
        let screenshot = screenshot_buffer(ctx, &swapchain)?;
        Ok(Self {
            swapchain: swapchain.keep(),
            ring: ring.keep(),
            sync: sync.keep(),
            surface: surface.keep(),
            screenshot,
            vsync,
            samples,
            stale: false,
            timing_pending: false,
        })
    }

    /// The format of the presented images (the passes' pipelines are built for it).
    pub fn format(&self) -> vk::Format {
        self.swapchain.format
    }

    /// Samples per pixel of [`WindowFrame::scene`] (the scene's pipelines are built for it).
    pub fn samples(&self) -> vk::SampleCountFlags {
        self.swapchain.samples
    }

    /// The presented images' size in pixels.
    pub fn extent(&self) -> vk::Extent2D {
        self.swapchain.extent
    }

    /// The swapchain is remade before the next frame (the window was resized).
    pub fn mark_stale(&mut self) {
        self.stale = true;
    }

    /// Remakes the swapchain for a window of `size` pixels if it is stale. A window with no area (minimised)
    /// keeps the old one until it has an area again.
    fn refresh(&mut self, ctx: &Context, size: (u32, u32)) -> Result<()> {
        if !self.stale || size.0 == 0 || size.1 == 0 {
            return Ok(());
        }
        ctx.wait_idle()?;
        // The old swapchain is retired by the new one's creation (even by a failed one, which leaves this
        // target unable to present, and the viewer stops); it is destroyed here or at teardown.
        let made = ctx.create_swapchain(&self.surface, size, self.vsync, self.samples, Some(&self.swapchain))?;
        let old = std::mem::replace(&mut self.swapchain, made);
        // SAFETY: the device is idle.
        unsafe {
            old.destroy(ctx);
            self.screenshot.take().destroy(ctx);
        }
        self.screenshot = screenshot_buffer(ctx, &self.swapchain)?;
        self.stale = false;
        Ok(())
    }

    /// Waits for the frame in flight, acquires an image for a window of `size` pixels and begins recording (its
    /// passes timed: see [`Self::laps`]). None: no frame now (the window has no area, or the swapchain was out of
    /// date and is remade before the next one).
    pub fn begin_frame(&mut self, ctx: &Context, size: (u32, u32)) -> Result<Option<WindowFrame>> {
        self.refresh(ctx, size)?;
        if size.0 == 0 || size.1 == 0 {
            return Ok(None);
        }
        self.sync.wait(ctx)?;
        let mut previous = None;
        if std::mem::take(&mut self.timing_pending) {
            if let Some(ring) = &self.ring {
                previous = Some(ring.read(ctx, 0)?);
            }
        }
        let index = match self.swapchain.acquire(self.sync.image_available)? {
            Acquired::Image { index, suboptimal } => {
                self.stale |= suboptimal;
                index
            }
            Acquired::OutOfDate => {
                self.stale = true;
                return Ok(None);
            }
        };
        self.sync.begin(ctx)?;
        let (cmd, s) = (self.sync.cmd, &self.swapchain);
        let presented = s.views[index as usize];
        let one = vk::SampleCountFlags::TYPE_1;
        let (scene, flat) = match &s.msaa {
            Some(msaa) => (
                TargetView {
                    color: msaa.view,
                    resolve: Some(presented),
                    depth: Some(s.depth.view),
                    extent: s.extent,
                    samples: s.samples,
                    storage: None,
                },
                // A multisampled depth buffer would not match the single-sampled presented image.
                TargetView {
                    color: presented,
                    resolve: None,
                    depth: None,
                    extent: s.extent,
                    samples: one,
                    storage: None,
                },
            ),
            None => {
                let view = TargetView {
                    color: presented,
                    resolve: None,
                    depth: Some(s.depth.view),
                    extent: s.extent,
                    samples: one,
                    storage: None,
                };
                (view, view)
            }
        };
        ctx.barrier_raw_image(
            cmd,
            s.images[index as usize],
            Swapchain::color_range(),
            ImageState::UNDEFINED,
            ImageState::COLOR_ATTACHMENT,
        );
        s.begin_attachments(ctx, cmd);
        if let Some(ring) = &self.ring {
            ring.begin_frame(ctx, cmd, 0);
        }
        Ok(Some(WindowFrame { cmd, previous, index, extent: s.extent, scene, flat }))
    }

    /// Where the passes of the frame being recorded mark their ends ([`crate::render::pass`]); this target adds the copy
    /// of a screenshot and the hand-over to the window in [`Self::end_frame`].
    pub fn laps<'a>(&'a self, ctx: &'a Context) -> Laps<'a> {
        self.ring.as_ref().map_or(Laps::NONE, |ring| ring.laps(ctx))
    }

    /// Ends the frame's recording, submits it and presents it; with `copy`, the presented image is also copied
    /// into the screenshot buffer (see [`Self::save_screenshot`]).
    pub fn end_frame(&mut self, ctx: &Context, frame: WindowFrame, copy: bool) -> Result<()> {
        let (cmd, index) = (frame.cmd, frame.index);
        let laps = self.laps(ctx);
        let image = self.swapchain.images[index as usize];
        match (copy, &self.screenshot) {
            (true, Some(buffer)) => {
                self.swapchain.record_copy(ctx, cmd, index, buffer);
                laps.lap(cmd, crate::render::pass::COPY);
            }
            (true, None) => return Err(Error::Window("this window's images cannot be copied for a screenshot".into())),
            (false, _) => ctx.barrier_raw_image(
                cmd,
                image,
                Swapchain::color_range(),
                ImageState::COLOR_ATTACHMENT,
                ImageState::PRESENT,
            ),
        }
        laps.lap(cmd, crate::render::pass::PRESENT);
        self.sync.end(ctx)?;
        ctx.submit_frame(&self.sync, self.swapchain.render_finished[index as usize])?;
        self.timing_pending = self.ring.is_some();
        if !self.swapchain.present(ctx.queue(), index)? {
            self.stale = true;
        }
        Ok(())
    }

    /// Writes the last frame copied by [`Self::end_frame`] to a PNG file.
    pub fn save_screenshot(&self, ctx: &Context, path: &Path) -> Result<()> {
        let buffer = self.screenshot.as_ref().ok_or_else(|| Error::Window("no frame to save".into()))?;
        self.sync.wait(ctx)?;
        let bytes = ctx.read_buffer(buffer)?;
        let bgra = self.swapchain.format == vk::Format::B8G8R8A8_UNORM;
        let rgba: Vec<u8> = bytes
            .chunks(4)
            .flat_map(|p| if bgra { [p[2], p[1], p[0], 255] } else { [p[0], p[1], p[2], 255] })
            .collect();
        let extent = self.swapchain.extent;
        crate::io::output::write_png_rgba8(path, extent.width, extent.height, &rgba)
    }

    /// # Safety
    /// The device must be idle; the window must still exist.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.screenshot.destroy(ctx);
        self.ring.destroy(ctx);
        self.sync.destroy(ctx);
        self.swapchain.destroy(ctx);
        self.surface.destroy(ctx);
    }
}

crate::impl_destroy!(WindowTarget);

/// A buffer for one frame's pixels, where the swapchain's images can be copied out.
fn screenshot_buffer(ctx: &Context, swapchain: &Swapchain) -> Result<Option<Buffer>> {
    if !swapchain.readable {
        return Ok(None);
    }
    let bytes = u64::from(swapchain.extent.width) * u64::from(swapchain.extent.height) * 4;
    Ok(Some(ctx.create_buffer(BufferDesc::readback(bytes), "screenshot")?))
}
