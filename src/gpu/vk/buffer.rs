//! Buffers: GPU-only, upload (host-visible, written by the CPU) and readback (host-visible, read by the CPU).

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::vk::{Context, Guard, MemoryState};

/// What a buffer is for and where its memory lives.
#[derive(Clone, Copy, Debug)]
pub struct BufferDesc {
    pub size: u64,
    pub usage: vk::BufferUsageFlags,
    pub location: MemoryLocation,
}

impl BufferDesc {
    /// Device-local memory, filled by transfers or shaders.
    pub fn gpu_only(size: u64, usage: vk::BufferUsageFlags) -> Self {
        Self { size, usage: usage | vk::BufferUsageFlags::TRANSFER_DST, location: MemoryLocation::GpuOnly }
    }

    /// Host-visible memory the CPU writes and the GPU reads (staging, per-frame uniforms).
    pub fn upload(size: u64, usage: vk::BufferUsageFlags) -> Self {
        Self { size, usage, location: MemoryLocation::CpuToGpu }
    }

    /// Host-visible memory the GPU writes and the CPU reads back.
    pub fn readback(size: u64) -> Self {
        Self {
            size,
            usage: vk::BufferUsageFlags::TRANSFER_DST | vk::BufferUsageFlags::STORAGE_BUFFER,
            location: MemoryLocation::GpuToCpu,
        }
    }
}

pub struct Buffer {
    pub raw: vk::Buffer,
    pub allocation: Allocation,
    pub desc: BufferDesc,
}

impl Buffer {
    /// The mapped bytes of a host-visible buffer.
    pub fn mapped(&self) -> Option<&[u8]> {
        self.allocation.mapped_slice().map(|s| &s[..self.desc.size as usize])
    }

    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        let size = self.desc.size as usize;
        self.allocation.mapped_slice_mut().map(|s| &mut s[..size])
    }

    /// Copies `data` into a host-visible buffer.
    pub fn write(&mut self, data: &[u8]) -> Result<()> {
        let dst = self.mapped_mut().ok_or_else(|| Error::Invalid("buffer is not host-visible".into()))?;
        if data.len() > dst.len() {
            return Err(Error::Invalid(format!("{} bytes do not fit a {}-byte buffer", data.len(), dst.len())));
        }
        dst[..data.len()].copy_from_slice(data);
        Ok(())
    }

    /// # Safety
    /// The GPU must be done with the buffer.
    pub unsafe fn destroy(self, ctx: &Context) {
        ctx.device().destroy_buffer(self.raw, None);
        let _ = ctx.allocator().free(self.allocation);
    }
}

impl Context {
    pub fn create_buffer(&self, desc: BufferDesc, name: &str) -> Result<Buffer> {
        if desc.size == 0 {
            return Err(Error::Invalid(format!("buffer {name:?} has size 0")));
        }
        let info = vk::BufferCreateInfo::default().size(desc.size).usage(desc.usage);
        // SAFETY: a plain create on a live device.
        let raw = Guard::new(self, unsafe { self.device().create_buffer(&info, None) }.vk("vkCreateBuffer")?);
        // SAFETY: `raw` is a live buffer.
        let requirements = unsafe { self.device().get_buffer_memory_requirements(*raw) };
        let allocation = self.allocate(name, requirements, desc.location, true)?;
        // SAFETY: memory and offset come from an allocation made for this buffer's requirements.
        unsafe { self.device().bind_buffer_memory(*raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindBufferMemory")?;
        self.set_name(*raw, name);
        Ok(Buffer { raw: raw.keep(), allocation: allocation.keep(), desc })
    }

    /// Memory for a buffer or image of `requirements` (`linear`: a buffer, or an image with linear tiling), under
    /// a guard that gives it back to the allocator unless kept.
    pub(crate) fn allocate(
        &self,
        name: &str,
        requirements: vk::MemoryRequirements,
        location: MemoryLocation,
        linear: bool,
    ) -> Result<Guard<'_, Allocation>> {
        let allocation = self
            .allocator()
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|cause| Error::Allocation { name: name.into(), cause })?;
        Ok(Guard::new(self, allocation))
    }

    /// A GPU-only buffer filled with `data` through a staging copy.
    pub fn create_buffer_init(&self, usage: vk::BufferUsageFlags, data: &[u8], name: &str) -> Result<Buffer> {
        let buffer = Guard::new(self, self.create_buffer(BufferDesc::gpu_only(data.len() as u64, usage), name)?);
        // A failed upload was waited for (or never submitted): the guard may destroy the buffer.
        self.upload_to_buffer(&buffer, data)?;
        Ok(buffer.keep())
    }

    fn upload_to_buffer(&self, buffer: &Buffer, data: &[u8]) -> Result<()> {
        let desc = BufferDesc::upload(data.len() as u64, vk::BufferUsageFlags::TRANSFER_SRC);
        // Destroyed at the scope's end: one_shot waits for the copy.
        let mut staging = Guard::new(self, self.create_buffer(desc, "staging (buffer upload)")?);
        staging.write(data)?;
        self.one_shot("buffer upload", |cmd| {
            let region = vk::BufferCopy::default().size(data.len() as u64);
            // SAFETY: both buffers are live and large enough.
            unsafe { self.device().cmd_copy_buffer(cmd, staging.raw, buffer.raw, &[region]) };
            self.barrier_memory(cmd, MemoryState::TRANSFER_WRITE, MemoryState::ALL_READS);
        })
    }

    /// Copies a buffer's contents back to the CPU (directly if it is host-visible).
    pub fn read_buffer(&self, buffer: &Buffer) -> Result<Vec<u8>> {
        if let Some(bytes) = buffer.mapped() {
            return Ok(bytes.to_vec());
        }
        // Destroyed at the scope's end: one_shot waits for the copy.
        let readback =
            Guard::new(self, self.create_buffer(BufferDesc::readback(buffer.desc.size), "readback (buffer)")?);
        self.one_shot("buffer readback", |cmd| {
            self.barrier_memory(cmd, MemoryState::ALL_WRITES, MemoryState::TRANSFER_READ);
            let region = vk::BufferCopy::default().size(buffer.desc.size);
            // SAFETY: both buffers are live and the same size.
            unsafe { self.device().cmd_copy_buffer(cmd, buffer.raw, readback.raw, &[region]) };
            self.barrier_memory(cmd, MemoryState::TRANSFER_WRITE, MemoryState::HOST_READ);
        })?;
        Ok(readback.mapped().map(<[u8]>::to_vec).unwrap_or_default())
    }
}
