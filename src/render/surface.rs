//! The surface pass: meshes shaded by diffraction, offscreen (and, later, in a window).

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use super::diffraction::{patch_bindings, PatchResources};
use super::{begin_rendering, end_rendering, MeshBuffers, OffscreenTarget, TargetView, DEPTH_FORMAT, LINEAR_FORMAT};
use crate::camera::Camera;
use crate::error::Result;
use crate::mesh::{Mesh, Vertex};
use crate::shaders;
use crate::shading::Material;
use crate::vk::{
    Binding, Buffer, BufferDesc, Context, DescriptorWrite, GraphicsPipelineDesc, Pipeline, VertexAttribute,
};

/// Mirrors `SurfaceUniforms` in `glsl/include/surface_frame.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SurfaceUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 4],
    pub camera_pos: [f32; 4],
    pub light_dir: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<SurfaceUniforms>() == 224);

/// One object under a directional light, seen by a camera.
#[derive(Clone, Debug)]
pub struct SurfaceScene {
    pub mesh: Mesh,
    pub model: Mat4,
    pub camera: Camera,
    /// World-space unit vector towards the light.
    pub light_dir: Vec3,
    pub background: [f32; 4],
}

/// The vertex layout of [`Vertex`].
pub const VERTEX_ATTRIBUTES: [VertexAttribute; 4] = [
    VertexAttribute { location: 0, format: vk::Format::R32G32B32_SFLOAT, offset: 0 },
    VertexAttribute { location: 1, format: vk::Format::R32G32B32_SFLOAT, offset: 12 },
    VertexAttribute { location: 2, format: vk::Format::R32G32B32A32_SFLOAT, offset: 24 },
    VertexAttribute { location: 3, format: vk::Format::R32G32_SFLOAT, offset: 40 },
];

/// GPU state of the surface pass for one material and mesh.
pub struct SurfacePass {
    pipeline: Pipeline,
    patch: PatchResources,
    mesh: MeshBuffers,
    uniforms: Buffer,
}

impl SurfacePass {
    pub const NAME: &'static str = "surface";

    /// `display_output`: write exposure-scaled sRGB for an UNORM target instead of linear RGB.
    pub fn new(
        ctx: &Context,
        material: &Material,
        mesh: &Mesh,
        color_format: vk::Format,
        display_output: bool,
    ) -> Result<Self> {
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let [p, t, s] = patch_bindings(stages);
        let bindings = [Binding { binding: 0, kind: vk::DescriptorType::UNIFORM_BUFFER, stages }, p, t, s];
        let mesh = MeshBuffers::new(ctx, mesh, Self::NAME)?;
        let mut uniforms = None;
        let mut patch = None;
        let made = (|| {
            let size = std::mem::size_of::<SurfaceUniforms>() as u64;
            uniforms = Some(
                ctx.create_buffer(BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER), "surface uniforms")?,
            );
            patch = Some(PatchResources::new(ctx, material)?);
            ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                name: Self::NAME,
                vertex: shaders::SURFACE_VERT,
                fragment: shaders::SURFACE_FRAG,
                specialization: material.spec_constants(display_output),
                bindings: &bindings,
                push_constant_size: 0,
                vertex_stride: std::mem::size_of::<Vertex>() as u32,
                vertex_attributes: &VERTEX_ATTRIBUTES,
                color_format,
                depth_format: Some(DEPTH_FORMAT),
                cull_back_faces: false,
            })
        })();
        match made {
            // The uniforms and the patch are made before the pipeline.
            Ok(pipeline) => Ok(Self {
                pipeline,
                patch: patch.expect("made before the pipeline"),
                mesh,
                uniforms: uniforms.expect("made before the pipeline"),
            }),
            Err(e) => {
                // SAFETY: nothing was submitted with these.
                unsafe {
                    mesh.destroy(ctx);
                    if let Some(u) = uniforms {
                        u.destroy(ctx);
                    }
                    if let Some(p) = patch {
                        p.destroy(ctx);
                    }
                }
                Err(e)
            }
        }
    }

    /// Writes the frame's uniforms; no submitted work may still read them.
    pub fn update(&mut self, scene: &SurfaceScene, aspect: f32) -> Result<()> {
        let normal = Mat4::from_mat3(glam::Mat3::from_mat4(scene.model).inverse().transpose());
        let u = SurfaceUniforms {
            view_proj: scene.camera.view_projection(aspect).to_cols_array_2d(),
            model: scene.model.to_cols_array_2d(),
            normal_matrix: normal.to_cols_array_2d(),
            camera_pos: scene.camera.position.extend(1.0).to_array(),
            light_dir: scene.light_dir.normalize().extend(0.0).to_array(),
        };
        self.uniforms.write(bytemuck::bytes_of(&u))
    }

    /// Records the pass into `target` (in attachment layouts).
    pub fn record(&self, ctx: &Context, cmd: vk::CommandBuffer, target: &TargetView, background: [f32; 4]) {
        begin_rendering(ctx, cmd, target, background, None);
        let [p, t, s] = self.patch.writes();
        ctx.bind(cmd, &self.pipeline, &[DescriptorWrite::UniformBuffer(0, &self.uniforms), p, t, s], &[]);
        self.mesh.draw(ctx, cmd);
        end_rendering(ctx, cmd);
    }

    /// # Safety
    /// The GPU must be done with the pass.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.pipeline.destroy(ctx);
        self.patch.destroy(ctx);
        self.mesh.destroy(ctx);
        self.uniforms.destroy(ctx);
    }
}

/// A surface frame read back: linear RGBA float rows (top first), or display RGBA8 when asked.
pub struct SurfaceFrame {
    pub width: u32,
    pub height: u32,
    pub linear: Option<Vec<f32>>,
    pub rgba8: Option<Vec<u8>>,
    pub gpu_ms: Option<f64>,
}

/// Renders `scene` with `material` headless: linear float RGB, or (with `display_output`) 8-bit sRGB from the
/// shader's own exposure and transfer function.
pub fn render_surface(
    ctx: &Context,
    material: &Material,
    scene: &SurfaceScene,
    width: u32,
    height: u32,
    display_output: bool,
) -> Result<SurfaceFrame> {
    let format = if display_output { vk::Format::R8G8B8A8_UNORM } else { LINEAR_FORMAT };
    let mut pass = SurfacePass::new(ctx, material, &scene.mesh, format, display_output)?;
    let result = (|| {
        let target = OffscreenTarget::with_format(ctx, width, height, format, true)?;
        let frame = (|| {
            pass.update(scene, width as f32 / height as f32)?;
            let gpu_ms = ctx.one_shot_timed(SurfacePass::NAME, |cmd| {
                target.begin(ctx, cmd);
                pass.record(ctx, cmd, &target.view(), scene.background);
            })?;
            let bytes = target.read(ctx)?;
            let (linear, rgba8) =
                if display_output { (None, Some(bytes)) } else { (Some(bytemuck::pod_collect_to_vec(&bytes)), None) };
            Ok(SurfaceFrame { width, height, linear, rgba8, gpu_ms })
        })();
        // SAFETY: all work has completed.
        unsafe { target.destroy(ctx) };
        frame
    })();
    // SAFETY: all work has completed.
    unsafe { pass.destroy(ctx) };
    result
}
