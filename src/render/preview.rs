//! The preview pass: a mesh lit by one directional light, with an anisotropic streak along the tangent so
//! the patch orientation shows, without diffraction (`diffract render --preview`: a scene's geometry, tangent
//! frames and pigment at a glance).

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::gpu::interface::FrameUniforms;
use crate::gpu::interface::Vertex;
use crate::gpu::interface::BINDING_FRAME;
use crate::gpu::shaders;
use crate::gpu::shaders::VERTEX_ATTRIBUTES;
use crate::gpu::vk::VertexAttribute;
use crate::gpu::vk::{
    Blend, Buffer, BufferDesc, Context, DepthTest, DescriptorWrite, GraphicsPipelineDesc, Guard, Pipeline,
    SpecConstants,
};
use crate::render::{
    begin_rendering, end_rendering, Frame, MeshBuffers, OffscreenTarget, Pixels, TargetView, COLOR_FORMAT, DEPTH_FORMAT,
};
use crate::scene::camera::Camera;
use crate::scene::mesh::Mesh;

/// The vertex inputs preview.vert reads: all but the UVs, the last (it draws no maps). A release build's SPIR-V
/// optimiser strips an input the shader does not read, and the validation layer then warns of an attribute that no
/// shader consumes (scripts/check-release.sh saw it).
const PREVIEW_ATTRIBUTES: [VertexAttribute; 4] =
    [VERTEX_ATTRIBUTES[0], VERTEX_ATTRIBUTES[1], VERTEX_ATTRIBUTES[2], VERTEX_ATTRIBUTES[3]];
// The one it leaves out is the UVs.
const _: () =
    assert!(VERTEX_ATTRIBUTES.len() == 5 && VERTEX_ATTRIBUTES[4].offset == std::mem::offset_of!(Vertex, uv) as u32);

/// What the preview draws.
#[derive(Clone, Debug)]
pub struct PreviewScene {
    pub mesh: Mesh,
    pub model: Mat4,
    pub camera: Camera,
    /// Unit vector towards the light, world space.
    pub light_dir: Vec3,
    pub base_color: Vec3,
    pub background: [f32; 4],
}

impl PreviewScene {
    /// A sphere under a light from the upper right: the pass's test scene (its golden image).
    pub fn lit_sphere() -> Self {
        Self {
            mesh: Mesh::uv_sphere(1.0, 64, 32),
            model: Mat4::IDENTITY,
            camera: Camera {
                position: Vec3::new(0.0, 0.6, 3.6),
                target: Vec3::ZERO,
                up: Vec3::Y,
                fov_y_deg: 40.0,
                near: 0.05,
                far: 100.0,
            },
            light_dir: Vec3::new(0.5, 0.8, 0.6).normalize(),
            base_color: Vec3::new(0.18, 0.32, 0.25),
            background: [0.02, 0.02, 0.025, 1.0],
        }
    }
}

/// GPU state of the preview pass.
pub struct PreviewPass {
    pipeline: Pipeline,
    mesh: MeshBuffers,
    uniforms: Buffer,
}

impl PreviewPass {
    pub const NAME: &'static str = "preview";

    /// The pass for targets of `samples` per pixel.
    pub fn new(ctx: &Context, mesh: &Mesh, samples: vk::SampleCountFlags) -> Result<Self> {
        let mesh = Guard::new(ctx, MeshBuffers::new(ctx, mesh, Self::NAME)?);
        let size = std::mem::size_of::<FrameUniforms>() as u64;
        let uniforms = Guard::new(
            ctx,
            ctx.create_buffer(BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER), "preview uniforms")?,
        );
        let pipeline = ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
            name: Self::NAME,
            vertex: &shaders::PREVIEW_VERT,
            fragment: Some(&shaders::PREVIEW_FRAG),
            specialization: SpecConstants::default(),
            push_constant_size: 0,
            vertex_stride: std::mem::size_of::<Vertex>() as u32,
            vertex_attributes: &PREVIEW_ATTRIBUTES,
            color_format: COLOR_FORMAT,
            depth: Some((DEPTH_FORMAT, DepthTest::Write)),
            cull_back_faces: true,
            samples,
            blend: Blend::Replace,
        })?;
        Ok(Self { pipeline, mesh: mesh.keep(), uniforms: uniforms.keep() })
    }

    /// Writes the frame's uniforms; the previous frame using them must have completed.
    pub fn update(&mut self, scene: &PreviewScene, aspect: f32) -> Result<()> {
        let u = FrameUniforms {
            view_proj: scene.camera.view_projection(aspect).to_cols_array_2d(),
            model: scene.model.to_cols_array_2d(),
            camera_pos: scene.camera.position.extend(1.0).to_array(),
            light_dir: scene.light_dir.normalize().extend(0.0).to_array(),
            base_color: scene.base_color.extend(1.0).to_array(),
        };
        self.uniforms.write(bytemuck::bytes_of(&u))
    }

    /// Records the pass into `target`, which must be in attachment layouts.
    pub fn record(&self, ctx: &Context, cmd: vk::CommandBuffer, target: &TargetView, background: [f32; 4]) {
        begin_rendering(ctx, cmd, target, Some(background), None);
        ctx.bind(cmd, &self.pipeline, &[DescriptorWrite::UniformBuffer(BINDING_FRAME, &self.uniforms)], &[]);
        self.mesh.draw(ctx, cmd);
        end_rendering(ctx, cmd);
    }

    /// # Safety
    /// The GPU must be done with the pass.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.pipeline.destroy(ctx);
        self.mesh.destroy(ctx);
        self.uniforms.destroy(ctx);
    }
}

/// Renders `scene` headless at `width`×`height`, `samples` per pixel.
pub fn render_offscreen(
    ctx: &Context,
    scene: &PreviewScene,
    width: u32,
    height: u32,
    samples: vk::SampleCountFlags,
) -> Result<Frame> {
    let mut pass = Guard::new(ctx, PreviewPass::new(ctx, &scene.mesh, samples)?);
    let target = Guard::new(ctx, OffscreenTarget::multisampled(ctx, width, height, COLOR_FORMAT, true, samples)?);
    pass.update(scene, width as f32 / height as f32)?;
    let times = ctx.one_shot_laps(PreviewPass::NAME, |cmd, laps| {
        target.begin(ctx, cmd);
        pass.record(ctx, cmd, &target.view(), scene.background);
        laps.lap(cmd, crate::render::pass::SHADING);
    })?;
    let pixels = Pixels::Rgba8(target.read(ctx)?);
    Ok(Frame { width, height, pixels, times })
}

crate::impl_destroy!(PreviewPass);
