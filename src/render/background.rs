//! The environment drawn behind a scene: a full-screen triangle at the far plane, drawn after the objects with an
//! EQUAL depth test so that it covers only the samples no object covered (`glsl/background.frag.glsl`), looks up
//! each pixel's view ray in the environment's equirectangular map.
//!
//! The map is the scene's file (`[light] environment = "FILE.exr"`, uploaded once) or the clear sky with its sun
//! (`environment = "sky"`, rendered by [`EnvironmentMap::of_sky_and_sun`] at [`SKY_WIDTH`] and again whenever the
//! sun moves). Its texels (cd/m²) are shown in the frame's units, the sun's radiance, as the pigment's sky light is.

use ash::vk;
use bytemuck::Zeroable;
use glam::Vec3;

use crate::error::Result;
use crate::gpu::interface::BackgroundUniforms;
use crate::gpu::interface::{BINDING_ENVIRONMENT, BINDING_FRAME, SPEC_DISPLAY_OUTPUT};
use crate::gpu::shaders;
use crate::gpu::vk::{
    Blend, Buffer, BufferDesc, Context, DepthTest, DescriptorWrite, GraphicsPipelineDesc, Guard, Image, ImageDesc,
    ImageState, Pipeline, Sampler, SpecConstants,
};
use crate::light::environment::EnvironmentMap;
use crate::scene::Environment;

/// The width of the clear sky's map behind a scene (its height is half): 0.7° texels, about the sun's disc.
pub const SKY_WIDTH: u32 = 512;
/// The pass's name (labels).
pub const NAME: &str = "environment";

/// Which map is on the GPU: a file's (by its address in memory: the scene's map is shared, never changed) or the
/// sky's for one sun.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shown {
    Map(usize),
    Sky { turbidity: u64, sun: [u32; 3] },
}

/// An environment's equirectangular map on the GPU (`Environment::panorama`), uploaded again only when another map
/// or another sun is asked for.
pub(crate) struct Panorama {
    texture: Option<(Image, Shown)>,
    /// Whether the sky's map holds its sun (drawn behind) or not (lighting).
    with_sun: bool,
    /// The clear sky's map width.
    sky_width: u32,
}

impl Panorama {
    pub fn new(with_sun: bool, sky_width: u32) -> Self {
        Self { texture: None, with_sun, sky_width }
    }

    /// The map for `environment` around the sun towards `light_dir` (uploaded where it is not there yet), its
    /// factor to the frame's units and its turn (radians); None while the sun is below the horizon. No submitted
    /// work may still read the old map.
    pub fn update(&mut self, ctx: &Context, environment: &Environment, light_dir: Vec3) -> Result<Option<(f64, f64)>> {
        let shown = match environment {
            Environment::Map(m) => Shown::Map(std::sync::Arc::as_ptr(m) as usize),
            Environment::Sky(sky) => {
                Shown::Sky { turbidity: sky.turbidity.to_bits(), sun: light_dir.to_array().map(f32::to_bits) }
            }
        };
        if self.texture.as_ref().map(|t| t.1) == Some(shown) {
            // The same map: only the unit (the sun's luminance) to give.
            return Ok(environment.panorama_units(light_dir));
        }
        let Some((map, scale, rotation)) = environment.panorama(light_dir, self.with_sun, self.sky_width)? else {
            return Ok(None);
        };
        let image = Guard::new(ctx, upload(ctx, &map)?);
        if let Some((old, _)) = self.texture.replace((image.keep(), shown)) {
            // SAFETY: the caller promises no submitted work still reads the map.
            unsafe { old.destroy(ctx) };
        }
        Ok(Some((scale, rotation)))
    }

    /// The map on the GPU, once updated.
    pub fn image(&self) -> Option<&Image> {
        self.texture.as_ref().map(|t| &t.0)
    }

    /// # Safety
    /// The GPU must be done with it.
    pub unsafe fn destroy(self, ctx: &Context) {
        if let Some((image, _)) = self.texture {
            image.destroy(ctx);
        }
    }
}

/// The pass: its pipeline, the map's texture and the uniforms.
pub struct BackgroundPass {
    pipeline: Pipeline,
    sampler: Sampler,
    uniforms: Buffer,
    panorama: Panorama,
    values: BackgroundUniforms,
}

impl BackgroundPass {
    /// A pass drawing into `color_format` targets of `samples` (display-encoded with `display_output`), behind
    /// the objects (an EQUAL depth test at the far plane); with `under`, into a one-sample target whose depth it
    /// leaves untested, under the premultiplied colours and coverage the objects left there (the visibility
    /// buffer's).
    pub fn new(
        ctx: &Context,
        color_format: vk::Format,
        display_output: bool,
        samples: vk::SampleCountFlags,
        under: bool,
    ) -> Result<Self> {
        let pipeline = Guard::new(
            ctx,
            ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                name: NAME,
                vertex: &shaders::BACKGROUND_VERT,
                fragment: Some(&shaders::BACKGROUND_FRAG),
                specialization: SpecConstants::default().u32(SPEC_DISPLAY_OUTPUT, u32::from(display_output)),
                push_constant_size: 0,
                vertex_stride: 0,
                vertex_attributes: &[],
                color_format,
                depth: Some((crate::render::DEPTH_FORMAT, if under { DepthTest::Off } else { DepthTest::Equal })),
                cull_back_faces: false,
                samples: if under { vk::SampleCountFlags::TYPE_1 } else { samples },
                blend: if under { Blend::Under } else { Blend::Replace },
            })?,
        );
        let sampler = Guard::new(ctx, ctx.create_panorama_sampler(NAME)?);
        let size = std::mem::size_of::<BackgroundUniforms>() as u64;
        let uniforms = ctx.create_buffer(BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER), NAME)?;
        let values = BackgroundUniforms::zeroed();
        let panorama = Panorama::new(true, SKY_WIDTH);
        Ok(Self { pipeline: pipeline.keep(), sampler: sampler.keep(), uniforms, panorama, values })
    }

    /// Makes the pass show `environment` around the sun towards `light_dir` from `camera` into a target of
    /// `aspect` (uploading its map where it is not there yet); no submitted work may still read it.
    pub fn update(
        &mut self,
        ctx: &Context,
        environment: &Environment,
        light_dir: Vec3,
        (camera, aspect): (&crate::scene::camera::Camera, f32),
    ) -> Result<()> {
        let Some((scale, rotation)) = self.panorama.update(ctx, environment, light_dir)? else {
            // The sun below the horizon: the frame has no unit, the environment shows black.
            self.values.view[0] = 0.0;
            return self.uniforms.write(bytemuck::bytes_of(&self.values));
        };
        self.values.inverse_view_proj = camera.view_projection(aspect).inverse().to_cols_array_2d();
        self.values.camera = camera.position.extend(0.0).to_array();
        self.values.view = [scale as f32, rotation as f32, 0.0, 0.0];
        self.uniforms.write(bytemuck::bytes_of(&self.values))
    }

    /// Sets a display-encoded target's exposure and tone curve (`display::tone::display_uniform`); no submitted
    /// work may still read the uniforms.
    pub fn set_display(&mut self, display: [f32; 4]) -> Result<()> {
        self.values.display = display;
        self.uniforms.write(bytemuck::bytes_of(&self.values))
    }

    /// Records the draw (inside the scene's rendering, after its objects); nothing before the first update.
    pub fn record(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        let Some(image) = self.panorama.image() else { return };
        ctx.begin_label(cmd, NAME);
        let writes = [
            DescriptorWrite::UniformBuffer(BINDING_FRAME, &self.uniforms),
            DescriptorWrite::SampledImage(BINDING_ENVIRONMENT, image, &self.sampler),
        ];
        ctx.bind(cmd, &self.pipeline, &writes, &[]);
        // SAFETY: cmd is recording inside a rendering scope with this pipeline bound.
        unsafe { ctx.device().cmd_draw(cmd, 3, 1, 0, 0) };
        ctx.end_label(cmd);
    }

    /// # Safety
    /// The GPU must be done with it.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.pipeline.destroy(ctx);
        self.sampler.destroy(ctx);
        self.uniforms.destroy(ctx);
        self.panorama.destroy(ctx);
    }
}

/// The map as an RGBA32F texture.
pub(crate) fn upload(ctx: &Context, map: &EnvironmentMap) -> Result<Image> {
    let image = Guard::new(
        ctx,
        ctx.create_image(ImageDesc::texture(map.width, map.height, crate::render::LINEAR_FORMAT), NAME)?,
    );
    ctx.upload_image(&image, bytemuck::cast_slice(&map.to_rgba()), ImageState::SHADER_READ)?;
    Ok(image.keep())
}

crate::impl_destroy!(BackgroundPass);
