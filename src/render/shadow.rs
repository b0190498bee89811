//! The sun's shadow (model.md §3.9): a depth map drawn along the sun's rays, fitted each frame to what the camera
//! sees ([`ShadowFrame::of_objects`]: the receivers in view and the casters over them; the ground does not cast),
//! redrawn only when the sun, the placements or the casters change, and read by the surface pass and the G-buffer
//! (`sun_visibility` in glsl/include/shadow.glsl): a point pushed off its surface by [`NORMAL_OFFSET_TEXELS`]
//! texels, the casters' mean depth above it setting the penumbra of the sun's disc ([`sun_tan_radius`]), over which
//! the comparisons are averaged. A point the map does not cover is lit.

use std::cell::RefCell;

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::gpu::interface::Vertex;
use crate::gpu::interface::{BINDING_FRAME, BINDING_SHADOW, BINDING_SHADOW_DEPTH};
use crate::gpu::shaders;
use crate::gpu::vk::{
    Blend, Buffer, BufferDesc, Context, DepthTest, DescriptorWrite, GraphicsPipelineDesc, Guard, Image, ImageDesc,
    ImageState, Pipeline, Sampler,
};
use crate::render::MeshBuffers;

/// Texels along each edge of the shadow map (D32: 16 MiB).
pub const SHADOW_SIZE: u32 = 2048;
/// How far a point is pushed along its normal before it is looked up, in shadow-map texels (at normal
/// incidence; divided by cos θ_i up to [`MAX_OFFSET_GROWTH`] as the light grazes it).
pub const NORMAL_OFFSET_TEXELS: f32 = crate::gpu::interface::SHADOW_NORMAL_OFFSET_TEXELS as f32;
/// The largest factor the normal offset grows by at grazing light (surface.vert reads the same number).
pub const MAX_OFFSET_GROWTH: f32 = crate::gpu::interface::SHADOW_MAX_OFFSET_GROWTH as f32;
/// The pass's name (labels, timings).
pub const NAME: &str = "shadow map";

/// A world-space box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    /// The box of a mesh's vertices (None without any).
    pub fn of(vertices: &[Vertex]) -> Option<Self> {
        vertices.first()?;
        Some(Self::around(vertices.iter().map(|v| Vec3::from(v.position))))
    }

    /// The box around this one's corners moved by `model`.
    pub fn moved(&self, model: Mat4) -> Self {
        Self::around(self.corners().map(|c| model.transform_point3(c)))
    }

    pub(crate) fn around(points: impl IntoIterator<Item = Vec3>) -> Self {
        let mut it = points.into_iter();
        let first = it.next().unwrap_or(Vec3::ZERO);
        let (min, max) = it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        Self { min, max }
    }

    pub(crate) fn corners(&self) -> [Vec3; 8] {
        corners(self.min, self.max)
    }

    /// How far the point `p` is from the box (0 inside it).
    pub(crate) fn distance_to(&self, p: Vec3) -> f32 {
        (p.clamp(self.min, self.max) - p).length()
    }
}

fn corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// Where a frame's shadow map lies: the light's view-projection (world → the map's clip space, depth 0 at the
/// light's side) and the width of one of its texels in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowFrame {
    pub view_proj: Mat4,
    pub texel_world: f32,
    /// World units along the rays from depth 0 to depth 1 (far − near).
    pub depth_range: f32,
}

/// What the surface uniforms hold of the shadow map (`SurfaceUniforms::shadow_view_proj`, `shadow` and
/// `shadow_penumbra`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub lookup: [f32; 4],
    pub penumbra: [f32; 4],
}

/// The tangent of the sun's angular radius (its disc of `SUN_SOLID_ANGLE`: α = √(Ω/π), 0.2666°).
pub fn sun_tan_radius() -> f64 {
    (crate::physics::optics::SUN_SOLID_ANGLE / std::f64::consts::PI).sqrt().tan()
}

impl ShadowFrame {
    /// The map for a sun towards `light_dir` (world, unit) fitted across its rays to `casters` (with a margin of
    /// two texels for the filter) and along them from the nearest caster to the farthest of `receivers` (which
    /// should include the casters); None without casters.
    pub fn fit(light_dir: Vec3, casters: &[Aabb], receivers: &[Aabb], size: u32) -> Option<Self> {
        let dir = light_dir.try_normalize()?;
        let up = if dir.y.abs() < 0.99 { Vec3::Y } else { Vec3::Z };
        // Looking from the light down its rays, from the origin (the box is found in this view's coordinates).
        let view = crate::scene::camera::look_at(Vec3::ZERO, -dir, up);
        let in_view = |boxes: &[Aabb]| -> Vec<Aabb> {
            boxes.iter().map(|b| Aabb::around(b.corners().map(|c| view.transform_point3(c)))).collect()
        };
        Self::fit_across(view, &in_view(casters), &in_view(receivers), size)
    }

    /// [`Self::fit`] of boxes already in the light's `view` (looking down −z along the rays).
    fn fit_across(view: Mat4, casters: &[Aabb], receivers: &[Aabb], size: u32) -> Option<Self> {
        let around = |boxes: &[Aabb]| Aabb::around(boxes.iter().flat_map(|b| b.corners()));
        if casters.is_empty() {
            return None;
        }
        let cast = around(casters);
        let all = around(receivers).union(&cast);
        // Square texels: the wider side sets the size; two texels of margin each side for the 3×3 filter.
        let side = (cast.max.x - cast.min.x).max(cast.max.y - cast.min.y).max(1e-6);
        let texel = side / (size as f32 - 4.0).max(1.0);
        let half = 0.5 * side + 2.0 * texel;
        let centre = 0.5 * (cast.min + cast.max);
        // The view looks down −z: the nearest caster has the largest z; the far plane lies past every receiver.
        let depth = (all.max.z - all.min.z).max(1e-6);
        let (near, far) = (-cast.max.z - 0.01 * depth, -all.min.z + 0.01 * depth);
        let proj = orthographic(centre.x - half, centre.x + half, centre.y - half, centre.y + half, near, far);
        Some(Self { view_proj: proj * view, texel_world: 2.0 * half / size as f32, depth_range: far - near })
    }

    /// The map for objects placed in `boxes` (world; whether each casts) seen through `view_proj` (the camera's
    /// view-projection), or None where nothing casts onto what the camera sees. Only the part of the scene the
    /// camera can see receives a shadow that shows, so the map covers, across the sun's rays, the receivers
    /// within the view's box and the casters over them: an object far outside the view (a cube a million units
    /// away) cannot take the map's resolution from the shadows in it.
    pub fn of_objects(light_dir: Vec3, boxes: &[(Aabb, bool)], view_proj: Mat4) -> Option<Self> {
        let seen = seen_box(boxes, view_proj)?;
        let dir = light_dir.try_normalize()?;
        let up = if dir.y.abs() < 0.99 { Vec3::Y } else { Vec3::Z };
        let light_view = crate::scene::camera::look_at(Vec3::ZERO, -dir, up);
        let across = |b: &Aabb| Aabb::around(b.corners().map(|c| light_view.transform_point3(c)));
        let region = across(&seen);
        // The casters whose shadow can fall on the seen receivers (their boxes overlap across the rays), each cut
        // to that region across the rays (a long caster only needs its part over what is seen).
        let casters: Vec<Aabb> = boxes
            .iter()
            .filter(|b| b.1)
            .filter_map(|b| {
                let c = across(&b.0);
                let cut = Aabb {
                    min: c.min.max(Vec3::new(region.min.x, region.min.y, c.min.z)),
                    max: c.max.min(Vec3::new(region.max.x, region.max.y, c.max.z)),
                };
                (cut.min.x <= cut.max.x && cut.min.y <= cut.max.y).then_some(cut)
            })
            .collect();
        let frame = Self::fit_across(light_view, &casters, &[region], SHADOW_SIZE)?;
        // A caster a few texels wide casts a shadow the map cannot draw: said once a process.
        let smallest = casters.iter().map(|c| (c.max.x - c.min.x).max(c.max.y - c.min.y)).fold(f32::INFINITY, f32::min);
        static SAID: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
        if smallest < 8.0 * frame.texel_world && !SAID.swap(true, std::sync::atomic::Ordering::Relaxed) {
            log::warn!(
                "the sun's shadows are coarse here: a texel of the shadow map is {:.3e} world units across, more than \
                 an eighth of the smallest object in view that casts one ({smallest:.3e}); a camera whose far plane \
                 stops nearer sharpens them",
                frame.texel_world
            );
        }
        Some(frame)
    }

    /// The surface uniforms' share: the view-projection; on, the normal offset in world units, the map's texel in
    /// texture coordinates; the penumbra's scales.
    pub fn uniforms(frame: Option<&Self>, size: u32) -> ShadowUniforms {
        match frame {
            Some(f) => ShadowUniforms {
                view_proj: f.view_proj.to_cols_array_2d(),
                lookup: [1.0, NORMAL_OFFSET_TEXELS * f.texel_world, 1.0 / size as f32, 0.0],
                penumbra: [f.texel_world, f.depth_range, sun_tan_radius() as f32, 0.0],
            },
            None => {
                ShadowUniforms { view_proj: Mat4::IDENTITY.to_cols_array_2d(), lookup: [0.0; 4], penumbra: [0.0; 4] }
            }
        }
    }
}

/// Orthographic projection of the view box x ∈ [l, r], y ∈ [b, t], z ∈ [−far, −near] (looking down −z) to
/// Vulkan's clip space: x, y to [−1, 1], depth 0 at the near plane and 1 at the far one.
fn orthographic(l: f32, r: f32, b: f32, t: f32, near: f32, far: f32) -> Mat4 {
    Mat4::from_cols(
        glam::Vec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, 2.0 / (t - b), 0.0, 0.0),
        glam::Vec4::new(0.0, 0.0, -1.0 / (far - near), 0.0),
        glam::Vec4::new(-(r + l) / (r - l), -(t + b) / (t - b), -near / (far - near), 1.0),
    )
}

impl Aabb {
    pub(crate) fn union(&self, other: &Self) -> Self {
        Self { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// The common part of two boxes, None where they do not meet.
    pub(crate) fn intersection(&self, other: &Self) -> Option<Self> {
        let b = Self { min: self.min.max(other.min), max: self.max.min(other.max) };
        (b.min.cmple(b.max).all()).then_some(b)
    }
}

/// What the camera of `view_proj` sees of `boxes` (placed objects, whether each casts): the box around them cut to
/// the box around the view frustum; None where they do not meet (or the view-projection is not invertible). The
/// sun's and the lamps' shadow maps are fitted to it.
pub(crate) fn seen_box(boxes: &[(Aabb, bool)], view_proj: Mat4) -> Option<Aabb> {
    Aabb::around(boxes.iter().flat_map(|b| b.0.corners())).intersection(&frustum_box(view_proj)?)
}

/// The world box around the view frustum of `view_proj` (Vulkan clip space: depth 0 to 1), None where it is not
/// invertible.
fn frustum_box(view_proj: Mat4) -> Option<Aabb> {
    let inverse = view_proj.inverse();
    let points = corners(Vec3::new(-1.0, -1.0, 0.0), Vec3::ONE).map(|c| inverse.project_point3(c));
    points.iter().all(|p| p.is_finite()).then(|| Aabb::around(points))
}

/// The pipeline that draws casters' depths into a shadow map (surface.vert alone, the map's view-projection in
/// the object's uniforms; both faces, since a caster's back faces cast too).
fn depth_pipeline(ctx: &Context, name: &str) -> Result<Pipeline> {
    ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
        name,
        vertex: &shaders::SURFACE_VERT,
        fragment: None,
        specialization: crate::gpu::vk::SpecConstants::default(),
        push_constant_size: 0,
        vertex_stride: std::mem::size_of::<Vertex>() as u32,
        vertex_attributes: &crate::gpu::shaders::VERTEX_ATTRIBUTES,
        color_format: vk::Format::UNDEFINED,
        depth: Some((crate::render::DEPTH_FORMAT, DepthTest::WriteLess)),
        cull_back_faces: false,
        samples: vk::SampleCountFlags::TYPE_1,
        blend: Blend::Replace,
    })
}

/// A shadow map's GPU objects (the sun's, the lamps' atlas): a depth image, its comparison and depth samplers and
/// the depth-only pipeline that draws the casters into it.
pub(crate) struct DepthMap {
    pub image: Image,
    sampler: Sampler,
    /// Reads its depths (the blocker search).
    depths: Sampler,
    pipeline: Pipeline,
}

impl DepthMap {
    /// A `width`×`height` map named `name`.
    pub fn new(ctx: &Context, width: u32, height: u32, name: &str) -> Result<Self> {
        let image = Guard::new(ctx, ctx.create_image(ImageDesc::sampled_depth(width, height), name)?);
        let sampler = Guard::new(ctx, ctx.create_shadow_sampler(name, true)?);
        let depths = Guard::new(ctx, ctx.create_shadow_sampler(name, false)?);
        let pipeline = depth_pipeline(ctx, name)?;
        Ok(Self { image: image.keep(), sampler: sampler.keep(), depths: depths.keep(), pipeline })
    }

    /// Begins drawing it, cleared (labelled `name`; its viewport the whole image).
    pub fn begin(&self, ctx: &Context, cmd: vk::CommandBuffer, name: &str) {
        ctx.begin_label(cmd, name);
        ctx.barrier_image(cmd, &self.image, ImageState::UNDEFINED, ImageState::DEPTH_ATTACHMENT);
        let extent = self.image.extent();
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(self.image.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } });
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        let info = vk::RenderingInfo::default().render_area(area).layer_count(1).depth_attachment(&depth);
        // SAFETY: cmd is recording; the image is in the depth-attachment layout.
        unsafe { crate::render::begin_rendering_info(ctx, cmd, &info, extent, area) };
    }

    /// Draws the `meshes` that cast (each with its `uniforms`, the light's view-projection in them).
    pub fn draw_casters(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        meshes: &[(&MeshBuffers, bool)],
        uniforms: &[Buffer],
    ) {
        for ((mesh, casts), uniforms) in meshes.iter().zip(uniforms) {
            if *casts {
                ctx.bind(cmd, &self.pipeline, &[DescriptorWrite::UniformBuffer(BINDING_FRAME, uniforms)], &[]);
                mesh.draw(ctx, cmd);
            }
        }
    }

    /// Ends the drawing begun by [`Self::begin`] and leaves the map ready for the shaders to sample.
    pub fn end(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        crate::render::end_rendering(ctx, cmd);
        ctx.barrier_image(cmd, &self.image, ImageState::DEPTH_ATTACHMENT, ImageState::SHADER_READ);
        ctx.end_label(cmd);
    }

    /// The descriptors that bind it for reading: by comparison at `compare`, as depths at `depths`.
    pub fn writes(&self, compare: u32, depths: u32) -> [DescriptorWrite<'_>; 2] {
        [
            DescriptorWrite::SampledImage(compare, &self.image, &self.sampler),
            DescriptorWrite::SampledImage(depths, &self.image, &self.depths),
        ]
    }

    /// # Safety
    /// The GPU must be done with it.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.image.destroy(ctx);
        self.sampler.destroy(ctx);
        self.depths.destroy(ctx);
        self.pipeline.destroy(ctx);
    }
}

/// The shadow map's GPU objects: its depth image (a 1×1 one while no shadow is cast, so the surface pipelines
/// always have something bound), the comparison sampler, the depth-only pipeline and one uniform buffer per
/// object (the surface uniforms with the light's view-projection).
pub struct ShadowMap {
    map: DepthMap,
    uniforms: Vec<Buffer>,
    /// This frame's placement; None: nothing is drawn and every surface is lit.
    frame: Option<ShadowFrame>,
    /// This frame's objects' model matrices ([`Self::update`]).
    models: Vec<[[f32; 4]; 4]>,
    /// What the map holds, as last recorded (None: nothing yet).
    drawn: RefCell<Option<Drawn>>,
}

/// What a shadow map's depths depend on: its placement, the objects' model matrices and which of them cast. The
/// camera is not among them, so a view that only moves the camera keeps the map ([`ShadowMap::record`]).
#[derive(Clone, Debug, PartialEq)]
struct Drawn {
    frame: Option<ShadowFrame>,
    models: Vec<[[f32; 4]; 4]>,
    casts: Vec<bool>,
}

impl ShadowMap {
    /// A map for `objects` objects, `size` texels square (1 while there is no shadow to draw).
    pub fn new(ctx: &Context, objects: usize, size: u32) -> Result<Self> {
        let map = Guard::new(ctx, DepthMap::new(ctx, size, size, NAME)?);
        let mut uniforms = Guard::new(ctx, Vec::with_capacity(objects));
        for i in 0..objects {
            let size = std::mem::size_of::<crate::gpu::interface::SurfaceUniforms>() as u64;
            let desc = BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER);
            uniforms.push(ctx.create_buffer(desc, &format!("object {i} uniforms (shadow map)"))?);
        }
        Ok(Self {
            map: map.keep(),
            uniforms: uniforms.keep(),
            frame: None,
            models: Vec::new(),
            drawn: RefCell::new(None),
        })
    }

    /// Texels along an edge.
    pub fn size(&self) -> u32 {
        self.map.image.extent().width
    }

    /// This frame's placement (None: no shadow).
    pub fn frame(&self) -> Option<&ShadowFrame> {
        self.frame.as_ref()
    }

    /// Places the map for this frame and writes each object's uniforms for the shadow pass (`objects`: the
    /// surface pass's, whose view-projection is replaced by the light's); no submitted work may still read them.
    pub fn update(
        &mut self,
        frame: Option<ShadowFrame>,
        objects: &[crate::gpu::interface::SurfaceUniforms],
    ) -> Result<()> {
        self.frame = frame;
        self.models = objects.iter().map(|u| u.model).collect();
        if let Some(f) = frame {
            for (buffer, u) in self.uniforms.iter_mut().zip(objects) {
                let u = crate::gpu::interface::SurfaceUniforms { view_proj: f.view_proj.to_cols_array_2d(), ..*u };
                buffer.write(bytemuck::bytes_of(&u))?;
            }
        }
        Ok(())
    }

    /// Records the map (cleared; `meshes` that cast, drawn from the light when there is a frame) and leaves it
    /// ready for the fragment shaders to sample, unless it already holds that: the same placement, model matrices
    /// and casters as when last recorded. The recorded work must then be submitted, before any work that samples
    /// the map in a later frame (on the same queue: the layout change at its end orders the reads after it).
    /// Redrawing the map every frame cost ~10 % of the ground scene's 800² frame on lavapipe.
    pub(crate) fn record<'a>(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        meshes: impl Iterator<Item = (&'a MeshBuffers, bool)>,
    ) {
        let meshes: Vec<(&MeshBuffers, bool)> = meshes.collect();
        let now = Drawn { frame: self.frame, models: self.models.clone(), casts: meshes.iter().map(|m| m.1).collect() };
        if self.drawn.borrow().as_ref() == Some(&now) {
            return;
        }
        self.map.begin(ctx, cmd, NAME);
        if self.frame.is_some() {
            self.map.draw_casters(ctx, cmd, &meshes, &self.uniforms);
        }
        self.map.end(ctx, cmd);
        *self.drawn.borrow_mut() = Some(now);
    }

    /// The descriptors that bind it for reading (`BINDING_SHADOW` by comparison, `BINDING_SHADOW_DEPTH` as depths).
    pub fn writes(&self) -> [DescriptorWrite<'_>; 2] {
        self.map.writes(BINDING_SHADOW, BINDING_SHADOW_DEPTH)
    }

    /// # Safety
    /// The GPU must be done with it.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.map.destroy(ctx);
        self.uniforms.into_iter().for_each(|b| b.destroy(ctx));
    }
}

crate::impl_destroy!(DepthMap, ShadowMap);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_holds_the_casters_and_reaches_past_the_receivers() {
        let ball = Aabb { min: Vec3::new(-1.0, 0.5, -1.0), max: Vec3::new(1.0, 2.5, 1.0) };
        let ground = Aabb { min: Vec3::new(-50.0, 0.0, -50.0), max: Vec3::new(50.0, 0.0, 50.0) };
        let light = Vec3::new(0.3, 1.0, 0.2).normalize();
        let f = ShadowFrame::fit(light, &[ball], &[ball, ground], 256).unwrap();
        let clip = |p: Vec3| f.view_proj.project_point3(p);
        for c in ball.corners() {
            let q = clip(c);
            assert!(q.x.abs() < 1.0 && q.y.abs() < 1.0 && (0.0..=1.0).contains(&q.z), "{c} → {q}");
        }
        // The ground under the ball lies deeper than the ball, within the depth range.
        let (top, below) = (clip(Vec3::new(0.0, 2.5, 0.0)), clip(Vec3::ZERO));
        assert!(top.z < below.z && below.z <= 1.0, "{top} {below}");
        // Texels square and about side/size wide: the ball's box across the rays is under 4 units.
        assert!(f.texel_world > 0.0 && f.texel_world < 4.0 / 250.0, "{}", f.texel_world);
        assert!(ShadowFrame::fit(light, &[], &[ground], 256).is_none());
    }
}
