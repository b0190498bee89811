//! The preview pass: a mesh lit by one directional light, with an anisotropic streak along the tangent so
//! the patch orientation shows. It is the default scene until diffraction shading replaces it.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use super::{begin_rendering, end_rendering, OffscreenTarget, TargetView, COLOR_FORMAT, DEPTH_FORMAT};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::mesh::{Mesh, Vertex};
use crate::shaders;
use crate::vk::{
    Binding, Buffer, BufferDesc, Context, DescriptorWrite, GraphicsPipelineDesc, Pipeline, SpecConstants,
    VertexAttribute,
};

/// Mirrors `FrameUniforms` in `glsl/include/preview_frame.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub model: [[f32; 4]; 4],
    pub camera_pos: [f32; 4],
    pub light_dir: [f32; 4],
    pub base_color: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 176);

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
    /// The project's default scene for now: a sphere under a light from the upper right.
    pub fn default_scene() -> Self {
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
    vertices: Buffer,
    indices: Buffer,
    uniforms: Buffer,
    index_count: u32,
}

impl PreviewPass {
    pub const NAME: &'static str = "preview";

    pub fn new(ctx: &Context, mesh: &Mesh) -> Result<Self> {
        if mesh.indices.is_empty() {
            return Err(Error::Invalid("the mesh has no triangles".into()));
        }
        let attrs = [
            VertexAttribute { location: 0, format: vk::Format::R32G32B32_SFLOAT, offset: 0 },
            VertexAttribute { location: 1, format: vk::Format::R32G32B32_SFLOAT, offset: 12 },
            VertexAttribute { location: 2, format: vk::Format::R32G32B32A32_SFLOAT, offset: 24 },
            VertexAttribute { location: 3, format: vk::Format::R32G32_SFLOAT, offset: 40 },
        ];
        let bindings = [Binding {
            binding: 0,
            kind: vk::DescriptorType::UNIFORM_BUFFER,
            stages: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
        }];
        let pipeline = ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
            name: Self::NAME,
            vertex: shaders::PREVIEW_VERT,
            fragment: shaders::PREVIEW_FRAG,
            specialization: SpecConstants::default(),
            bindings: &bindings,
            push_constant_size: 0,
            vertex_stride: std::mem::size_of::<Vertex>() as u32,
            vertex_attributes: &attrs,
            color_format: COLOR_FORMAT,
            depth_format: Some(DEPTH_FORMAT),
            cull_back_faces: true,
        })?;
        let mut created: Vec<Buffer> = Vec::new();
        let buffers = (|| {
            created.push(ctx.create_buffer_init(
                vk::BufferUsageFlags::VERTEX_BUFFER,
                bytemuck::cast_slice(&mesh.vertices),
                "preview vertices",
            )?);
            created.push(ctx.create_buffer_init(
                vk::BufferUsageFlags::INDEX_BUFFER,
                bytemuck::cast_slice(&mesh.indices),
                "preview indices",
            )?);
            let size = std::mem::size_of::<FrameUniforms>() as u64;
            created.push(
                ctx.create_buffer(BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER), "preview uniforms")?,
            );
            Ok::<(), Error>(())
        })();
        if let Err(e) = buffers {
            // SAFETY: none of these were used by submitted work that is still pending.
            unsafe {
                for b in created {
                    b.destroy(ctx);
                }
                pipeline.destroy(ctx);
            }
            return Err(e);
        }
        let uniforms = created.pop().expect("three buffers");
        let indices = created.pop().expect("three buffers");
        let vertices = created.pop().expect("three buffers");
        Ok(Self { pipeline, vertices, indices, uniforms, index_count: mesh.indices.len() as u32 })
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
        begin_rendering(ctx, cmd, target, background, None);
        ctx.bind(cmd, &self.pipeline, &[DescriptorWrite::UniformBuffer(0, &self.uniforms)], &[]);
        // SAFETY: cmd is recording inside a rendering scope with this pipeline bound.
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
        self.vertices.destroy(ctx);
        self.indices.destroy(ctx);
        self.uniforms.destroy(ctx);
    }
}

/// A rendered frame read back to the CPU.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// RGBA8, sRGB-encoded, top row first.
    pub rgba8: Vec<u8>,
    /// GPU time of the pass from timestamp queries, where the device has them.
    pub gpu_ms: Option<f64>,
}

/// Renders `scene` headless at `width`×`height`.
pub fn render_offscreen(ctx: &Context, scene: &PreviewScene, width: u32, height: u32) -> Result<Frame> {
    let mut pass = PreviewPass::new(ctx, &scene.mesh)?;
    let result = (|| {
        let target = OffscreenTarget::new(ctx, width, height)?;
        let mut ring = match ctx.create_timestamp_ring(1, 1, "preview timestamps") {
            Ok(r) => r,
            Err(e) => {
                // SAFETY: unused.
                unsafe { target.destroy(ctx) };
                return Err(e);
            }
        };
        let frame = (|| {
            pass.update(scene, width as f32 / height as f32)?;
            let mut scope_error = None;
            ctx.one_shot("offscreen frame", |cmd| {
                target.begin(ctx, cmd);
                let scope = ring.as_mut().map(|r| {
                    r.begin_frame(ctx, cmd, 0);
                    r.begin_scope(ctx, cmd, PreviewPass::NAME)
                });
                pass.record(ctx, cmd, &target.view(), scene.background);
                match (ring.as_mut(), scope) {
                    (Some(r), Some(Ok(i))) => r.end_scope(ctx, cmd, i),
                    (_, Some(Err(e))) => scope_error = Some(e),
                    _ => {}
                }
            })?;
            if let Some(e) = scope_error {
                return Err(e);
            }
            let gpu_ms = match &ring {
                Some(r) => r.read(ctx, 0)?.first().map(|s| s.ms),
                None => None,
            };
            let rgba8 = target.read(ctx)?;
            Ok(Frame { width, height, rgba8, gpu_ms })
        })();
        // SAFETY: one_shot and read_rgba8 waited for all work.
        unsafe {
            if let Some(r) = ring {
                r.destroy(ctx);
            }
            target.destroy(ctx);
        }
        frame
    })();
    // SAFETY: all work using the pass has completed (or failed and been waited for).
    unsafe { pass.destroy(ctx) };
    result
}
