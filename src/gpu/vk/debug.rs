//! Deliberate misuse for the test harness's canary: proves that a validation message is seen and counted.

use ash::vk;

use crate::gpu::vk::Context;

impl Context {
    /// Creates and destroys a buffer of size 0, which the Vulkan spec forbids (VUID-VkBufferCreateInfo-size-00912),
    /// so the validation layer reports an error. Used only by the test that checks the harness counts messages.
    #[doc(hidden)]
    pub fn provoke_validation_error(&self) {
        let info = vk::BufferCreateInfo::default().size(0).usage(vk::BufferUsageFlags::STORAGE_BUFFER);
        // SAFETY: invalid on purpose; the layer reports it before the driver sees it, and whatever handle comes
        // back is destroyed at once without being bound or used.
        unsafe {
            if let Ok(buffer) = self.device().create_buffer(&info, None) {
                self.device().destroy_buffer(buffer, None);
            }
        }
    }
}
