//! Command recording and submission, and synchronization2 barriers.
//!
//! Barriers are written as a transition between two named states (layout + stage + access), after niagara's
//! helpers: `ctx.barrier_image(cmd, &img, ImageState::UNDEFINED, ImageState::TRANSFER_DST)`.

use std::ffi::CString;

use ash::vk;

use crate::error::{Result, VkResultExt};
use crate::gpu::vk::{Context, Image};

/// A layout together with the stages and accesses that use an image in it.
#[derive(Clone, Copy, Debug)]
pub struct ImageState {
    pub layout: vk::ImageLayout,
    pub stage: vk::PipelineStageFlags2,
    pub access: vk::AccessFlags2,
}

impl ImageState {
    pub const UNDEFINED: Self =
        Self::new(vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
    pub const TRANSFER_DST: Self = Self::new(
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_WRITE,
    );
    pub const TRANSFER_SRC: Self = Self::new(
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
    );
    /// Sampled by fragment or compute shaders.
    pub const SHADER_READ: Self = Self::new(
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw() | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw(),
        ),
        vk::AccessFlags2::SHADER_SAMPLED_READ,
    );
    pub const COLOR_ATTACHMENT: Self = Self::new(
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE.as_raw() | vk::AccessFlags2::COLOR_ATTACHMENT_READ.as_raw(),
        ),
    );
    pub const DEPTH_ATTACHMENT: Self = Self::new(
        vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
        vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
        ),
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw()
                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw(),
        ),
    );
    /// Written (and read) by compute shaders as a storage image.
    pub const STORAGE: Self = Self::new(
        vk::ImageLayout::GENERAL,
        vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw() | vk::AccessFlags2::SHADER_STORAGE_READ.as_raw(),
        ),
    );
    pub const PRESENT: Self =
        Self::new(vk::ImageLayout::PRESENT_SRC_KHR, vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);

    pub const fn new(layout: vk::ImageLayout, stage: vk::PipelineStageFlags2, access: vk::AccessFlags2) -> Self {
        Self { layout, stage, access }
    }
}

/// Stages and accesses on one side of a global memory barrier (buffers).
#[derive(Clone, Copy, Debug)]
pub struct MemoryState {
    pub stage: vk::PipelineStageFlags2,
    pub access: vk::AccessFlags2,
}

impl MemoryState {
    pub const TRANSFER_WRITE: Self =
        Self { stage: vk::PipelineStageFlags2::COPY, access: vk::AccessFlags2::TRANSFER_WRITE };
    pub const TRANSFER_READ: Self =
        Self { stage: vk::PipelineStageFlags2::COPY, access: vk::AccessFlags2::TRANSFER_READ };
    pub const HOST_READ: Self = Self { stage: vk::PipelineStageFlags2::HOST, access: vk::AccessFlags2::HOST_READ };
    pub const COMPUTE_WRITE: Self =
        Self { stage: vk::PipelineStageFlags2::COMPUTE_SHADER, access: vk::AccessFlags2::SHADER_STORAGE_WRITE };
    /// Fragment shaders' storage-buffer reads and writes (atomic counters).
    pub const FRAGMENT_STORAGE: Self = Self {
        stage: vk::PipelineStageFlags2::FRAGMENT_SHADER,
        access: vk::AccessFlags2::from_raw(
            vk::AccessFlags2::SHADER_STORAGE_READ.as_raw() | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
        ),
    };
    pub const ALL_WRITES: Self =
        Self { stage: vk::PipelineStageFlags2::ALL_COMMANDS, access: vk::AccessFlags2::MEMORY_WRITE };
    pub const ALL_READS: Self =
        Self { stage: vk::PipelineStageFlags2::ALL_COMMANDS, access: vk::AccessFlags2::MEMORY_READ };
}

impl Context {
    /// Records `record` into a fresh command buffer, submits it and waits for it to finish.
    /// `name` labels the work for debuggers and validation messages.
    pub fn one_shot(&self, name: &str, record: impl FnOnce(vk::CommandBuffer)) -> Result<()> {
        let device = self.device();
        // The pool must be externally synchronised: hold its lock for the whole record-submit-wait.
        let pool_guard = self.command_pool.lock().unwrap_or_else(|e| e.into_inner());
        let pool = *pool_guard;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is owned by this context and locked above.
        let cmd = unsafe { device.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?[0];
        self.set_name(cmd, name);
        let fence_result = {
            // SAFETY: a plain create on a live device.
            unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence")
        };
        let fence = match fence_result {
            Ok(f) => f,
            Err(e) => {
                // SAFETY: never submitted.
                unsafe { device.free_command_buffers(pool, &[cmd]) };
                return Err(e);
            }
        };
        // SAFETY: cmd is a fresh primary command buffer; it is submitted once and waited for before it is freed.
        let result = unsafe {
            (|| {
                let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
                device.begin_command_buffer(cmd, &begin).vk("vkBeginCommandBuffer")?;
                self.begin_label(cmd, name);
                record(cmd);
                self.end_label(cmd);
                device.end_command_buffer(cmd).vk("vkEndCommandBuffer")?;
                let cmd_info = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
                let submit = vk::SubmitInfo2::default().command_buffer_infos(&cmd_info);
                device.queue_submit2(self.queue(), &[submit], fence).vk("vkQueueSubmit2")?;
                device.wait_for_fences(&[fence], true, u64::MAX).vk("vkWaitForFences")
            })()
        };
        // SAFETY: the fence was waited for (or the buffer never submitted).
        unsafe {
            if result.is_err() {
                let _ = device.queue_wait_idle(self.queue());
            }
            device.destroy_fence(fence, None);
            device.free_command_buffers(pool, &[cmd]);
        }
        result
    }

    /// Opens a debug label (a pass name) on `cmd` when validation/debug names are on.
    pub fn begin_label(&self, cmd: vk::CommandBuffer, name: &str) {
        let Some(du) = &self.device.debug_utils else {
            return;
        };
        let Ok(cname) = CString::new(name) else {
            return;
        };
        let label = vk::DebugUtilsLabelEXT::default().label_name(&cname);
        // SAFETY: cmd is recording.
        unsafe { du.cmd_begin_debug_utils_label(cmd, &label) };
    }

    pub fn end_label(&self, cmd: vk::CommandBuffer) {
        let Some(du) = &self.device.debug_utils else {
            return;
        };
        // SAFETY: paired with begin_label on the same recording command buffer.
        unsafe { du.cmd_end_debug_utils_label(cmd) };
    }

    /// Transitions all layers and mips of `image` from one state to another.
    pub fn barrier_image(&self, cmd: vk::CommandBuffer, image: &Image, from: ImageState, to: ImageState) {
        let range = vk::ImageSubresourceRange::default()
            .aspect_mask(image.aspect())
            .level_count(image.desc.mip_levels)
            .layer_count(image.desc.layers);
        self.barrier_raw_image(cmd, image.raw, range, from, to);
    }

    /// The same for an image this module does not own as an `Image` (a swapchain image).
    pub fn barrier_raw_image(
        &self,
        cmd: vk::CommandBuffer,
        image: vk::Image,
        range: vk::ImageSubresourceRange,
        from: ImageState,
        to: ImageState,
    ) {
        let barrier = [vk::ImageMemoryBarrier2::default()
            .image(image)
            .subresource_range(range)
            .old_layout(from.layout)
            .new_layout(to.layout)
            .src_stage_mask(from.stage)
            .src_access_mask(from.access)
            .dst_stage_mask(to.stage)
            .dst_access_mask(to.access)];
        let dep = vk::DependencyInfo::default().image_memory_barriers(&barrier);
        // SAFETY: cmd is recording; the barrier describes a live image.
        unsafe { self.device().cmd_pipeline_barrier2(cmd, &dep) };
    }

    /// A global memory barrier (for buffers).
    pub fn barrier_memory(&self, cmd: vk::CommandBuffer, from: MemoryState, to: MemoryState) {
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(from.stage)
            .src_access_mask(from.access)
            .dst_stage_mask(to.stage)
            .dst_access_mask(to.access)];
        let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
        // SAFETY: cmd is recording.
        unsafe { self.device().cmd_pipeline_barrier2(cmd, &dep) };
    }
}
