//! Window surfaces, swapchains and the per-frame synchronisation of a window's render loop.
//!
//! Out-of-date and suboptimal swapchains are control flow (the caller recreates), not errors. One frame is in
//! flight: the next frame waits for the previous one's fence before its uniforms are rewritten, which keeps the
//! per-object uniform buffers single (the viewer is GPU-bound on lavapipe, so a second frame would gain nothing
//! there).

use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::vk::{Buffer, Context, Guard, Image, ImageDesc, ImageState, MemoryState};

/// Instance extensions a window on this display needs.
pub fn required_instance_extensions(display: RawDisplayHandle) -> Result<Vec<*const std::ffi::c_char>> {
    Ok(ash_window::enumerate_required_extensions(display).vk("vkEnumerateInstanceExtensionProperties")?.to_vec())
}

/// A window's Vulkan surface.
pub struct Surface {
    pub raw: vk::SurfaceKHR,
    loader: ash::khr::surface::Instance,
}

impl Surface {
    /// # Safety
    /// Every swapchain of the surface must be destroyed.
    pub unsafe fn destroy(self, _ctx: &Context) {
        self.loader.destroy_surface(self.raw, None);
    }
}

crate::impl_destroy!(Surface, Swapchain, FrameSync);

/// The images a window presents, with a depth buffer of the same extent and, when multisampled, the image drawn
/// into and resolved into the presented one.
pub struct Swapchain {
    pub raw: vk::SwapchainKHR,
    loader: ash::khr::swapchain::Device,
    pub images: Vec<vk::Image>,
    pub views: Vec<vk::ImageView>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub depth: Image,
    /// The multisampled colour image (None with one sample per pixel).
    pub msaa: Option<Image>,
    /// Samples per pixel of `depth` and `msaa`.
    pub samples: vk::SampleCountFlags,
    /// Whether images can be copied out (screenshots).
    pub readable: bool,
    /// One "rendering finished" semaphore per image, signalled by the frame that draws into it.
    pub render_finished: Vec<vk::Semaphore>,
}

/// The properties a new swapchain is created with.
struct SwapchainChoice {
    format: vk::SurfaceFormatKHR,
    extent: vk::Extent2D,
    mode: vk::PresentModeKHR,
    /// Whether images can be copied out (screenshots).
    readable: bool,
    usage: vk::ImageUsageFlags,
    count: u32,
    transform: vk::SurfaceTransformFlagsKHR,
}

/// What acquiring an image gave.
pub enum Acquired {
    Image { index: u32, suboptimal: bool },
    OutOfDate,
}

impl Context {
    /// Creates a surface for a window and checks the queue can present to it.
    pub fn create_surface(&self, display: RawDisplayHandle, window: RawWindowHandle) -> Result<Surface> {
        // SAFETY: the handles come from a live window that outlives the surface (the viewer drops the surface
        // before the window).
        let raw = unsafe { ash_window::create_surface(self.entry(), self.instance(), display, window, None) }
            .vk("vkCreate*SurfaceKHR")?;
        let loader = ash::khr::surface::Instance::new(self.entry(), self.instance());
        // SAFETY: plain query on live objects.
        let supported = unsafe { loader.get_physical_device_surface_support(self.info.raw, self.queue_family(), raw) }
            .unwrap_or(false);
        let surface = Guard::new(self, Surface { raw, loader });
        if !supported {
            return Err(Error::UnsuitableDevice {
                name: self.info.name.clone(),
                reason: "it cannot present to this window".into(),
            });
        }
        Ok(surface.keep())
    }

    /// Creates (or re-creates, retiring `old`, which the caller still destroys) a swapchain of about
    /// `width`×`height` with 8-bit UNORM images (the shaders encode sRGB themselves). `vsync`: FIFO; otherwise
    /// MAILBOX or IMMEDIATE where offered. `samples` per pixel (refused, before `old` is retired, if the device
    /// cannot) are drawn into a multisampled image and depth buffer.
    pub fn create_swapchain(
        &self,
        surface: &Surface,
        (width, height): (u32, u32),
        vsync: bool,
        samples: u32,
        old: Option<&Swapchain>,
    ) -> Result<Swapchain> {
        let choice = self.swapchain_choice(surface, (width, height), vsync)?;
        let (format, extent, readable) = (choice.format, choice.extent, choice.readable);
        let samples = self.sample_count(samples, format.format)?;
        let (w, h) = (extent.width.max(1), extent.height.max(1));
        let depth = Guard::new(self, self.create_image(ImageDesc::depth(w, h).multisampled(samples), "window depth")?);
        let loader = ash::khr::swapchain::Device::new(self.instance(), self.device());
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(choice.count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(choice.usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(choice.transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(choice.mode)
            .clipped(true)
            .old_swapchain(old.as_ref().map_or(vk::SwapchainKHR::null(), |o| o.raw));
        // SAFETY: every pointer in `info` outlives the call; `old` is retired by it (even if it fails).
        let raw = unsafe { loader.create_swapchain(&info, None) }.vk("vkCreateSwapchainKHR")?;
        let mut made = Guard::new(
            self,
            Swapchain {
                raw,
                loader,
                images: Vec::new(),
                views: Vec::new(),
                format: format.format,
                extent,
                depth: depth.keep(),
                msaa: None,
                samples,
                readable,
                render_finished: Vec::new(),
            },
        );
        // A swapchain that fails to fill was never presented from: the guard may destroy it.
        self.fill_swapchain(&mut made)?;
        Ok(made.keep())
    }

    /// What a swapchain on `surface` will be: its format, extent, present mode, usage and image count.
    fn swapchain_choice(&self, surface: &Surface, (width, height): (u32, u32), vsync: bool) -> Result<SwapchainChoice> {
        let sl = &surface.loader;
        // SAFETY: plain queries on live objects.
        let (caps, formats, modes) = unsafe {
            (
                sl.get_physical_device_surface_capabilities(self.info.raw, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?,
                sl.get_physical_device_surface_formats(self.info.raw, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?,
                sl.get_physical_device_surface_present_modes(self.info.raw, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfacePresentModesKHR")?,
            )
        };
        let format = formats
            .iter()
            .find(|f| matches!(f.format, vk::Format::B8G8R8A8_UNORM | vk::Format::R8G8B8A8_UNORM))
            .copied()
            .ok_or_else(|| Error::Window("the window offers no 8-bit UNORM format".into()))?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: width.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: height.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mode = if vsync {
            vk::PresentModeKHR::FIFO
        } else {
            [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE]
                .into_iter()
                .find(|m| modes.contains(m))
                .unwrap_or(vk::PresentModeKHR::FIFO)
        };
        let readable = caps.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let mut usage = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        if readable {
            usage |= vk::ImageUsageFlags::TRANSFER_SRC;
        }
        let count =
            (caps.min_image_count + 1).min(if caps.max_image_count == 0 { u32::MAX } else { caps.max_image_count });
        Ok(SwapchainChoice { format, extent, mode, readable, usage, count, transform: caps.current_transform })
    }

    fn fill_swapchain(&self, s: &mut Swapchain) -> Result<()> {
        if s.samples != vk::SampleCountFlags::TYPE_1 {
            let (w, h) = (s.extent.width.max(1), s.extent.height.max(1));
            let desc = ImageDesc::render_target(w, h, s.format).multisampled(s.samples);
            s.msaa = Some(self.create_image(desc, "window colour (multisampled)")?);
        }
        // SAFETY: plain query on the swapchain just made.
        s.images = unsafe { s.loader.get_swapchain_images(s.raw) }.vk("vkGetSwapchainImagesKHR")?;
        for (i, &image) in s.images.iter().enumerate() {
            self.set_name(image, &format!("swapchain image {i}"));
            let info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(s.format)
                .subresource_range(Swapchain::color_range());
            // SAFETY: a plain create on a live image.
            s.views.push(unsafe { self.device().create_image_view(&info, None) }.vk("vkCreateImageView")?);
            // SAFETY: a plain create.
            s.render_finished.push(
                unsafe { self.device().create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                    .vk("vkCreateSemaphore")?,
            );
        }
        Ok(())
    }
}

impl Swapchain {
    pub fn color_range() -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange::default().aspect_mask(vk::ImageAspectFlags::COLOR).level_count(1).layer_count(1)
    }

    /// Puts the depth buffer and the multisampled image (if any) into attachment layouts for a new frame (their
    /// contents are discarded).
    pub fn begin_attachments(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        ctx.barrier_image(cmd, &self.depth, ImageState::UNDEFINED, ImageState::DEPTH_ATTACHMENT);
        if let Some(msaa) = &self.msaa {
            ctx.barrier_image(cmd, msaa, ImageState::UNDEFINED, ImageState::COLOR_ATTACHMENT);
        }
    }

    /// Records a copy of image `index` (drawn, in the colour-attachment state) into `buffer` (w·h·4 bytes) and
    /// leaves the image ready to present.
    pub fn record_copy(&self, ctx: &Context, cmd: vk::CommandBuffer, index: u32, buffer: &Buffer) {
        let image = self.images[index as usize];
        ctx.barrier_raw_image(cmd, image, Self::color_range(), ImageState::COLOR_ATTACHMENT, ImageState::TRANSFER_SRC);
        let region = vk::BufferImageCopy::default()
            .image_subresource(
                vk::ImageSubresourceLayers::default().aspect_mask(vk::ImageAspectFlags::COLOR).layer_count(1),
            )
            .image_extent(vk::Extent3D { width: self.extent.width, height: self.extent.height, depth: 1 });
        // SAFETY: the buffer holds the image's texels; the image is in TRANSFER_SRC_OPTIMAL.
        unsafe {
            ctx.device().cmd_copy_image_to_buffer(
                cmd,
                image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer.raw,
                &[region],
            )
        };
        ctx.barrier_raw_image(cmd, image, Self::color_range(), ImageState::TRANSFER_SRC, ImageState::PRESENT);
        ctx.barrier_memory(cmd, MemoryState::TRANSFER_WRITE, MemoryState::HOST_READ);
    }

    /// Acquires the next image, signalling `available` when it can be drawn into.
    pub fn acquire(&self, available: vk::Semaphore) -> Result<Acquired> {
        // SAFETY: the semaphore is unsignalled (the previous frame waited on it).
        match unsafe { self.loader.acquire_next_image(self.raw, u64::MAX, available, vk::Fence::null()) } {
            Ok((index, suboptimal)) => Ok(Acquired::Image { index, suboptimal }),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(result) => Err(Error::Vulkan { call: "vkAcquireNextImageKHR", result }),
        }
    }

    /// Presents image `index` once `render_finished[index]` is signalled; `false` means: recreate.
    pub fn present(&self, queue: vk::Queue, index: u32) -> Result<bool> {
        let waits = [self.render_finished[index as usize]];
        let swapchains = [self.raw];
        let indices = [index];
        let info =
            vk::PresentInfoKHR::default().wait_semaphores(&waits).swapchains(&swapchains).image_indices(&indices);
        // SAFETY: the image was acquired and rendered by this frame.
        match unsafe { self.loader.queue_present(queue, &info) } {
            Ok(false) => Ok(true),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(result) => Err(Error::Vulkan { call: "vkQueuePresentKHR", result }),
        }
    }

    /// # Safety
    /// The device must be idle with respect to the swapchain's images.
    pub unsafe fn destroy(self, ctx: &Context) {
        for v in self.views {
            ctx.device().destroy_image_view(v, None);
        }
        for s in self.render_finished {
            ctx.device().destroy_semaphore(s, None);
        }
        self.depth.destroy(ctx);
        if let Some(msaa) = self.msaa {
            msaa.destroy(ctx);
        }
        self.loader.destroy_swapchain(self.raw, None);
    }
}

/// A command buffer, its fence and the "image available" semaphore of the one frame in flight.
pub struct FrameSync {
    pool: vk::CommandPool,
    pub cmd: vk::CommandBuffer,
    pub fence: vk::Fence,
    pub image_available: vk::Semaphore,
}

impl Context {
    pub fn create_frame_sync(&self) -> Result<FrameSync> {
        let device = self.device();
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(self.queue_family())
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: plain creates on a live device (each destroyed by its guard if a later one fails).
        unsafe {
            let pool = Guard::new(self, device.create_command_pool(&pool_info, None).vk("vkCreateCommandPool")?);
            let alloc = vk::CommandBufferAllocateInfo::default().command_pool(*pool).command_buffer_count(1);
            // Freed with the pool.
            let cmd = device.allocate_command_buffers(&alloc).vk("vkAllocateCommandBuffers")?[0];
            let signalled = vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED);
            let fence = Guard::new(self, device.create_fence(&signalled, None).vk("vkCreateFence")?);
            let image_available = device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None);
            let image_available = image_available.vk("vkCreateSemaphore")?;
            self.set_name(cmd, "window frame");
            Ok(FrameSync { pool: pool.keep(), cmd, fence: fence.keep(), image_available })
        }
    }

    /// Submits `sync.cmd`, waiting for `sync.image_available` before drawing and signalling `signal` and the
    /// fence when done.
    pub fn submit_frame(&self, sync: &FrameSync, signal: vk::Semaphore) -> Result<()> {
        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(sync.image_available)
            .stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)];
        let signals =
            [vk::SemaphoreSubmitInfo::default().semaphore(signal).stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(sync.cmd)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&waits)
            .signal_semaphore_infos(&signals)
            .command_buffer_infos(&cmds);
        // SAFETY: the command buffer is recorded; the fence was reset by the caller.
        unsafe { self.device().queue_submit2(self.queue(), &[submit], sync.fence) }.vk("vkQueueSubmit2")
    }
}

impl FrameSync {
    /// Resets the fence and opens the command buffer; call after [`FrameSync::wait`] and a successful acquire
    /// (so that a frame given up on leaves the fence signalled).
    pub fn begin(&self, ctx: &Context) -> Result<()> {
        let device = ctx.device();
        // SAFETY: the caller waited for the fence, so the command buffer is free to reuse.
        unsafe {
            device.reset_fences(&[self.fence]).vk("vkResetFences")?;
            device.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty()).vk("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(self.cmd, &begin).vk("vkBeginCommandBuffer")
        }
    }

    /// Ends the command buffer's recording (before [`Context::submit_frame`]).
    pub fn end(&self, ctx: &Context) -> Result<()> {
        // SAFETY: the command buffer was begun by `begin`.
        unsafe { ctx.device().end_command_buffer(self.cmd) }.vk("vkEndCommandBuffer")
    }

    /// Waits for the frame in flight (before rewriting its uniforms or reading back what it drew).
    pub fn wait(&self, ctx: &Context) -> Result<()> {
        // SAFETY: a plain wait.
        unsafe { ctx.device().wait_for_fences(&[self.fence], true, u64::MAX) }.vk("vkWaitForFences")
    }

    /// # Safety
    /// The device must be idle.
    pub unsafe fn destroy(self, ctx: &Context) {
        ctx.device().destroy_semaphore(self.image_available, None);
        ctx.device().destroy_fence(self.fence, None);
        ctx.device().destroy_command_pool(self.pool, None);
    }
}
