//! The surface pass: meshes shaded by diffraction, offscreen (and, later, in a window).

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use super::diffraction::{patch_bindings, PatchResources};
use super::{begin_rendering, end_rendering, OffscreenTarget, TargetView, DEPTH_FORMAT, LINEAR_FORMAT};
use crate::camera::Camera;
use crate::error::{Error, Result};
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
    vertices: Buffer,
    indices: Buffer,
    uniforms: Buffer,
    index_count: u32,
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
        if mesh.indices.is_empty() {
            return Err(Error::Invalid("the mesh has no triangles".into()));
        }
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let [p, t, s] = patch_bindings(stages);
        let bindings = [Binding { binding: 0, kind: vk::DescriptorType::UNIFORM_BUFFER, stages }, p, t, s];
        let pipeline = ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
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
        })?;
        let patch = match PatchResources::new(ctx, material) {
            Ok(p) => p,
            Err(e) => {
                // SAFETY: unused.
                unsafe { pipeline.destroy(ctx) };
                return Err(e);
            }
        };
        let mut made: Vec<Buffer> = Vec::new();
        let buffers = (|| {
            made.push(ctx.create_buffer_init(
                vk::BufferUsageFlags::VERTEX_BUFFER,
                bytemuck::cast_slice(&mesh.vertices),
                "surface vertices",
            )?);
            made.push(ctx.create_buffer_init(
                vk::BufferUsageFlags::INDEX_BUFFER,
                bytemuck::cast_slice(&mesh.indices),
                "surface indices",
            )?);
            let size = std::mem::size_of::<SurfaceUniforms>() as u64;
            made.push(
                ctx.create_buffer(BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER), "surface uniforms")?,
            );
            Ok::<(), Error>(())
        })();
        if let Err(e) = buffers {
            // SAFETY: no pending work uses them.
            unsafe {
                for b in made {
                    b.destroy(ctx);
                }
                patch.destroy(ctx);
                pipeline.destroy(ctx);
            }
            return Err(e);
        }
        let uniforms = made.pop().expect("three buffers");
        let indices = made.pop().expect("three buffers");
        let vertices = made.pop().expect("three buffers");
        Ok(Self { pipeline, patch, vertices, indices, uniforms, index_count: mesh.indices.len() as u32 })
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
        // SAFETY: recording inside a rendering scope with the pipeline bound.
        unsafe {
            ctx.device().cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw], &[0]);
            ctx.device().cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
            ctx.device().cmd_draw_indexed(cmd, self.index_count, 1, 0, 0, 0);
        }
        end_rendering(ctx, cmd);
    }

    /// # Safety
    /// The GPU must be done with the pass.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.pipeline.destroy(ctx);
        self.patch.destroy(ctx);
        self.vertices.destroy(ctx);
        self.indices.destroy(ctx);
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
            let mut ring = ctx.create_timestamp_ring(1, 1, "surface timestamps")?;
            let mut scope_err = None;
            let submitted = ctx.one_shot("surface frame", |cmd| {
                target.begin(ctx, cmd);
                let scope = ring.as_mut().map(|r| {
                    r.begin_frame(ctx, cmd, 0);
                    r.begin_scope(ctx, cmd, SurfacePass::NAME)
                });
                pass.record(ctx, cmd, &target.view(), scene.background);
                match (ring.as_mut(), scope) {
                    (Some(r), Some(Ok(i))) => r.end_scope(ctx, cmd, i),
                    (_, Some(Err(e))) => scope_err = Some(e),
                    _ => {}
                }
            });
            let gpu_ms = match (&submitted, &ring) {
                (Ok(()), Some(r)) => r.read(ctx, 0).ok().and_then(|t| t.first().map(|s| s.ms)),
                _ => None,
            };
            if let Some(r) = ring {
                // SAFETY: one_shot waited.
                unsafe { r.destroy(ctx) };
            }
            submitted?;
            if let Some(e) = scope_err {
                return Err(e);
            }
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
