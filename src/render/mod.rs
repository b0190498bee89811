//! Frames: offscreen targets, the passes that draw into them, and readback to CPU images.
//!
//! Offscreen capture and the window share everything but the final target: a pass records into a
//! [`TargetView`], which either an [`OffscreenTarget`] or a `window::WindowTarget`'s frame provides.

pub mod background;
pub mod capture;
pub mod diffraction;
pub mod env_map;
pub mod forward;
pub mod gbuffer;
pub mod lamp_shadow;
pub mod map;
pub mod maps;
pub mod offscreen;
pub mod preview;
pub mod scene_gpu;
pub mod shadow;
pub mod surface;
pub(crate) mod variants;
pub mod visibility;
#[cfg(feature = "view")]
pub mod window;
pub mod workload;

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::vk::{Buffer, Context, Destroy, Guard, Image, ImageDesc, ImageState, Laps, Statistics};
use crate::scene::mesh::Mesh;

/// The format of offscreen colour targets: 8-bit sRGB, so the store applies the sRGB transfer function and the
/// bytes read back are what a PNG holds.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The largest edge a frame may have (a sanity bound for user input; far above any display).
pub const MAX_EDGE: u32 = 16384;

/// Linear, scene-referred float colour (BRDF maps, EXR output).
pub const LINEAR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// The names of a frame's passes, as timed (`crate::gpu::vk::Laps`), labelled and reported: a scene's frame is the
/// depth pre-pass, the shading, the resolve of its samples (multisampled frames), and the copy to the CPU
/// (offscreen) or the hand-over to the window.
pub mod pass {
    pub const DEPTH: &str = "depth pre-pass";
    pub const SHADING: &str = "shading";
    pub const RESOLVE: &str = "resolve";
    pub const COPY: &str = "copy";
    pub const PRESENT: &str = "present";
    /// The visibility buffer's raster pass (`render::visibility`): depth and triangle ids, before the shading.
    pub const VISIBILITY: &str = "visibility";
    /// The visibility buffer's edge pass: the further triangles of the pixels that see more than one, after the
    /// shading (multisampled frames).
    pub const EDGES: &str = "edges";
    /// Every pass, in frame order (the profile's columns).
    pub const ALL: [&str; 7] = [DEPTH, VISIBILITY, SHADING, EDGES, RESOLVE, COPY, PRESENT];
}

/// Each pass's median GPU time over `frames`, for the passes every frame timed, in frame order:
/// `depth pre-pass 7.03, shading 13.40, copy 0.71` (None where the frames have no timings).
pub fn pass_medians(frames: &[crate::gpu::vk::FrameTimes]) -> Option<String> {
    let passes: Vec<String> = pass::ALL
        .iter()
        .filter_map(|&name| {
            let ms: Vec<f64> = frames.iter().filter_map(|t| t.pass_ms(name)).collect();
            (ms.len() == frames.len())
                .then(|| crate::io::stats::median(&ms))
                .flatten()
                .map(|m| format!("{name} {m:.2}"))
        })
        .collect();
    (!passes.is_empty()).then(|| passes.join(", "))
}

/// What a frame's recording is measured with (all off by default).
#[derive(Clone, Copy, Default)]
pub struct Instruments<'a> {
    /// A counting renderer's per-pixel fetch counters.
    pub counts: Option<&'a Buffer>,
    /// The shading draws' pipeline-statistics query.
    pub statistics: Option<&'a Statistics<'a>>,
    /// Where each pass's end is timed.
    pub laps: Laps<'a>,
}

/// What a pass draws into.
#[derive(Clone, Copy, Debug)]
pub struct TargetView {
    /// The image drawn into: multisampled when `resolve` is set.
    pub color: vk::ImageView,
    /// The single-sampled image that the multisampled `color` is averaged into at the end of the pass.
    pub resolve: Option<vk::ImageView>,
    pub depth: Option<vk::ImageView>,
    pub extent: vk::Extent2D,
    /// Samples per pixel of `color` and `depth` (the pipelines drawing must be built for it).
    pub samples: vk::SampleCountFlags,
    /// The single-sampled colour image where it is also a storage image (a target readied for a visibility
    /// buffer: [`OffscreenTarget::for_visibility_buffer`]), whose edge pass adds to it; None elsewhere.
    pub storage: Option<vk::Image>,
}

/// What a scene's surface frame is drawn under: the camera, the light, the sky, each object's placement and the
/// background (clear) colour.
#[derive(Clone, Debug)]
pub struct SceneView {
    pub camera: crate::scene::camera::Camera,
    /// World-space unit vector towards the light.
    pub light_dir: glam::Vec3,
    /// 1, or 0 where no sun lights the scene (`Scene::sun_strength`: a map alone).
    pub sun: f32,
    /// The sky's radiance relative to the sun seen in a mirror.
    pub ambient: f32,
    /// The environment's irradiance for this light (`surface::SurfaceUniforms::sky_sh`; zero without one).
    pub sky_sh: [[f32; 4]; 9],
    /// One model matrix per object, in the order the renderer was built with.
    pub models: Vec<glam::Mat4>,
    /// The sun's shadow: which objects cast one (in the same order; the others only receive); None: no shadow
    /// map, every surface is lit.
    pub shadow_casters: Option<Vec<bool>>,
    /// The environment drawn behind the objects (None: the background colour).
    pub behind: Option<crate::scene::Environment>,
    /// The environment whose light the objects reflect (its specular reflection; None: no environment).
    pub lighting: Option<crate::scene::Environment>,
    pub background: [f32; 4],
    /// The lamps, in the frame's units (`light::lamp::LampUniforms`).
    pub lamps: crate::light::lamp::LampUniforms,
}

impl SceneView {
    /// The scene file's own camera, light, sky, placements and background.
    pub fn of(scene: &crate::scene::Scene) -> Self {
        Self::lit(scene, scene.camera, scene.light_dir)
    }

    /// The scene seen from `camera` with its light towards `light_dir` (the sky follows its sun).
    pub fn lit(scene: &crate::scene::Scene, camera: crate::scene::camera::Camera, light_dir: glam::Vec3) -> Self {
        let [r, g, b] = scene.render.background;
        Self {
            camera,
            light_dir,
            sun: scene.sun_strength(),
            ambient: scene.ambient,
            sky_sh: scene.environment.as_ref().map_or([[0.0; 4]; 9], |e| e.irradiance(light_dir)),
            models: scene.objects.iter().map(|o| o.model).collect(),
            shadow_casters: scene.shadows.then(|| scene.objects.iter().map(|o| o.casts_shadow).collect()),
            behind: scene.environment.clone().filter(|_| scene.environment_behind),
            lighting: scene.environment.clone(),
            background: [r, g, b, 1.0],
            lamps: crate::light::lamp::LampUniforms::new(&scene.lamps, scene.unit_luminance(light_dir)),
        }
    }

    /// The same view with nothing behind the objects (transparent black, no environment drawn): its frame's alpha
    /// is each pixel's coverage by the objects, the subject auto exposure meters (`SceneCapture::meter`).
    pub fn without_background(&self) -> Self {
        Self { behind: None, background: [0.0; 4], ..self.clone() }
    }
}

/// A frame read back to the CPU, rows top first: what every offscreen pass but the BRDF map (a
/// [`map::MapImage`], square and in direction space) gives.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub pixels: Pixels,
    /// GPU time of each of the frame's passes from timestamp queries, where the device has them.
    pub times: Option<crate::gpu::vk::FrameTimes>,
}

/// A frame's pixels, four channels each.
#[derive(Clone, Debug)]
pub enum Pixels {
    /// 8-bit, display-encoded (sRGB).
    Rgba8(Vec<u8>),
    /// Linear, scene-referred float.
    Linear(Vec<f32>),
}

impl Frame {
    /// The frame's GPU time (its passes together), where the device has timestamps.
    pub fn gpu_ms(&self) -> Option<f64> {
        self.times.as_ref().map(crate::gpu::vk::FrameTimes::total_ms)
    }

    /// The display-encoded pixels, if the frame has them.
    pub fn rgba8(&self) -> Option<&[u8]> {
        match &self.pixels {
            Pixels::Rgba8(p) => Some(p),
            Pixels::Linear(_) => None,
        }
    }

    /// The linear pixels, if the frame has them.
    pub fn linear(&self) -> Option<&[f32]> {
        match &self.pixels {
            Pixels::Linear(p) => Some(p),
            Pixels::Rgba8(_) => None,
        }
    }
}

/// A colour and (optionally) a depth image for headless rendering, multisampled or not.
pub struct OffscreenTarget {
    /// The single-sampled image read back (the resolve target when multisampled).
    pub color: Image,
    /// The multisampled image drawn into, resolved into `color`.
    pub msaa: Option<Image>,
    pub depth: Option<Image>,
}

impl OffscreenTarget {
    /// An 8-bit sRGB colour target with depth, one sample per pixel.
    pub fn new(ctx: &Context, width: u32, height: u32) -> Result<Self> {
        Self::with_format(ctx, width, height, COLOR_FORMAT, true)
    }

    /// One sample per pixel.
    pub fn with_format(ctx: &Context, width: u32, height: u32, format: vk::Format, depth: bool) -> Result<Self> {
        Self::multisampled(ctx, width, height, format, depth, vk::SampleCountFlags::TYPE_1)
    }

    /// A single-sampled colour image of `desc` (which may add usages, e.g. storage) and no depth.
    pub fn with_color(ctx: &Context, desc: ImageDesc) -> Result<Self> {
        let color = ctx.create_image(desc, "offscreen colour")?;
        Ok(Self { color, msaa: None, depth: None })
    }

    /// `samples` per pixel (then resolved into the single-sampled [`Self::color`] by each pass).
    pub fn multisampled(
        ctx: &Context,
        width: u32,
        height: u32,
        format: vk::Format,
        depth: bool,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        let limit = ctx.info.limits.max_image_dimension2_d;
        if width > limit || height > limit {
            return Err(crate::Error::unsupported(
                &ctx.info.name,
                format!("{width}×{height} exceeds the device's {limit}-pixel image limit"),
            ));
        }
        let color =
            Guard::new(ctx, ctx.create_image(ImageDesc::render_target(width, height, format), "offscreen colour")?);
        let msaa = match samples {
            vk::SampleCountFlags::TYPE_1 => None,
            _ => {
                let desc = ImageDesc::render_target(width, height, format).multisampled(samples);
                Some(ctx.create_image(desc, "offscreen colour (multisampled)")?)
            }
        };
        let msaa = Guard::new(ctx, msaa);
        let depth = match depth {
            true => Some(ctx.create_image(ImageDesc::depth(width, height).multisampled(samples), "offscreen depth")?),
            false => None,
        };
        Ok(Self { color: color.keep(), msaa: msaa.keep(), depth })
    }

    pub fn view(&self) -> TargetView {
        let (color, resolve, samples) = match &self.msaa {
            Some(m) => (m.view, Some(self.color.view), m.desc.samples),
            None => (self.color.view, None, vk::SampleCountFlags::TYPE_1),
        };
        // Without colour samples (`for_visibility_buffer`) the depth says how many the frame has.
        let samples = self.depth.as_ref().map_or(samples, |d| d.desc.samples);
        let storage = self.color.desc.usage.contains(vk::ImageUsageFlags::STORAGE).then_some(self.color.raw);
        let depth = self.depth.as_ref().map(|d| d.view);
        TargetView { color, resolve, depth, extent: self.color.extent(), samples, storage }
    }

    /// Readies the target for frames a visibility buffer draws (`render::visibility`): frees its colour samples
    /// (only its depth is multisampled, and the shading pass writes straight into [`Self::color`]) and makes
    /// [`Self::color`] a storage image as well, which the edge pass adds to.
    ///
    /// # Safety
    /// The GPU must be done with the target.
    pub unsafe fn for_visibility_buffer(&mut self, ctx: &Context) -> Result<()> {
        if let Some(msaa) = self.msaa.take() {
            msaa.destroy(ctx);
        }
        if !self.color.desc.usage.contains(vk::ImageUsageFlags::STORAGE) {
            let mut desc = self.color.desc;
            desc.usage |= vk::ImageUsageFlags::STORAGE;
            let color = ctx.create_image(desc, "offscreen colour")?;
            std::mem::replace(&mut self.color, color).destroy(ctx);
        }
        Ok(())
    }

    /// Puts the images into attachment layouts (their contents are discarded).
    pub fn begin(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        for image in std::iter::once(&self.color).chain(&self.msaa) {
            ctx.barrier_image(cmd, image, ImageState::UNDEFINED, ImageState::COLOR_ATTACHMENT);
        }
        if let Some(depth) = &self.depth {
            ctx.barrier_image(cmd, depth, ImageState::UNDEFINED, ImageState::DEPTH_ATTACHMENT);
        }
    }

    /// Orders this submission's attachment writes after the previous one's (rendering in bands).
    pub fn continue_rendering(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        for image in std::iter::once(&self.color).chain(&self.msaa) {
            ctx.barrier_image(cmd, image, ImageState::COLOR_ATTACHMENT, ImageState::COLOR_ATTACHMENT);
        }
    }

    /// Reads the colour image back as tightly packed rows, top row first (RGBA8 sRGB-encoded, or RGBA32F).
    pub fn read(&self, ctx: &Context) -> Result<Vec<u8>> {
        ctx.read_image(&self.color, ImageState::COLOR_ATTACHMENT)
    }

    /// # Safety
    /// The GPU must be done with the images.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.color.destroy(ctx);
        self.msaa.destroy(ctx);
        self.depth.destroy(ctx);
    }
}

/// Begins dynamic rendering into `target` within `area` (the whole target when `None`), clearing colour to
/// `clear` and depth to 1 there; the viewport covers the whole target. With `clear` None the colour is left as it
/// comes (undefined): the passes must draw every sample, as a background behind the objects does.
pub(crate) fn begin_rendering(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    target: &TargetView,
    clear: Option<[f32; 4]>,
    area: Option<vk::Rect2D>,
) {
    let mut color = vk::RenderingAttachmentInfo::default()
        .image_view(target.color)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(if clear.is_some() { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::DONT_CARE })
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: clear.unwrap_or_default() } });
    if let Some(resolve) = target.resolve {
        // The samples are averaged into the resolve image; they themselves need not be kept.
        color = color
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .resolve_mode(vk::ResolveModeFlags::AVERAGE)
            .resolve_image_view(resolve)
            .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
    }
    let color = [color];
    let depth = target.depth.map(|view| {
        vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: crate::scene::camera::FAR_DEPTH, stencil: 0 },
            })
    });
    let full = vk::Rect2D { offset: vk::Offset2D::default(), extent: target.extent };
    let area = area.unwrap_or(full);
    let mut info = vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&color);
    if let Some(depth) = &depth {
        info = info.depth_attachment(depth);
    }
    // SAFETY: cmd is recording and the target's images are in attachment layouts.
    unsafe { begin_rendering_info(ctx, cmd, &info, full.extent, area) };
}

/// Begins rendering `info` with a viewport over `extent` (depth 0–1) and the scissor `area`.
///
/// # Safety
/// `cmd` is recording and `info`'s attachments are in their attachment layouts.
pub(crate) unsafe fn begin_rendering_info(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    info: &vk::RenderingInfo<'_>,
    extent: vk::Extent2D,
    area: vk::Rect2D,
) {
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    ctx.device().cmd_begin_rendering(cmd, info);
    ctx.device().cmd_set_viewport(cmd, 0, &[viewport]);
    ctx.device().cmd_set_scissor(cmd, 0, &[area]);
}

pub(crate) fn end_rendering(ctx: &Context, cmd: vk::CommandBuffer) {
    // SAFETY: paired with begin_rendering.
    unsafe { ctx.device().cmd_end_rendering(cmd) };
}

/// Whether a scene's passes cull back faces: only where no mesh shows a back ([`Mesh::one_sided`]). Every pass
/// that draws the scene asks here, so that they all rasterise the same fragments (the shading pass's EQUAL depth
/// test needs its pre-pass's; the G-buffer's must be the frame's).
pub(crate) fn culls_back_faces<'a>(meshes: impl IntoIterator<Item = &'a Mesh>) -> bool {
    meshes.into_iter().all(|m| m.one_sided)
}

/// A mesh's vertex and index buffers on the GPU.
pub(crate) struct MeshBuffers {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub index_count: u32,
    pub vertex_count: u32,
}

impl MeshBuffers {
    pub fn new(ctx: &Context, mesh: &Mesh, name: &str) -> Result<Self> {
        if mesh.indices.is_empty() {
            return Err(Error::Invalid(format!("the mesh {name:?} has no triangles")));
        }
        let vertices = ctx.create_buffer_init(
            vk::BufferUsageFlags::VERTEX_BUFFER,
            bytemuck::cast_slice(&mesh.vertices),
            &format!("{name} vertices"),
        );
        let vertices = Guard::new(ctx, vertices?);
        // Also read as a storage buffer by the visibility buffer's shading pass.
        let indices = ctx.create_buffer_init(
            vk::BufferUsageFlags::INDEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            bytemuck::cast_slice(&mesh.indices),
            &format!("{name} indices"),
        )?;
        let (index_count, vertex_count) = (mesh.indices.len() as u32, mesh.vertices.len() as u32);
        Ok(Self { vertices: vertices.keep(), indices, index_count, vertex_count })
    }

    /// Binds the buffers and draws every triangle (a pipeline must be bound inside a rendering scope).
    pub fn draw(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        // SAFETY: cmd is recording inside a rendering scope with a pipeline of this vertex layout bound.
        unsafe {
            ctx.device().cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw], &[0]);
            ctx.device().cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
            ctx.device().cmd_draw_indexed(cmd, self.index_count, 1, 0, 0, 0);
        }
    }

    /// # Safety
    /// The GPU must be done with the buffers.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.vertices.destroy(ctx);
        self.indices.destroy(ctx);
    }
}

crate::impl_destroy!(OffscreenTarget, MeshBuffers);
