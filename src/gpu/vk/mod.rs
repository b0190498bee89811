//! The Vulkan backend: the only module that creates or destroys Vulkan objects.
//! - One top-level [`Context`] owns the instance, the device, the allocator and a command pool; its `Drop` waits
//!   idle and destroys them in reverse order (allocator before device). The only other `Drop`s that free Vulkan
//!   state are `Guard`'s (an object under construction, on an early return) and `Owned`'s (a user's finished
//!   object: waits idle first).
//! - Leaves (`Buffer`, `Image`, `Pipeline`, `Sampler`, `TimestampRing`) are plain structs `{ raw, allocation, desc }`
//!   without `Drop`, consumed by `unsafe fn destroy(self, &Context)` (`Destroy`). Tests assert that no allocation
//!   is live when the context goes.
//! - Vulkan 1.3 only: synchronization2 barriers, dynamic rendering, push descriptors; one graphics+compute queue,
//!   work recorded and submitted with [`Context::one_shot`]. Every object is named at creation when validation is
//!   on (its allocation too), so validation messages say which object they mean.

mod buffer;
mod command;
mod debug;
mod device;
mod guard;
mod image;
mod instance;
mod pipeline;
pub(crate) mod query;
#[cfg(feature = "view")]
pub mod swapchain;
#[cfg(test)]
pub(crate) mod tests;

use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

pub(crate) use buffer::{Buffer, BufferDesc};
pub(crate) use command::{ImageState, MemoryState};
pub use device::{choose as choose_device, DeviceInfo, DeviceSelector};
pub use gpu_allocator::MemoryLocation;
pub(crate) use guard::Guard;
pub use guard::{Destroy, Owned};
pub(crate) use image::{Image, ImageDesc, Sampler};
pub use instance::ValidationLog;
pub(crate) use pipeline::{
    Blend, ComputePipelineDesc, DepthTest, DescriptorWrite, GraphicsPipelineDesc, Pipeline, SpecConstants,
    VertexAttribute,
};
pub use pipeline::{Shader, ShaderBinding};
pub use query::{FrameTimes, PassProfile, ScopeTiming};
pub(crate) use query::{Laps, Statistics, TimestampRing};

crate::impl_destroy!(Buffer, Image, Sampler, Pipeline, TimestampRing);

use crate::error::{Error, Result, VkResultExt};

/// How to open a [`Context`].
#[derive(Clone, Debug, Default)]
pub struct ContextDesc {
    pub device: DeviceSelector,
    /// Enable `VK_LAYER_KHRONOS_validation`, print and count its messages, and name every object.
    pub validation: bool,
    /// Enable presenting to windows (`VK_KHR_swapchain`).
    pub window: bool,
}

impl ContextDesc {
    /// Validation is on when asked for or when `DIFFRACT_VALIDATION=1` is set.
    pub fn new(device: DeviceSelector, validation: bool) -> Self {
        let env = std::env::var("DIFFRACT_VALIDATION").is_ok_and(|v| v == "1" || v.eq_ignore_ascii_case("true"));
        Self { device, validation: validation || env, window: false }
    }
}

/// Lists every Vulkan device without opening one (for `diffract devices`).
pub fn list_devices(validation: bool) -> Result<(Vec<DeviceInfo>, Arc<ValidationLog>)> {
    let instance = instance::Instance::new(validation, &[])?;
    let devices = device::list(&instance.raw);
    let log = instance.validation.clone();
    // SAFETY: nothing was created from this instance.
    unsafe { instance.destroy() };
    Ok((devices?, log))
}

/// The device and everything long-lived on it.
pub struct Context {
    instance: ManuallyDrop<instance::Instance>,
    pub info: DeviceInfo,
    device: ManuallyDrop<device::Device>,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    command_pool: Mutex<vk::CommandPool>,
}

impl Context {
    pub fn new(desc: &ContextDesc) -> Result<Self> {
        Self::with_instance_extensions(desc, &[])
    }

    /// Opens a context whose instance also enables `extensions` (the window's surface extensions).
    pub fn with_instance_extensions(desc: &ContextDesc, extensions: &[*const std::ffi::c_char]) -> Result<Self> {
        let instance = instance::Instance::new(desc.validation, extensions)?;
        let opened = Self::open_device(&instance, desc);
        match opened {
            Ok((info, device, allocator, command_pool)) => Ok(Self {
                instance: ManuallyDrop::new(instance),
                info,
                device: ManuallyDrop::new(device),
                allocator: ManuallyDrop::new(Mutex::new(allocator)),
                command_pool: Mutex::new(command_pool),
            }),
            Err(e) => {
                // SAFETY: open_device cleans up what it created before failing.
                unsafe { instance.destroy() };
                Err(e)
            }
        }
    }

    fn open_device(
        instance: &instance::Instance,
        desc: &ContextDesc,
    ) -> Result<(DeviceInfo, device::Device, Allocator, vk::CommandPool)> {
        let devices = device::list(&instance.raw)?;
        let info = device::choose(&devices, &desc.device)?;
        let device = device::Device::new(&instance.raw, &info, desc.validation, desc.window)?;
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.raw.clone(),
            device: device.raw.clone(),
            physical_device: info.raw,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(cause) => {
                // SAFETY: the device has no children yet.
                unsafe { device.raw.destroy_device(None) };
                return Err(Error::Allocation { name: "allocator".into(), cause });
            }
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: a plain create on a live device.
        let pool = unsafe { device.raw.create_command_pool(&pool_info, None) };
        match pool {
            Ok(pool) => {
                device.set_name(pool, "command pool");
                Ok((info, device, allocator, pool))
            }
            Err(result) => {
                drop(allocator);
                // SAFETY: the allocator (its only child) is gone.
                unsafe { device.raw.destroy_device(None) };
                Err(Error::Vulkan { call: "vkCreateCommandPool", result })
            }
        }
    }

    /// The raw `ash` device, for recording commands.
    pub fn device(&self) -> &ash::Device {
        &self.device.raw
    }

    pub fn instance(&self) -> &ash::Instance {
        &self.instance.raw
    }

    pub fn entry(&self) -> &ash::Entry {
        &self.instance.entry
    }

    pub fn queue(&self) -> vk::Queue {
        self.device.queue
    }

    pub fn queue_family(&self) -> u32 {
        self.device.queue_family
    }

    /// The validation log (empty and never written when validation is off).
    pub fn validation(&self) -> Arc<ValidationLog> {
        self.instance.validation.clone()
    }

    pub fn validation_enabled(&self) -> bool {
        self.instance.debug_utils.is_some()
    }

    /// Whether pipeline-statistics queries were enabled on this device.
    pub fn has_pipeline_statistics(&self) -> bool {
        self.device.pipeline_statistics
    }

    /// Whether the device can draw a visibility buffer (`render::visibility`).
    pub fn has_visibility_buffer(&self) -> bool {
        self.device.visibility_buffer
    }

    pub(crate) fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        self.device.set_name(handle, name)
    }

    pub(crate) fn allocator(&self) -> MutexGuard<'_, Allocator> {
        // A panic while holding the lock cannot leave the allocator half-updated in a way we rely on.
        self.allocator.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Names of the allocations still live (empty when everything was destroyed).
    pub fn live_allocations(&self) -> Vec<String> {
        self.allocator().generate_report().allocations.into_iter().map(|a| a.name).collect()
    }

    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: a plain wait on a live device.
        unsafe { self.device.raw.device_wait_idle() }.vk("vkDeviceWaitIdle")
    }

    /// Closes the context and checks its teardown, as the GPU tests require: the device goes idle, no allocation
    /// is still live, and the validation layer (when on) reported nothing, the destruction included. Err: what
    /// was wrong, in words.
    pub fn close_checked(self) -> std::result::Result<(), String> {
        self.wait_idle().map_err(|e| format!("the device did not go idle: {e}"))?;
        let live = self.live_allocations();
        let log = self.validation();
        drop(self);
        if !live.is_empty() {
            return Err(format!("allocations still live at teardown: {live:?}"));
        }
        match log.count() {
            0 => Ok(()),
            n => Err(format!("{n} validation message(s):\n{}", log.messages().join("\n"))),
        }
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: the context owns these objects and drops them once, in reverse order of creation:
        // wait for the GPU, command pool, allocator (it frees its memory blocks through the device), device,
        // then the instance with its messenger.
        unsafe {
            let _ = self.device.raw.device_wait_idle();
            self.device.raw.destroy_command_pool(*self.command_pool.get_mut().unwrap_or_else(|e| e.into_inner()), None);
            ManuallyDrop::drop(&mut self.allocator);
            self.device.raw.destroy_device(None);
            ManuallyDrop::take(&mut self.instance).destroy();
        }
    }
}
