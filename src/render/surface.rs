//! The surface pass: meshes shaded by diffraction, offscreen and in a window.
//!
//! A [`SceneRenderer`] holds one pipeline and one set of patch resources per material (uploaded once, shared
//! by every object that uses it) and a vertex/index/uniform set per object. A frame draws every object twice: a
//! depth pre-pass (vertex shader only), then the shading pass with an EQUAL depth test, so that overlapping
//! surfaces (a snake's scales lie four deep) are shaded once per pixel, not once per layer. Where every mesh
//! draws its triangles front first ([`Mesh::front_first`]: the snake's scales top row first, flat and convex
//! shapes) the pre-pass is left out: the shading pass tests LESS and writes depth, and the hidden fragments fail
//! that test before they are shaded (what that saves: docs/performance.md).

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::gpu::interface::SurfaceUniforms;
use crate::gpu::interface::Vertex;
use crate::gpu::interface::{
    VisibilityPush, BINDING_FETCH_COUNTS, BINDING_FRAME, BINDING_MESH_INDICES, BINDING_VERTEX_OUTPUTS,
    BINDING_VISIBILITY_EDGES, BINDING_VISIBILITY_IDS, BINDING_VISIBILITY_TARGET, SKY_DIFFRACTION_NONE,
    SKY_DIFFRACTION_VERTEX, SPEC_SHADOWS, SPEC_SKY_DIFFRACTION,
};
use crate::gpu::shaders;
use crate::gpu::shaders::VERTEX_ATTRIBUTES;
use crate::gpu::vk::{
    Blend, Buffer, BufferDesc, ComputePipelineDesc, Context, DepthTest, DescriptorWrite, GraphicsPipelineDesc, Guard,
    Image, ImageState, Laps, MemoryState, Pipeline, Sampler, Shader, Statistics,
};
use crate::material::Material;
use crate::render::background::BackgroundPass;
use crate::render::diffraction::{counting_constants, PatchResources};
use crate::render::shadow::{Aabb, ShadowFrame, ShadowMap, ShadowUniforms, SHADOW_SIZE};
use crate::render::visibility;
use crate::render::visibility::{ShadingPath, VisibilityState, VERTEX_STORAGE_WRITE};
use crate::render::{
    begin_rendering, end_rendering, pass, Frame, MeshBuffers, OffscreenTarget, Pixels, SceneView, TargetView,
    DEPTH_FORMAT, LINEAR_FORMAT,
};
use crate::scene::camera::Camera;
use crate::scene::mesh::Mesh;

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

/// What every object of a frame shares: the camera (and the target's aspect), the light, the sky.
#[derive(Clone, Copy, Debug)]
pub struct ObjectView<'a> {
    pub camera: &'a Camera,
    pub aspect: f32,
    /// World-space unit vector towards the light.
    pub light_dir: Vec3,
    /// 1, or 0 where no sun lights the scene (`Scene::sun_strength`).
    pub sun: f32,
    pub ambient: f32,
    /// The environment's irradiance (`SurfaceUniforms::sky_sh`).
    pub sky_sh: [[f32; 4]; 9],
    /// Its radiance to l = 2 (`SurfaceUniforms::sky_quadratic`, `w` of the first 0): zero without an environment.
    pub sky_quadratic: [[f32; 4]; 10],
    /// Where the sun's shadow map lies (`SurfaceUniforms::shadow_view_proj` and `shadow`).
    pub shadow: ShadowUniforms,
}

impl SurfaceUniforms {
    /// One object's uniforms: its model matrix, its material's orientation (cos, sin) and pigment, the
    /// material's index (`orientation.z`, which the G-buffer writes) and whether it is matte.
    pub fn new(view: &ObjectView<'_>, model: Mat4, material: &SurfaceMaterial, index: usize) -> Self {
        let SurfaceMaterial { orientation, pigment, matte } = *material;
        let normal = Mat4::from_mat3(glam::Mat3::from_mat4(model).inverse().transpose());
        let [cos, sin] = orientation;
        let [r, g, b] = pigment;
        Self {
            view_proj: view.camera.view_projection(view.aspect).to_cols_array_2d(),
            model: model.to_cols_array_2d(),
            normal_matrix: normal.to_cols_array_2d(),
            camera_pos: view.camera.position.extend(1.0).to_array(),
            light_dir: view.light_dir.normalize().extend(view.sun).to_array(),
            orientation: [cos, sin, index as f32, if matte { 1.0 } else { 0.0 }],
            pigment: [r, g, b, view.ambient],
            sky_sh: view.sky_sh,
            shadow_view_proj: view.shadow.view_proj,
            shadow: view.shadow.lookup,
            shadow_penumbra: view.shadow.penumbra,
            sky_quadratic: view.sky_quadratic,
        }
    }
}

/// How a material lies on its objects: the patch's rotation (cos, sin) about the normal, the pigment's linear
/// RGB albedo (0: none, only diffraction), and whether it is matte (pigment only).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceMaterial {
    pub orientation: [f32; 2],
    pub pigment: [f32; 3],
    pub matte: bool,
}

impl SurfaceMaterial {
    /// A scene material's.
    pub fn of(m: &crate::scene::SceneMaterial) -> Self {
        Self { orientation: orientation(m.orientation_deg), pigment: m.pigment, matte: m.matte }
    }
}

/// cos and sin of a patch's rotation about the normal.
pub fn orientation(degrees: f32) -> [f32; 2] {
    let (sin, cos) = degrees.to_radians().sin_cos();
    [cos, sin]
}

/// What the renderer draws: a material (prepared patch) and how it lies on its objects (its orientation on the
/// surface, the pigment under it, whether it is matte: then its diffraction is not drawn).
pub struct MaterialInput<'a> {
    pub material: &'a Material,
    pub surface: SurfaceMaterial,
}

struct MaterialGpu {
    /// The shading pipeline for a view without shadows ([0]) and with ([1]), each built the first time a view
    /// needs it (`SPEC_SHADOWS`).
    pipelines: [Option<Pipeline>; 2],
    /// What those pipelines are built from: the vertex and fragment shaders and the specialization constants
    /// (all but `SPEC_SHADOWS`).
    recipe: (&'static Shader, &'static Shader, crate::gpu::vk::SpecConstants),
    /// The visibility buffer's pipelines, as `pipelines` (built where the renderer takes that path), and their
    /// shaders: the raster pass's vertex shader, the shading pass's fragment shaders (one sample, several) and
    /// the edge pass's compute shader.
    visibility_pipelines: [Option<VisibilityPipelines>; 2],
    visibility_recipe: (&'static Shader, [&'static Shader; 2], &'static Shader),
    patch: PatchResources,
    params: crate::gpu::interface::DiffractionParams,
    surface: SurfaceMaterial,
}

/// A material's pipelines for the visibility buffer's passes (`render::visibility`): the raster pass, the shading
/// pass and, where the frame has several samples, the edge pass.
struct VisibilityPipelines {
    raster: Pipeline,
    shade: Pipeline,
    edges: Option<Pipeline>,
}

impl VisibilityPipelines {
    /// # Safety
    /// No pending work may use them.
    unsafe fn destroy(self, ctx: &Context) {
        self.raster.destroy(ctx);
        self.shade.destroy(ctx);
        if let Some(edges) = self.edges {
            edges.destroy(ctx);
        }
    }
}

struct ObjectGpu {
    mesh: MeshBuffers,
    uniforms: Buffer,
    material: usize,
    /// The mesh's own box (object space), which the shadow map is fitted to once placed.
    bounds: Option<Aabb>,
}

/// Which build of the surface shader a renderer uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceVariant {
    /// The colour (linear, or display-encoded).
    Shade { display_output: bool },
    /// Linear colour, and each fragment's texel fetches and shading added to per-pixel counters (row stride
    /// given).
    CountFetches { stride: u32 },
}

/// The width of the clear sky's map (without its sun) the surface pass reflects: 1.4° texels (the sky is smooth).
pub const LIGHTING_SKY_WIDTH: u32 = 256;

/// The environment the surface pass reflects at each pixel's mirror direction (`BINDING_ENV_LIGHT`).
struct EnvLighting {
    panorama: crate::render::background::Panorama,
    sampler: Sampler,
    /// One black texel, bound until a view has an environment.
    fallback: Image,
}

impl EnvLighting {
    fn new(ctx: &Context) -> Result<Self> {
        let sampler = Guard::new(ctx, ctx.create_panorama_sampler("environment lighting")?);
        let black = crate::light::environment::EnvironmentMap { width: 1, height: 1, rgb: vec![[0.0; 3]] };
        let fallback = crate::render::background::upload(ctx, &black)?;
        let panorama = crate::render::background::Panorama::new(false, LIGHTING_SKY_WIDTH);
        Ok(Self { panorama, sampler: sampler.keep(), fallback })
    }

    fn write(&self) -> DescriptorWrite<'_> {
        let image = self.panorama.image().unwrap_or(&self.fallback);
        DescriptorWrite::SampledImage(crate::gpu::interface::BINDING_ENV_LIGHT, image, &self.sampler)
    }

    /// # Safety
    /// The GPU must be done with it.
    unsafe fn destroy(self, ctx: &Context) {
        self.panorama.destroy(ctx);
        self.sampler.destroy(ctx);
        self.fallback.destroy(ctx);
    }
}

/// GPU state for drawing a set of objects with their materials.
pub struct SceneRenderer {
    materials: Vec<MaterialGpu>,
    objects: Vec<ObjectGpu>,
    /// The depth pre-pass's pipeline; None where every mesh is drawn front first (the shading pass then writes
    /// depth itself). Objects are drawn in the scene's order: one hidden by an object before it fails the depth
    /// test unshaded, one hidden by an object after it is shaded and then covered (the same image either way).
    depth: Option<Pipeline>,
    /// The sun's shadow map (1×1 and undrawn until a view asks for shadows).
    shadow: Option<ShadowMap>,
    /// Which objects cast a shadow in the current view (empty: none).
    casters: Vec<bool>,
    /// The environment drawn behind the objects (made when a view first shows one) and whether this view does.
    background: Option<BackgroundPass>,
    shows_background: bool,
    /// The environment without its sun, which each pixel reflects at its mirror direction (a black texel where
    /// the view has none), and the view's factor to the frame's units and turn, with 1 where it has one.
    lighting: Option<EnvLighting>,
    lighting_values: [f32; 3],
    /// What the background pass is built for: the targets' format and whether they are display-encoded.
    color_format: vk::Format,
    display_output: bool,
    /// A display-encoded target's exposure and tone curve (`display::tone::display_uniform`: the materials'
    /// `params.display`), for the background too.
    display: [f32; 4],
    counting: bool,
    /// Samples per pixel of the targets it draws into.
    samples: vk::SampleCountFlags,
    /// The shading pipelines' face culling.
    cull_back_faces: bool,
    /// Whether the current view casts shadows (which of each material's pipelines draws).
    shadows: bool,
    /// The visibility buffer's target and vertex outputs where the renderer takes that path
    /// ([`Self::use_visibility_buffer`]); None: forward.
    visibility: Option<VisibilityState>,
}

impl SceneRenderer {
    pub const NAME: &'static str = "surface";

    /// `objects`: (mesh, index into `materials`). `display_output`: exposure-scaled sRGB for an UNORM target
    /// instead of linear RGB.
    pub fn new(
        ctx: &Context,
        materials: &[MaterialInput<'_>],
        objects: &[(&Mesh, usize)],
        color_format: vk::Format,
        display_output: bool,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        Self::with_variant(ctx, materials, objects, color_format, SurfaceVariant::Shade { display_output }, samples)
    }

    /// A renderer with the profiler's variants of the shader (linear float targets).
    pub fn with_variant(
        ctx: &Context,
        materials: &[MaterialInput<'_>],
        objects: &[(&Mesh, usize)],
        color_format: vk::Format,
        variant: SurfaceVariant,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        let empty = Self {
            materials: Vec::new(),
            objects: Vec::new(),
            depth: None,
            shadow: None,
            casters: Vec::new(),
            background: None,
            shows_background: false,
            lighting: None,
            lighting_values: [0.0; 3],
            color_format,
            display_output: matches!(variant, SurfaceVariant::Shade { display_output: true }),
            display: materials.first().map_or([1.0, 0.0, 0.0, 0.0], |m| m.material.params.display),
            counting: false,
            samples,
            cull_back_faces: false,
            shadows: false,
            visibility: None,
        };
        let mut made = Guard::new(ctx, empty);
        made.fill(ctx, materials, objects, color_format, variant)?;
        Ok(made.keep())
    }

    fn fill(
        &mut self,
        ctx: &Context,
        materials: &[MaterialInput<'_>],
        objects: &[(&Mesh, usize)],
        color_format: vk::Format,
        variant: SurfaceVariant,
    ) -> Result<()> {
        let cull_back_faces = crate::render::culls_back_faces(objects.iter().map(|(mesh, _)| *mesh));
        let front_first = objects.iter().all(|(mesh, _)| mesh.front_first);
        self.depth = (!front_first)
            .then(|| {
                ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                    name: pass::DEPTH,
                    vertex: &shaders::SURFACE_VERT,
                    fragment: None,
                    specialization: crate::gpu::vk::SpecConstants::default(),
                    push_constant_size: 0,
                    vertex_stride: std::mem::size_of::<Vertex>() as u32,
                    vertex_attributes: &VERTEX_ATTRIBUTES,
                    color_format,
                    depth: Some((DEPTH_FORMAT, DepthTest::Write)),
                    cull_back_faces,
                    samples: self.samples,
                    blend: Blend::Replace,
                })
            })
            .transpose()?;
        self.lighting = Some(EnvLighting::new(ctx)?);
        self.shadow = Some(ShadowMap::new(ctx, objects.len(), 1)?);
        self.counting = matches!(variant, SurfaceVariant::CountFetches { .. });
        for input in materials {
            let patch = Guard::new(ctx, PatchResources::new(ctx, input.material)?);
            let baked = input.material.table.is_some();
            let sky = match input.material.moments {
                None => SKY_DIFFRACTION_NONE,
                Some(_) => input.material.settings.sky_at.spec(),
            };
            let (fragment, specialization) = match variant {
                SurfaceVariant::Shade { display_output } => (
                    if baked { &shaders::SURFACE_BAKED_FRAG } else { &shaders::SURFACE_FRAG },
                    input.material.spec_constants(display_output),
                ),
                SurfaceVariant::CountFetches { stride } => (
                    if baked { &shaders::SURFACE_BAKED_COUNT_FRAG } else { &shaders::SURFACE_COUNT_FRAG },
                    counting_constants(ctx, input.material, input.material.spec_constants(false), stride),
                ),
            };
            let specialization = specialization.u32(SPEC_SKY_DIFFRACTION, sky);
            let vertex =
                if sky == SKY_DIFFRACTION_VERTEX { &shaders::SURFACE_SKY_VERT } else { &shaders::SURFACE_VERT };
            let visibility_vertex = if sky == SKY_DIFFRACTION_VERTEX {
                &shaders::SURFACE_SKY_VISIBILITY_VERT
            } else {
                &shaders::SURFACE_VISIBILITY_VERT
            };
            // The shading pass's fragment shader for frames of one sample per pixel and of several.
            let resolve = match baked {
                true => [&shaders::SURFACE_RESOLVE_BAKED_ONE_FRAG, &shaders::SURFACE_RESOLVE_BAKED_FRAG],
                false => [&shaders::SURFACE_RESOLVE_ONE_FRAG, &shaders::SURFACE_RESOLVE_FRAG],
            };
            let edges = if baked { &shaders::SURFACE_EDGES_BAKED_COMP } else { &shaders::SURFACE_EDGES_COMP };
            self.materials.push(MaterialGpu {
                pipelines: [None, None],
                recipe: (vertex, fragment, specialization),
                visibility_pipelines: [None, None],
                visibility_recipe: (visibility_vertex, resolve, edges),
                patch: patch.keep(),
                params: input.material.params,
                surface: input.surface,
            });
        }
        self.cull_back_faces = cull_back_faces;
        for (i, &(mesh, material)) in objects.iter().enumerate() {
            if material >= self.materials.len() {
                return Err(crate::Error::Invalid(format!(
                    "object {i} names material {material}, which does not exist"
                )));
            }
            let bounds = Aabb::of(&mesh.vertices);
            let mesh = Guard::new(ctx, MeshBuffers::new(ctx, mesh, &format!("object {i}"))?);
            let size = std::mem::size_of::<SurfaceUniforms>() as u64;
            let desc = BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER);
            let uniforms = ctx.create_buffer(desc, &format!("object {i} uniforms"))?;
            self.objects.push(ObjectGpu { mesh: mesh.keep(), uniforms, material, bounds });
        }
        Ok(())
    }

    /// Makes the renderer draw its frames through a visibility buffer ([`crate::render::visibility`]) into targets of
    /// `extent` (and the renderer's samples): linear colour only, and not the counting variant. Call it before the
    /// first [`Self::update`].
    pub fn use_visibility_buffer(&mut self, ctx: &Context, extent: vk::Extent2D) -> Result<()> {
        if self.display_output || self.counting {
            return Err(crate::Error::Invalid(
                "the visibility buffer draws linear frames (not a window's, nor the profiler's counting ones)".into(),
            ));
        }
        let meshes: Vec<&MeshBuffers> = self.objects.iter().map(|o| &o.mesh).collect();
        let state = VisibilityState::new(ctx, extent, self.samples, &meshes)?;
        if let Some(old) = self.visibility.replace(state) {
            // SAFETY: the caller promises no submitted work still uses this renderer's resources.
            unsafe { old.destroy(ctx) };
        }
        if let Some(background) = self.background.take() {
            // SAFETY: as above; `update` makes the pass again, drawn under the objects.
            unsafe { background.destroy(ctx) };
        }
        // `update` builds the pipelines, for the shadows its view casts.
        Ok(())
    }

    /// Which path the renderer's frames take.
    pub fn path(&self) -> ShadingPath {
        if self.visibility.is_some() {
            ShadingPath::Visibility
        } else {
            ShadingPath::Forward
        }
    }

    /// Writes every object's uniforms for `view` (its camera, light, sky, placements and shadow casters) at
    /// `aspect`, and places the shadow map (made full size the first time a view casts a shadow); no submitted
    /// work may still read them.
    pub fn update(&mut self, ctx: &Context, view: &SceneView, aspect: f32) -> Result<()> {
        let models = &view.models;
        self.casters = match &view.shadow_casters {
            Some(casts) => (0..self.objects.len()).map(|i| casts.get(i).copied().unwrap_or(true)).collect(),
            None => Vec::new(),
        };
        let frame = view.shadow_casters.as_ref().and_then(|_| {
            let placed: Vec<(Aabb, bool)> = (self.objects.iter().zip(models).zip(&self.casters))
                .filter_map(|((o, m), &casts)| Some((o.bounds?.moved(*m), casts)))
                .collect();
            ShadowFrame::of_objects(view.light_dir, &placed, view.camera.view_projection(aspect))
        });
        self.shadows = frame.is_some();
        self.build_pipelines(ctx)?;
        if frame.is_some() && self.shadow.as_ref().is_some_and(|s| s.size() != SHADOW_SIZE) {
            let full = ShadowMap::new(ctx, self.objects.len(), SHADOW_SIZE)?;
            if let Some(old) = self.shadow.replace(full) {
                // SAFETY: the caller promises no submitted work still uses this renderer's resources.
                unsafe { old.destroy(ctx) };
            }
        }
        self.lighting_values = [0.0; 3];
        if let (Some(environment), Some(lighting)) = (&view.lighting, &mut self.lighting) {
            if let Some((scale, rotation)) = lighting.panorama.update(ctx, environment, view.light_dir)? {
                self.lighting_values = [scale as f32, rotation as f32, 1.0];
            }
        }
        let size = self.shadow.as_ref().map_or(1, ShadowMap::size);
        let object_view = ObjectView {
            camera: &view.camera,
            aspect,
            light_dir: view.light_dir,
            sun: view.sun,
            ambient: view.ambient,
            sky_sh: view.sky_sh,
            sky_quadratic: crate::light::prefilter::sky_quadratic(&view.sky_sh),
            shadow: ShadowFrame::uniforms(frame.as_ref(), size),
        };
        let mut all = Vec::with_capacity(self.objects.len());
        for (object, model) in self.objects.iter_mut().zip(models) {
            let material = &self.materials[object.material];
            let mut u = SurfaceUniforms::new(&object_view, *model, &material.surface, object.material);
            // The environment diffracts where the material has its moments, its specular reflection read from the
            // map where the view has one.
            u.sky_quadratic[0][3] = if material.patch.has_moments { 1.0 } else { 0.0 };
            for (k, v) in self.lighting_values.into_iter().enumerate() {
                u.sky_quadratic[k + 1][3] = v;
            }
            object.uniforms.write(bytemuck::bytes_of(&u))?;
            all.push(u);
        }
        if let Some(shadow) = &mut self.shadow {
            shadow.update(frame, &all)?;
        }
        self.shows_background = view.behind.is_some();
        if let Some(environment) = &view.behind {
            if self.background.is_none() {
                let under = self.visibility.is_some();
                let pass = BackgroundPass::new(ctx, self.color_format, self.display_output, self.samples, under)?;
                let mut pass = Guard::new(ctx, pass);
                pass.set_display(self.display)?;
                self.background = Some(pass.keep());
            }
            let background = self.background.as_mut().expect("made above");
            background.update(ctx, environment, view.light_dir, (&view.camera, aspect))?;
        }
        Ok(())
    }

    /// Builds each material's shading pipeline for the current view's shadows where it has none yet (for the
    /// path the renderer takes).
    fn build_pipelines(&mut self, ctx: &Context) -> Result<()> {
        let shadows = self.shadows;
        if self.visibility.is_some() {
            return self.build_visibility_pipelines(ctx);
        }
        for m in &mut self.materials {
            let slot = &mut m.pipelines[usize::from(shadows)];
            if slot.is_some() {
                continue;
            }
            let (vertex, fragment, specialization) = m.recipe.clone();
            *slot = Some(ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                name: Self::NAME,
                vertex,
                fragment: Some(fragment),
                specialization: specialization.u32(SPEC_SHADOWS, u32::from(shadows)),
                push_constant_size: 0,
                vertex_stride: std::mem::size_of::<Vertex>() as u32,
                vertex_attributes: &VERTEX_ATTRIBUTES,
                color_format: self.color_format,
                depth: Some((DEPTH_FORMAT, if self.depth.is_some() { DepthTest::Equal } else { DepthTest::Write })),
                cull_back_faces: self.cull_back_faces,
                samples: self.samples,
                blend: Blend::Replace,
            })?);
        }
        Ok(())
    }

    /// Builds each material's visibility-buffer pipelines for the current view's shadows where it has none yet.
    fn build_visibility_pipelines(&mut self, ctx: &Context) -> Result<()> {
        let shadows = self.shadows;
        let multisampled = self.samples != vk::SampleCountFlags::TYPE_1;
        let push_constant_size = std::mem::size_of::<VisibilityPush>() as u32;
        for m in &mut self.materials {
            let slot = &mut m.visibility_pipelines[usize::from(shadows)];
            if slot.is_some() {
                continue;
            }
            let (vertex, [one, several], edges) = m.visibility_recipe;
            let fragment = if multisampled { several } else { one };
            let specialization = m.recipe.2.clone().u32(SPEC_SHADOWS, u32::from(shadows));
            let raster = Guard::new(
                ctx,
                ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                    name: crate::render::pass::VISIBILITY,
                    vertex,
                    fragment: Some(&shaders::VISIBILITY_FRAG),
                    specialization: specialization.clone(),
                    push_constant_size,
                    vertex_stride: std::mem::size_of::<Vertex>() as u32,
                    vertex_attributes: &VERTEX_ATTRIBUTES,
                    color_format: vk::Format::R32_UINT,
                    depth: Some((DEPTH_FORMAT, DepthTest::Write)),
                    cull_back_faces: self.cull_back_faces,
                    samples: self.samples,
                    blend: Blend::Replace,
                })?,
            );
            // One triangle over the viewport at the far plane (background.vert), tested behind the resolved depth.
            let shade = Guard::new(
                ctx,
                ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                    name: Self::NAME,
                    vertex: &shaders::BACKGROUND_VERT,
                    fragment: Some(fragment),
                    specialization: specialization.clone(),
                    push_constant_size,
                    vertex_stride: 0,
                    vertex_attributes: &[],
                    color_format: self.color_format,
                    depth: Some((DEPTH_FORMAT, DepthTest::Behind)),
                    cull_back_faces: false,
                    samples: vk::SampleCountFlags::TYPE_1,
                    blend: Blend::Add,
                })?,
            );
            let edges = multisampled
                .then(|| {
                    ctx.create_compute_pipeline(&ComputePipelineDesc {
                        name: crate::render::pass::EDGES,
                        shader: edges,
                        specialization,
                        push_constant_size,
                    })
                })
                .transpose()?;
            *slot = Some(VisibilityPipelines { raster: raster.keep(), shade: shade.keep(), edges });
        }
        Ok(())
    }

    /// Sets the exposure and the tone curve of the shaders' display output; no submitted work may still read the
    /// uniforms.
    pub fn set_display(&mut self, exposure_ev: f64, tone: crate::display::Tone) -> Result<()> {
        self.display = crate::display::tone::display_uniform(exposure_ev, tone);
        for m in &mut self.materials {
            m.params.display = self.display;
            m.patch.update(&m.params)?;
        }
        if let Some(background) = &mut self.background {
            background.set_display(self.display)?;
        }
        Ok(())
    }

    /// Records every object into `target` (in attachment layouts).
    pub fn record(&self, ctx: &Context, cmd: vk::CommandBuffer, target: &TargetView, background: [f32; 4]) {
        self.record_with(ctx, cmd, target, background, Instruments::default());
    }

    /// [`Self::record`] with `instruments`: a counting renderer's per-pixel fetch counters, the shading draws
    /// bracketed for a pipeline-statistics query (the depth pre-pass is not counted), and a lap at the end of
    /// each pass ([`crate::render::pass`]: the depth pre-pass, the shading, and the resolve of a multisampled target).
    pub fn record_with(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        target: &TargetView,
        background: [f32; 4],
        instruments: Instruments<'_>,
    ) {
        let Instruments { counts, statistics, laps } = instruments;
        debug_assert_eq!(self.counting, counts.is_some(), "a counting renderer takes counters, and only it");
        debug_assert_eq!(self.samples, target.samples, "the renderer's pipelines are built for the target's samples");
        let shadow = self.shadow.as_ref().expect("a filled renderer has a shadow map");
        shadow.record(
            ctx,
            cmd,
            self.objects.iter().enumerate().map(|(i, o)| (&o.mesh, self.casters.get(i) == Some(&true))),
        );
        if let Some(state) = &self.visibility {
            self.record_visibility(ctx, cmd, target, background, (state, statistics, laps));
            return;
        }
        // Where the environment is drawn behind the objects, every sample is drawn: the colour needs no clear
        // (on a GPU, clearing a multisampled float target is much of what its samples cost).
        let covered = self.shows_background && self.background.is_some();
        begin_rendering(ctx, cmd, target, (!covered).then_some(background), None);
        if let Some(depth) = &self.depth {
            ctx.begin_label(cmd, pass::DEPTH);
            for object in &self.objects {
                ctx.bind(cmd, depth, &[DescriptorWrite::UniformBuffer(BINDING_FRAME, &object.uniforms)], &[]);
                object.mesh.draw(ctx, cmd);
            }
            ctx.end_label(cmd);
            laps.lap(cmd, pass::DEPTH);
        }
        if let Some(s) = statistics {
            s.begin(cmd);
        }
        ctx.begin_label(cmd, pass::SHADING);
        for object in &self.objects {
            let material = &self.materials[object.material];
            let mut writes = self.object_writes(object);
            if let Some(counts) = counts.filter(|_| self.counting) {
                writes.push(DescriptorWrite::StorageBuffer(BINDING_FETCH_COUNTS, counts));
            }
            let pipeline = material.pipelines[usize::from(self.shadows)].as_ref();
            ctx.bind(
                cmd,
                pipeline.expect("update builds the view's pipelines before a frame is recorded"),
                &writes,
                &[],
            );
            object.mesh.draw(ctx, cmd);
        }
        ctx.end_label(cmd);
        if let Some(s) = statistics {
            s.end(cmd);
        }
        if let Some(background) = self.background.as_ref().filter(|_| self.shows_background) {
            background.record(ctx, cmd);
        }
        if target.resolve.is_some() {
            laps.lap(cmd, pass::SHADING);
            end_rendering(ctx, cmd);
            laps.lap(cmd, pass::RESOLVE);
        } else {
            end_rendering(ctx, cmd);
            laps.lap(cmd, pass::SHADING);
        }
    }

    /// The descriptors an object's shading reads: its uniforms, its material's patch, the lighting and the
    /// shadow map.
    fn object_writes<'a>(&'a self, object: &'a ObjectGpu) -> Vec<DescriptorWrite<'a>> {
        let material = &self.materials[object.material];
        let [p, t, s] = material.patch.writes();
        let shadow = self.shadow.as_ref().expect("a filled renderer has a shadow map");
        let mut writes = vec![
            DescriptorWrite::UniformBuffer(BINDING_FRAME, &object.uniforms),
            p,
            t,
            s,
            material.patch.moments_write(),
            self.lighting.as_ref().expect("a filled renderer has its lighting").write(),
        ];
        writes.extend(shadow.writes());
        writes
    }

    /// [`Self::record_with`] through the visibility buffer: the raster pass into `state`'s ids and `target`'s
    /// depth at the target's samples, then the shading pass into its one-sample colour (the resolve image of a
    /// target that keeps colour samples, which are left untouched), the background under it.
    fn record_visibility(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        target: &TargetView,
        background: [f32; 4],
        (state, statistics, laps): (&VisibilityState, Option<&Statistics<'_>>, Laps<'_>),
    ) {
        debug_assert_eq!(state.ids.extent(), target.extent, "the visibility buffer is made for the target's size");
        let shadows = usize::from(self.shadows);
        let pipelines = |object: &ObjectGpu| {
            let slot = self.materials[object.material].visibility_pipelines[shadows].as_ref();
            slot.expect("update builds the view's pipelines before a frame is recorded")
        };
        let edges_into = (!state.edges.is_empty()).then(|| {
            target.storage.expect("a multisampled visibility frame's target is a storage image (for_visibility_buffer)")
        });
        let with_background = self.shows_background && self.background.is_some();
        // Under an environment the objects add their colours to zero and the background goes under them; over a
        // constant background each object takes its share of the background away (`surface_resolve.frag`).
        let constant = if with_background { [0.0; 4] } else { background };
        let push = |i: usize| VisibilityPush {
            object: i as u32 + 1,
            background_r: constant[0],
            background_g: constant[1],
            background_b: constant[2],
            background_a: constant[3],
            edge: 0,
        };
        ctx.barrier_image(cmd, &state.ids, visibility::IDS_READ, ImageState::COLOR_ATTACHMENT);
        if let Some(coverage) = &state.coverage {
            ctx.barrier_image(cmd, coverage, visibility::COVERAGE_TESTED, ImageState::DEPTH_ATTACHMENT);
        }
        ctx.barrier_memory(cmd, visibility::OUTPUTS_READ, VERTEX_STORAGE_WRITE);
        let depth = target.depth.expect("a scene's target has a depth buffer");
        let ids = [vk::RenderingAttachmentInfo::default()
            .image_view(state.ids.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue { color: vk::ClearColorValue { uint32: [0; 4] } })];
        let far = vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue { depth: crate::scene::camera::FAR_DEPTH, stencil: 0 },
        };
        let mut raster_depth = vk::RenderingAttachmentInfo::default()
            .image_view(depth)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(if state.coverage.is_some() {
                vk::AttachmentStoreOp::DONT_CARE
            } else {
                vk::AttachmentStoreOp::STORE
            })
            .clear_value(far);
        if let (Some(coverage), Some(mode)) = (&state.coverage, state.resolve) {
            raster_depth = raster_depth
                .resolve_mode(mode)
                .resolve_image_view(coverage.view)
                .resolve_image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL);
        }
        visibility::begin(ctx, cmd, &ids, &raster_depth, target.extent);
        ctx.begin_label(cmd, pass::VISIBILITY);
        for (i, object) in self.objects.iter().enumerate() {
            let mut writes = self.object_writes(object);
            writes.push(DescriptorWrite::StorageBuffer(BINDING_VERTEX_OUTPUTS, &state.outputs[i]));
            ctx.bind(cmd, &pipelines(object).raster, &writes, bytemuck::bytes_of(&push(i)));
            object.mesh.draw(ctx, cmd);
        }
        ctx.end_label(cmd);
        end_rendering(ctx, cmd);
        laps.lap(cmd, pass::VISIBILITY);
        ctx.barrier_image(cmd, &state.ids, ImageState::COLOR_ATTACHMENT, ImageState::SHADER_READ);
        ctx.barrier_memory(cmd, VERTEX_STORAGE_WRITE, MemoryState::FRAGMENT_STORAGE);
        ctx.barrier_memory(cmd, visibility::DEPTH_WRITTEN, visibility::DEPTH_TESTED);
        state.reset_edges(ctx, cmd);
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(target.resolve.unwrap_or(target.color))
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: constant } })];
        // The coverage: the resolved depth, or the one-sample frame's own; where the device resolves neither way,
        // the near plane's depth everywhere lets every pixel through.
        let known = state.coverage.is_none() || state.resolve.is_some();
        let shading_depth = vk::RenderingAttachmentInfo::default()
            .image_view(state.coverage.as_ref().map_or(depth, |c| c.view))
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(if known { vk::AttachmentLoadOp::LOAD } else { vk::AttachmentLoadOp::CLEAR })
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: crate::scene::camera::NEAR_DEPTH, stencil: 0 },
            });
        visibility::begin(ctx, cmd, &color, &shading_depth, target.extent);
        if let Some(s) = statistics {
            s.begin(cmd);
        }
        ctx.begin_label(cmd, pass::SHADING);
        let shade_writes = |i: usize| {
            let object = &self.objects[i];
            let mut writes = self.object_writes(object);
            writes.extend([
                DescriptorWrite::SampledImage(BINDING_VISIBILITY_IDS, &state.ids, &state.sampler),
                DescriptorWrite::StorageBuffer(BINDING_VERTEX_OUTPUTS, &state.outputs[i]),
                DescriptorWrite::StorageBuffer(BINDING_MESH_INDICES, &object.mesh.indices),
            ]);
            if let Some(list) = state.edges.get(i) {
                writes.push(DescriptorWrite::StorageBuffer(BINDING_VISIBILITY_EDGES, list));
            }
            writes
        };
        for (i, object) in self.objects.iter().enumerate() {
            ctx.bind(cmd, &pipelines(object).shade, &shade_writes(i), bytemuck::bytes_of(&push(i)));
            // SAFETY: cmd is recording inside a rendering scope with a full-screen pipeline bound.
            unsafe { ctx.device().cmd_draw(cmd, 3, 1, 0, 0) };
        }
        ctx.end_label(cmd);
        if let Some(s) = statistics {
            s.end(cmd);
        }
        if let Some(background) = self.background.as_ref().filter(|_| self.shows_background) {
            background.record(ctx, cmd);
        }
        end_rendering(ctx, cmd);
        laps.lap(cmd, pass::SHADING);
        let Some(image) = edges_into else { return };
        // The edge pass: each object's listed pixels, their further triangles added to the colour in place (the
        // frame's one-sample image, in the GENERAL layout meanwhile).
        let colour =
            vk::ImageSubresourceRange::default().aspect_mask(vk::ImageAspectFlags::COLOR).level_count(1).layer_count(1);
        ctx.barrier_raw_image(cmd, image, colour, ImageState::COLOR_ATTACHMENT, ImageState::STORAGE);
        ctx.barrier_memory(cmd, MemoryState::FRAGMENT_STORAGE, visibility::EDGES_NEXT);
        ctx.begin_label(cmd, pass::EDGES);
        for (i, object) in self.objects.iter().enumerate() {
            let pipeline = pipelines(object).edges.as_ref().expect("a multisampled renderer builds its edge pass");
            let mut writes = shade_writes(i);
            writes
                .push(DescriptorWrite::StorageView(BINDING_VISIBILITY_TARGET, target.resolve.unwrap_or(target.color)));
            ctx.bind(cmd, pipeline, &writes, &[]);
            for k in 1..=state.edge_lists() {
                if i > 0 || k > 1 {
                    ctx.barrier_memory(cmd, visibility::EDGES_ADDED, visibility::EDGES_NEXT);
                }
                let push = VisibilityPush { edge: k, ..push(i) };
                let offset = u64::from(k - 1) * visibility::edge_list_bytes(target.extent);
                // SAFETY: cmd is recording outside a rendering scope with the edge pass bound; each list begins
                // with its dispatch's size, which the shading pass counted.
                unsafe {
                    ctx.device().cmd_push_constants(
                        cmd,
                        pipeline.layout,
                        pipeline.push_stages,
                        0,
                        bytemuck::bytes_of(&push),
                    );
                    ctx.device().cmd_dispatch_indirect(cmd, state.edges[i].raw, offset);
                }
            }
        }
        ctx.end_label(cmd);
        ctx.barrier_raw_image(cmd, image, colour, ImageState::STORAGE, ImageState::COLOR_ATTACHMENT);
        laps.lap(cmd, pass::EDGES);
    }

    /// What the uploads of the materials' tables (or Taylor terms) cost, material by material.
    pub fn uploads(&self) -> Vec<crate::render::diffraction::Upload> {
        self.materials.iter().map(|m| m.patch.upload).collect()
    }

    /// # Safety
    /// The GPU must be done with everything.
    pub unsafe fn destroy(self, ctx: &Context) {
        if let Some(depth) = self.depth {
            depth.destroy(ctx);
        }
        if let Some(shadow) = self.shadow {
            shadow.destroy(ctx);
        }
        if let Some(background) = self.background {
            background.destroy(ctx);
        }
        if let Some(lighting) = self.lighting {
            lighting.destroy(ctx);
        }
        if let Some(visibility) = self.visibility {
            visibility.destroy(ctx);
        }
        for m in self.materials {
            for p in m.pipelines.into_iter().flatten() {
                p.destroy(ctx);
            }
            for pipelines in m.visibility_pipelines.into_iter().flatten() {
                pipelines.destroy(ctx);
            }
            m.patch.destroy(ctx);
        }
        for o in self.objects {
            o.mesh.destroy(ctx);
            o.uniforms.destroy(ctx);
        }
    }
}

/// What a scene's frames are drawn into: what `render` reads back, or what `view` presents. The profiler times
/// either (`--sweep target=linear,display`), so that a machine without a display measures the window's frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FrameTarget {
    #[default]
    /// Linear RGB in 32-bit floats, exposure and display encoding left to the CPU (`render`, the profiler's
    /// default): 16 bytes per sample.
    Linear,
    /// Exposure-scaled sRGB in 8 bits per channel, encoded by the shaders (the viewer's window): 4 bytes per
    /// sample. On an NVIDIA H100 the default scene's frame at 1920×1080 with 4 samples took 2.26 ms so, against
    /// 4.76 linear (docs/performance.md, "The window's frames on the H100").
    Display,
}

impl FrameTarget {
    pub const NAMES: [&'static str; 2] = ["linear", "display"];

    pub fn name(self) -> &'static str {
        match self {
            Self::Linear => "linear",
            Self::Display => "display",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "linear" => Some(Self::Linear),
            "display" => Some(Self::Display),
            _ => None,
        }
    }

    /// Whether the shaders apply the exposure and the sRGB encoding.
    pub fn display_output(self) -> bool {
        self == Self::Display
    }

    /// The colour format of the target (and of the [`SceneRenderer`] drawing into it).
    pub fn format(self) -> vk::Format {
        OffscreenFrames::format(self.display_output())
    }
}

/// An offscreen target for a [`SceneRenderer`]: renders frames and reads them back.
pub struct OffscreenFrames {
    target: OffscreenTarget,
    /// Where each frame's pixels are copied, in the frame's own submission.
    readback: Buffer,
    display_output: bool,
}

impl OffscreenFrames {
    /// Frames of `samples` per pixel, averaged into each pixel (multisample anti-aliasing).
    pub fn new(
        ctx: &Context,
        width: u32,
        height: u32,
        display_output: bool,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        let format = Self::format(display_output);
        let target = Guard::new(ctx, OffscreenTarget::multisampled(ctx, width, height, format, true, samples)?);
        let readback = ctx.create_readback(&target.color)?;
        Ok(Self { target: target.keep(), readback, display_output })
    }

    /// Readies the target for a renderer drawing through a visibility buffer
    /// ([`SceneRenderer::use_visibility_buffer`], [`OffscreenTarget::for_visibility_buffer`]); no submitted work may
    /// still use it.
    pub fn for_visibility_buffer(&mut self, ctx: &Context) -> Result<()> {
        // SAFETY: the caller promises the GPU is done with the target.
        unsafe { self.target.for_visibility_buffer(ctx) }
    }

    /// The colour format a [`SceneRenderer`] drawing into these frames must use.
    pub fn format(display_output: bool) -> vk::Format {
        if display_output {
            vk::Format::R8G8B8A8_UNORM
        } else {
            LINEAR_FORMAT
        }
    }

    /// Draws one frame (uniforms already updated) and copies it back in the same submission; its passes are
    /// timed (the renderer's, then [`pass::COPY`]).
    pub fn render(&self, ctx: &Context, renderer: &SceneRenderer, background: [f32; 4]) -> Result<Frame> {
        let times = ctx.one_shot_laps(SceneRenderer::NAME, |cmd, laps| {
            self.target.begin(ctx, cmd);
            let instruments = Instruments { laps, ..Instruments::default() };
            renderer.record_with(ctx, cmd, &self.target.view(), background, instruments);
            ctx.record_readback(cmd, &self.target.color, ImageState::COLOR_ATTACHMENT, &self.readback);
            laps.lap(cmd, pass::COPY);
        })?;
        let bytes = self.readback.mapped().map(<[u8]>::to_vec).unwrap_or_default();
        let extent = self.target.color.extent();
        let pixels = if self.display_output {
            Pixels::Rgba8(bytes)
        } else {
            Pixels::Linear(bytemuck::pod_collect_to_vec(&bytes))
        };
        Ok(Frame { width: extent.width, height: extent.height, pixels, times })
    }

    /// # Safety
    /// The GPU must be done with the target.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.target.destroy(ctx);
        self.readback.destroy(ctx);
    }
}

/// Renders `mesh` with `material` under `view` (its first model) headless, one sample per pixel: linear float
/// RGB, or (with `display_output`) 8-bit sRGB from the shader's own exposure and transfer function.
pub fn render_surface(
    ctx: &Context,
    material: &Material,
    mesh: &Mesh,
    view: &SceneView,
    width: u32,
    height: u32,
    display_output: bool,
) -> Result<Frame> {
    let format = OffscreenFrames::format(display_output);
    let surface = SurfaceMaterial { orientation: orientation(0.0), pigment: [0.0; 3], matte: false };
    let inputs = [MaterialInput { material, surface }];
    let one = vk::SampleCountFlags::TYPE_1;
    let mut renderer = Guard::new(ctx, SceneRenderer::new(ctx, &inputs, &[(mesh, 0)], format, display_output, one)?);
    let frames = Guard::new(ctx, OffscreenFrames::new(ctx, width, height, display_output, one)?);
    renderer.update(ctx, view, width as f32 / height as f32)?;
    frames.render(ctx, &renderer, view.background)
}

crate::impl_destroy!(SceneRenderer, OffscreenFrames);
