//! Images (render targets, depth buffers, 2D array textures) with their views, staging upload and readback,
//! and samplers.

use ash::vk;
use gpu_allocator::vulkan::Allocation;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::vk::{Buffer, BufferDesc, Context, Guard, ImageState, MemoryState};

/// Size, format and use of a GPU-only 2D (array) image.
#[derive(Clone, Copy, Debug)]
pub struct ImageDesc {
    pub width: u32,
    pub height: u32,
    pub layers: u32,
    pub format: vk::Format,
    pub usage: vk::ImageUsageFlags,
    /// View it as a 2D array even with one layer (shaders that declare `sampler2DArray` need that).
    pub array: bool,
    /// Mip levels (1: none); level l is max(1, width >> l) × max(1, height >> l).
    pub mip_levels: u32,
    /// Samples per pixel (`TYPE_1` except for multisampled render targets).
    pub samples: vk::SampleCountFlags,
}

impl ImageDesc {
    /// A colour target that can be read back.
    pub fn render_target(width: u32, height: u32, format: vk::Format) -> Self {
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        Self {
            width,
            height,
            layers: 1,
            format,
            usage,
            array: false,
            mip_levels: 1,
            samples: vk::SampleCountFlags::TYPE_1,
        }
    }

    pub fn depth(width: u32, height: u32) -> Self {
        let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        Self {
            width,
            height,
            layers: 1,
            format: vk::Format::D32_SFLOAT,
            usage,
            array: false,
            mip_levels: 1,
            samples: vk::SampleCountFlags::TYPE_1,
        }
    }

    /// A depth map drawn by one pass and sampled (with comparison) by a later one: the shadow map.
    pub fn sampled_depth(width: u32, height: u32) -> Self {
        let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        Self { usage, ..Self::depth(width, height) }
    }

    /// A sampled 2D texture (not an array) filled by upload.
    pub fn texture(width: u32, height: u32, format: vk::Format) -> Self {
        Self { array: false, ..Self::texture_array(width, height, 1, format) }
    }

    /// A sampled 2D array texture filled by upload (one layer per Taylor term, for instance).
    pub fn texture_array(width: u32, height: u32, layers: u32, format: vk::Format) -> Self {
        let usage =
            vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::TRANSFER_SRC;
        Self { width, height, layers, format, usage, array: true, mip_levels: 1, samples: vk::SampleCountFlags::TYPE_1 }
    }

    /// The same attachment with `samples` per pixel. A multisampled colour image is only rendered into and
    /// resolved (it is never read back), so it may live in transient memory.
    pub fn multisampled(self, samples: vk::SampleCountFlags) -> Self {
        if samples == vk::SampleCountFlags::TYPE_1 {
            return self;
        }
        let usage = if self.format == vk::Format::D32_SFLOAT {
            self.usage
        } else {
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT
        };
        Self { samples, usage, ..self }
    }

    /// The same with `levels` mip levels (uploaded level by level with [`Context::upload_image`]).
    pub fn with_mips(self, levels: u32) -> Self {
        Self { mip_levels: levels, ..self }
    }

    /// Width and height of mip level `level`.
    pub fn level_extent(&self, level: u32) -> (u32, u32) {
        ((self.width >> level).max(1), (self.height >> level).max(1))
    }

    /// Bytes per texel of the formats diffract uses.
    pub fn texel_size(&self) -> Result<u64> {
        Ok(match self.format {
            vk::Format::R8G8B8A8_UNORM | vk::Format::R8G8B8A8_SRGB | vk::Format::B8G8R8A8_SRGB => 4,
            vk::Format::B8G8R8A8_UNORM | vk::Format::R32_SFLOAT | vk::Format::D32_SFLOAT => 4,
            vk::Format::R32G32_SFLOAT => 8,
            vk::Format::R32G32B32A32_SFLOAT => 16,
            f => return Err(Error::Invalid(format!("no texel size known for {f:?}"))),
        })
    }

    /// Bytes of every layer of every mip level, tightly packed.
    pub fn byte_size(&self) -> Result<u64> {
        let texels: u64 =
            (0..self.mip_levels).map(|l| self.level_extent(l)).map(|(w, h)| u64::from(w) * u64::from(h)).sum();
        Ok(self.texel_size()? * texels * u64::from(self.layers))
    }
}

pub struct Image {
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub allocation: Allocation,
    pub desc: ImageDesc,
}

impl Image {
    pub fn aspect(&self) -> vk::ImageAspectFlags {
        if self.desc.format == vk::Format::D32_SFLOAT {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        }
    }

    pub fn extent(&self) -> vk::Extent2D {
        vk::Extent2D { width: self.desc.width, height: self.desc.height }
    }

    fn layers(&self, level: u32) -> vk::ImageSubresourceLayers {
        vk::ImageSubresourceLayers::default().aspect_mask(self.aspect()).mip_level(level).layer_count(self.desc.layers)
    }

    /// # Safety
    /// The GPU must be done with the image.
    pub unsafe fn destroy(self, ctx: &Context) {
        ctx.device().destroy_image_view(self.view, None);
        ctx.device().destroy_image(self.raw, None);
        let _ = ctx.allocator().free(self.allocation);
    }
}

/// A sampler (nearest filtering, clamped: diffract reads exact texels).
pub struct Sampler {
    pub raw: vk::Sampler,
}

impl Sampler {
    /// # Safety
    /// No pending work may use the sampler.
    pub unsafe fn destroy(self, ctx: &Context) {
        ctx.device().destroy_sampler(self.raw, None);
    }
}

impl Context {
    pub fn create_image(&self, desc: ImageDesc, name: &str) -> Result<Image> {
        if desc.width == 0 || desc.height == 0 || desc.layers == 0 || desc.mip_levels == 0 {
            return Err(Error::Invalid(format!("image {name:?} has an empty extent")));
        }
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D { width: desc.width, height: desc.height, depth: 1 })
            .mip_levels(desc.mip_levels)
            .array_layers(desc.layers)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: a plain create on a live device.
        let raw = Guard::new(self, unsafe { self.device().create_image(&info, None) }.vk("vkCreateImage")?);
        // SAFETY: `raw` is live.
        let requirements = unsafe { self.device().get_image_memory_requirements(*raw) };
        let allocation = self.allocate(name, requirements, MemoryLocation::GpuOnly, false)?;
        // SAFETY: memory fits the requirements.
        unsafe { self.device().bind_image_memory(*raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindImageMemory")?;
        let aspect = if desc.format == vk::Format::D32_SFLOAT {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let view_type =
            if desc.array || desc.layers > 1 { vk::ImageViewType::TYPE_2D_ARRAY } else { vk::ImageViewType::TYPE_2D };
        let view_info =
            vk::ImageViewCreateInfo::default().image(*raw).view_type(view_type).format(desc.format).subresource_range(
                vk::ImageSubresourceRange::default()
                    .aspect_mask(aspect)
                    .level_count(desc.mip_levels)
                    .layer_count(desc.layers),
            );
        // SAFETY: the view describes the image just created.
        let view = unsafe { self.device().create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        self.set_name(*raw, name);
        self.set_name(view, name);
        Ok(Image { raw: raw.keep(), view, allocation: allocation.keep(), desc })
    }

    /// Fills every layer of every mip level of `image` from `data` (tightly packed: level after level, each
    /// layer after layer) and leaves it in `final_state`. Returns the copy's GPU time in ms where the queue has
    /// timestamps.
    pub fn upload_image(&self, image: &Image, data: &[u8], final_state: ImageState) -> Result<Option<f64>> {
        let size = image.desc.byte_size()?;
        if data.len() as u64 != size {
            return Err(Error::Invalid(format!("image upload of {} bytes, expected {size}", data.len())));
        }
        // Destroyed at the scope's end: one_shot waits for the copy.
        let desc = BufferDesc::upload(size, vk::BufferUsageFlags::TRANSFER_SRC);
        let mut staging = Guard::new(self, self.create_buffer(desc, "staging (image upload)")?);
        staging.write(data)?;
        self.one_shot_timed("image upload", |cmd| {
            self.barrier_image(cmd, image, ImageState::UNDEFINED, ImageState::TRANSFER_DST);
            let texel = image.desc.texel_size().expect("checked by byte_size");
            let mut offset = 0;
            let regions: Vec<_> = (0..image.desc.mip_levels)
                .map(|level| {
                    let (width, height) = image.desc.level_extent(level);
                    let region = vk::BufferImageCopy::default()
                        .buffer_offset(offset)
                        .image_subresource(image.layers(level))
                        .image_extent(vk::Extent3D { width, height, depth: 1 });
                    offset += texel * u64::from(width * height) * u64::from(image.desc.layers);
                    region
                })
                .collect();
            // SAFETY: the staging buffer holds exactly the image's texels, level after level.
            unsafe {
                self.device().cmd_copy_buffer_to_image(
                    cmd,
                    staging.raw,
                    image.raw,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &regions,
                )
            };
            self.barrier_image(cmd, image, ImageState::TRANSFER_DST, final_state);
        })
    }

    /// Reads every layer of a colour image's first mip level back (tightly packed); `state` is the image's
    /// current state, and the image is left in it.
    pub fn read_image(&self, image: &Image, state: ImageState) -> Result<Vec<u8>> {
        // Destroyed at the scope's end: one_shot waits for the copy.
        let readback = Guard::new(self, self.create_readback(image)?);
        self.one_shot("image readback", |cmd| self.record_readback(cmd, image, state, &readback))?;
        Ok(readback.mapped().map(<[u8]>::to_vec).unwrap_or_default())
    }

    /// A host-visible buffer as large as `image`'s first mip level (every layer), for [`Self::record_readback`].
    pub fn create_readback(&self, image: &Image) -> Result<Buffer> {
        let size = ImageDesc { mip_levels: 1, ..image.desc }.byte_size()?;
        self.create_buffer(BufferDesc::readback(size), "readback (image)")
    }

    /// Records the copy of `image`'s first mip level (in `state`, and left in it) into `readback` (made by
    /// [`Self::create_readback`]), visible to the host once the submission completes.
    pub fn record_readback(&self, cmd: vk::CommandBuffer, image: &Image, state: ImageState, readback: &Buffer) {
        self.barrier_image(cmd, image, state, ImageState::TRANSFER_SRC);
        let region = vk::BufferImageCopy::default().image_subresource(image.layers(0)).image_extent(vk::Extent3D {
            width: image.desc.width,
            height: image.desc.height,
            depth: 1,
        });
        // SAFETY: the readback buffer is as large as the image's texels.
        unsafe {
            self.device().cmd_copy_image_to_buffer(
                cmd,
                image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.raw,
                &[region],
            )
        };
        self.barrier_image(cmd, image, ImageState::TRANSFER_SRC, state);
        self.barrier_memory(cmd, MemoryState::TRANSFER_WRITE, MemoryState::HOST_READ);
    }

    /// Whether the device filters `format` linearly when sampling (the baked table's trilinear fetches need it).
    pub fn filters_linearly(&self, format: vk::Format) -> bool {
        // SAFETY: a query on a live instance and one of its physical devices.
        let props = unsafe { self.instance().get_physical_device_format_properties(self.info.raw, format) };
        props.optimal_tiling_features.contains(vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR)
    }

    /// The sample count for `samples` per pixel in colour attachments of `format` with a depth buffer, or why
    /// the device cannot (the counts it can, in one line).
    pub fn sample_count(&self, samples: u32, format: vk::Format) -> Result<vk::SampleCountFlags> {
        let limits = &self.info.limits;
        let mut supported = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
        // SAFETY: a query on a live instance and one of its physical devices.
        let props = unsafe {
            self.instance().get_physical_device_image_format_properties(
                self.info.raw,
                format,
                vk::ImageType::TYPE_2D,
                vk::ImageTiling::OPTIMAL,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                vk::ImageCreateFlags::empty(),
            )
        };
        supported &= props.map_or(vk::SampleCountFlags::TYPE_1, |p| p.sample_counts);
        let flag = vk::SampleCountFlags::from_raw(samples);
        if samples.is_power_of_two() && samples <= 64 && supported.contains(flag) {
            return Ok(flag);
        }
        let counts: Vec<String> = (0..7)
            .map(|b| 1u32 << b)
            .filter(|&n| supported.contains(vk::SampleCountFlags::from_raw(n)))
            .map(|n| n.to_string())
            .collect();
        Err(Error::setting(
            "samples",
            format!("{samples} samples per pixel: {} supports {} (--samples)", self.info.name, counts.join(", ")),
        ))
    }

    /// A shadow map's sampler: with `compare`, a depth-comparison sampler (`sampler2DShadow`: a reference depth
    /// passes where it is at most the stored one, LESS_OR_EQUAL, filtered bilinearly where the device filters
    /// D32: four texels' results averaged); without, one that reads the depths themselves, nearest. Outside the
    /// map the border's depth 1 lets everything pass (what the map does not cover is lit).
    pub fn create_shadow_sampler(&self, name: &str, compare: bool) -> Result<Sampler> {
        let linear = compare && self.filters_linearly(vk::Format::D32_SFLOAT);
        let filter = if linear { vk::Filter::LINEAR } else { vk::Filter::NEAREST };
        let info = vk::SamplerCreateInfo::default()
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .compare_enable(compare)
            .compare_op(vk::CompareOp::LESS_OR_EQUAL)
            .border_color(vk::BorderColor::FLOAT_OPAQUE_WHITE);
        self.sampler(info, filter, vk::SamplerAddressMode::CLAMP_TO_BORDER, name)
    }

    /// `info` filtering by `filter` and addressing by `address` on every axis, named.
    fn sampler(
        &self,
        info: vk::SamplerCreateInfo<'_>,
        filter: vk::Filter,
        address: vk::SamplerAddressMode,
        name: &str,
    ) -> Result<Sampler> {
        let info = info
            .mag_filter(filter)
            .min_filter(filter)
            .address_mode_u(address)
            .address_mode_v(address)
            .address_mode_w(address);
        // SAFETY: a plain create on a live device.
        let raw = unsafe { self.device().create_sampler(&info, None) }.vk("vkCreateSampler")?;
        self.set_name(raw, name);
        Ok(Sampler { raw })
    }

    /// A surface map's sampler: repeating, trilinear, and anisotropic up to `anisotropy` (within the device's
    /// limit) where the device filters so and is not a CPU: lavapipe's anisotropic reads with explicit gradients
    /// return stray bright texels in a compute shader (the visibility buffer's edge pass: a dotted line of them
    /// along a plane's diagonal), where its fragment shaders read the same texels right.
    pub fn create_map_sampler(&self, name: &str, anisotropy: f32) -> Result<Sampler> {
        let mut info =
            vk::SamplerCreateInfo::default().mipmap_mode(vk::SamplerMipmapMode::LINEAR).max_lod(vk::LOD_CLAMP_NONE);
        if self.device.sampler_anisotropy && self.info.kind != vk::PhysicalDeviceType::CPU {
            let most = anisotropy.min(self.info.limits.max_sampler_anisotropy);
            info = info.anisotropy_enable(true).max_anisotropy(most);
        }
        self.sampler(info, vk::Filter::LINEAR, vk::SamplerAddressMode::REPEAT, name)
    }

    /// A bilinear sampler for an equirectangular map: wrapping around in x (the azimuth), clamped in y.
    pub fn create_panorama_sampler(&self, name: &str) -> Result<Sampler> {
        let info = vk::SamplerCreateInfo::default().address_mode_u(vk::SamplerAddressMode::REPEAT);
        let info = info
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE);
        // SAFETY: a plain create on a live device.
        let raw = unsafe { self.device().create_sampler(&info, None) }.vk("vkCreateSampler")?;
        self.set_name(raw, name);
        Ok(Sampler { raw })
    }

    /// A nearest-filtering, edge-clamped sampler (diffract reads exact texels with `texelFetch`).
    pub fn create_sampler(&self, name: &str) -> Result<Sampler> {
        self.create_filtered_sampler(name, false)
    }

    /// The baked table's sampler: bilinear within a level, edge-clamped, and between the mip levels by `mip`
    /// (`physics::baked::sample::MipFilter` chooses it; its CPU twin reads the table the same way).
    pub fn create_table_sampler(&self, name: &str, mip: vk::SamplerMipmapMode) -> Result<Sampler> {
        let info = vk::SamplerCreateInfo::default().mipmap_mode(mip).max_lod(vk::LOD_CLAMP_NONE);
        self.sampler(info, vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE, &format!("{name} ({mip:?})"))
    }

    /// An edge-clamped sampler: `linear` filters trilinearly over every mip level (the environment's moments),
    /// else nearest.
    pub fn create_filtered_sampler(&self, name: &str, linear: bool) -> Result<Sampler> {
        let (filter, mip) = if linear {
            (vk::Filter::LINEAR, vk::SamplerMipmapMode::LINEAR)
        } else {
            (vk::Filter::NEAREST, vk::SamplerMipmapMode::NEAREST)
        };
        let info = vk::SamplerCreateInfo::default().mipmap_mode(mip).max_lod(vk::LOD_CLAMP_NONE);
        self.sampler(info, filter, vk::SamplerAddressMode::CLAMP_TO_EDGE, name)
    }
}
