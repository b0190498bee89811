//! An object's surface maps on the GPU (`scene::mesh::maps`): the pigment map as an sRGB image (filtered in linear
//! light) and the normal map as a linear one, each with its mip chain, read through one repeating sampler that
//! filters trilinearly and anisotropically where the device can; one white texel stands in for a missing map (the
//! shaders skip it: `SurfaceUniforms::maps`).

use ash::vk;

use crate::error::Result;
use crate::gpu::interface::{BINDING_NORMAL_MAP, BINDING_PIGMENT_MAP};
use crate::gpu::vk::{Context, DescriptorWrite, Guard, Image, ImageDesc, ImageState, Sampler};
use crate::scene::mesh::maps::{MapKind, SurfaceMaps, Texture};

/// The anisotropy the maps' sampler asks for, where the device allows (16 is what GPUs offer).
pub const MAP_ANISOTROPY: f32 = 16.0;

pub(crate) struct MapImages {
    pigment: Image,
    normal: Image,
    sampler: Sampler,
    /// `SurfaceUniforms::maps`.
    pub flags: [f32; 4],
}

impl MapImages {
    pub fn new(ctx: &Context, maps: &SurfaceMaps) -> Result<Self> {
        let white = || Texture::with_mips(MapKind::Pigment, 1, 1, vec![[255; 4]], "none".into());
        let pigment = match &maps.pigment {
            Some(t) => upload(ctx, t)?,
            None => upload(ctx, &white())?,
        };
        let pigment = Guard::new(ctx, pigment);
        let normal = match &maps.normal {
            Some(t) => upload(ctx, t)?,
            None => upload(ctx, &Texture { kind: MapKind::Normal, ..white() })?,
        };
        let normal = Guard::new(ctx, normal);
        let sampler = ctx.create_map_sampler("surface maps", MAP_ANISOTROPY)?;
        Ok(Self { pigment: pigment.keep(), normal: normal.keep(), sampler, flags: maps.flags() })
    }

    pub fn writes(&self) -> [DescriptorWrite<'_>; 2] {
        [
            DescriptorWrite::SampledImage(BINDING_PIGMENT_MAP, &self.pigment, &self.sampler),
            DescriptorWrite::SampledImage(BINDING_NORMAL_MAP, &self.normal, &self.sampler),
        ]
    }

    /// # Safety
    /// The GPU must be done with them.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.pigment.destroy(ctx);
        self.normal.destroy(ctx);
        self.sampler.destroy(ctx);
    }
}

fn upload(ctx: &Context, t: &Texture) -> Result<Image> {
    let format = match t.kind {
        MapKind::Pigment => vk::Format::R8G8B8A8_SRGB,
        MapKind::Normal => vk::Format::R8G8B8A8_UNORM,
    };
    let mut desc = ImageDesc::texture_array(t.width, t.height, 1, format).with_mips(t.levels.len() as u32);
    desc.array = false;
    crate::render::diffraction::check_limits(ctx, &desc, &t.name)?;
    let image = Guard::new(ctx, ctx.create_image(desc, &t.name)?);
    let texels: Vec<[u8; 4]> = t.levels.iter().flatten().copied().collect();
    ctx.upload_image(&image, bytemuck::cast_slice(&texels), ImageState::SHADER_READ)?;
    Ok(image.keep())
}

crate::impl_destroy!(MapImages);
