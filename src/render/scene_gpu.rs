//! A scene's GPU state, which both shading paths read: each material's patch and uniforms, each object's buffers
//! and uniforms, the sun's shadow map, the environment the surfaces reflect and the one drawn behind them.
//!
//! `SceneGpu::update` writes all of it for a view and says what its pipelines are specialized for; the paths
//! (`render::forward`, `render::visibility`) build their pipelines from `SceneGpu::formats` and each material's
//! shader choices, and record draws that read this state. Nothing here records a draw of the objects.

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::{Error, Result};
use crate::gpu::interface::{
    DiffractionParams, SurfaceUniforms, BINDING_ENV_LIGHT, BINDING_FRAME, SKY_DIFFRACTION_NONE, SKY_DIFFRACTION_VERTEX,
    SPEC_LAMPS, SPEC_MAPS, SPEC_MATTE, SPEC_SHADOWS, SPEC_SKY_DIFFRACTION, SPEC_SUN,
};
use crate::gpu::vk::{Buffer, BufferDesc, Context, DescriptorWrite, Destroy, Guard, Image, Sampler, SpecConstants};
use crate::material::Material;
use crate::render::background::{BackgroundPass, Panorama};
use crate::render::diffraction::{counting_constants, PatchResources};
use crate::render::lamp_shadow::{LampShadowUniforms, LampShadows};
use crate::render::maps::MapImages;
use crate::render::shadow::{Aabb, ShadowFrame, ShadowMap, ShadowUniforms, SHADOW_SIZE};
pub(crate) use crate::render::variants::{ViewSpec, ViewVariants};
use crate::render::{MeshBuffers, SceneView};
use crate::scene::camera::Camera;
use crate::scene::mesh::Mesh;

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

/// Which build of the surface shader a renderer uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceVariant {
    /// The colour (linear, or display-encoded).
    Shade { display_output: bool },
    /// Linear colour, and each fragment's texel fetches and shading added to per-pixel counters (row stride
    /// given).
    CountFetches { stride: u32 },
}

impl SurfaceVariant {
    /// Whether the shaders write exposure-scaled, display-encoded colour.
    pub fn display_output(self) -> bool {
        self == Self::Shade { display_output: true }
    }

    /// Whether fragments count their fetches (the profiler's).
    pub fn counting(self) -> bool {
        matches!(self, Self::CountFetches { .. })
    }
}

/// What every pipeline drawing the scene is built for: the targets' colour format and samples, the shader's
/// build, and how the meshes rasterise.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Formats {
    pub color: vk::Format,
    pub samples: vk::SampleCountFlags,
    pub variant: SurfaceVariant,
    /// Back faces culled: no mesh shows one (`render::culls_back_faces`).
    pub cull_back_faces: bool,
    /// Every mesh draws its triangles front first ([`Mesh::front_first`]): no depth pre-pass is needed.
    pub front_first: bool,
}

/// A material on the GPU: its patch (terms or table, spectrum, uniforms) and what its shaders are built from.
pub(crate) struct MaterialGpu {
    pub patch: PatchResources,
    pub params: DiffractionParams,
    pub surface: SurfaceMaterial,
    /// Whether it reads a baked table (else Taylor terms): which fragment shaders draw it.
    pub baked: bool,
    /// Whether the environment's diffraction is evaluated per vertex (`SKY_DIFFRACTION_VERTEX`): which vertex
    /// shaders draw it.
    pub sky_at_vertex: bool,
    /// Its specialization constants, all but `SPEC_SHADOWS` ([`Self::specialization`]).
    constants: SpecConstants,
}

impl MaterialGpu {
    /// `maps`: whether any of its objects has a map.
    fn new(ctx: &Context, input: &MaterialInput<'_>, variant: SurfaceVariant, maps: bool) -> Result<Self> {
        let material = input.material;
        let patch = PatchResources::new(ctx, material)?;
        let sky = match material.moments {
            None => SKY_DIFFRACTION_NONE,
            Some(_) => material.settings.sky_at.spec(),
        };
        let constants = match variant {
            SurfaceVariant::Shade { display_output } => material.spec_constants(display_output),
            SurfaceVariant::CountFetches { stride } => {
                counting_constants(ctx, material, material.spec_constants(false), stride)
            }
        };
        Ok(Self {
            patch,
            params: material.params,
            surface: input.surface,
            baked: material.table.is_some(),
            sky_at_vertex: sky == SKY_DIFFRACTION_VERTEX,
            constants: constants
                .u32(SPEC_SKY_DIFFRACTION, sky)
                .u32(SPEC_MAPS, u32::from(maps))
                .u32(SPEC_MATTE, u32::from(input.surface.matte)),
        })
    }

    /// The constants of its pipelines for a view of `spec`.
    pub fn specialization(&self, spec: ViewSpec) -> SpecConstants {
        let constants = self.constants.clone().u32(SPEC_SHADOWS, u32::from(spec.shadows));
        constants.u32(SPEC_LAMPS, spec.lamps).u32(SPEC_SUN, u32::from(spec.sun))
    }

    /// # Safety
    /// The GPU must be done with it.
    unsafe fn destroy(self, ctx: &Context) {
        self.patch.destroy(ctx);
    }
}

/// An object on the GPU: its mesh, its maps, its uniforms and its material.
pub(crate) struct ObjectGpu {
    pub mesh: MeshBuffers,
    pub maps: MapImages,
    pub uniforms: Buffer,
    pub material: usize,
    /// The mesh's own box (object space), which the shadow map is fitted to once placed.
    bounds: Option<Aabb>,
}

impl ObjectGpu {
    fn new(ctx: &Context, i: usize, mesh: &Mesh, material: usize) -> Result<Self> {
        let bounds = Aabb::of(&mesh.vertices);
        let maps = Guard::new(ctx, MapImages::new(ctx, &mesh.maps)?);
        let mesh = Guard::new(ctx, MeshBuffers::new(ctx, mesh, &format!("object {i}"))?);
        let size = std::mem::size_of::<SurfaceUniforms>() as u64;
        let desc = BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER);
        let uniforms = ctx.create_buffer(desc, &format!("object {i} uniforms"))?;
        Ok(Self { mesh: mesh.keep(), maps: maps.keep(), uniforms, material, bounds })
    }

    /// # Safety
    /// The GPU must be done with it.
    unsafe fn destroy(self, ctx: &Context) {
        self.mesh.destroy(ctx);
        self.maps.destroy(ctx);
        self.uniforms.destroy(ctx);
    }
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
    /// The lamps (`SurfaceUniforms::lamps`).
    pub lamps: crate::light::lamp::LampUniforms,
    /// Where their shadow maps lie (`SurfaceUniforms::lamp_shadow_view_proj`, `lamp_shadow_scales`, `lamp_atlas`).
    pub lamp_shadows: LampShadowUniforms,
}

impl ObjectView<'_> {
    /// One object's uniforms: its model matrix, its material's orientation (cos, sin) and pigment, the
    /// material's index (`orientation.z`, which the G-buffer writes), whether it is matte, and which maps it has
    /// (`SurfaceMaps::flags`).
    pub fn uniforms(&self, model: Mat4, material: &SurfaceMaterial, index: usize, maps: [f32; 4]) -> SurfaceUniforms {
        let SurfaceMaterial { orientation, pigment, matte } = *material;
        let normal = Mat4::from_mat3(glam::Mat3::from_mat4(model).inverse().transpose());
        let [cos, sin] = orientation;
        let [r, g, b] = pigment;
        let view_proj = self.camera.view_projection(self.aspect);
        SurfaceUniforms {
            view_proj: view_proj.to_cols_array_2d(),
            model: model.to_cols_array_2d(),
            normal_matrix: normal.to_cols_array_2d(),
            camera_pos: self.camera.position.extend(1.0).to_array(),
            light_dir: self.light_dir.normalize().extend(self.sun).to_array(),
            orientation: [cos, sin, index as f32, if matte { 1.0 } else { 0.0 }],
            pigment: [r, g, b, self.ambient],
            sky_sh: self.sky_sh,
            shadow_view_proj: self.shadow.view_proj,
            shadow: self.shadow.lookup,
            shadow_penumbra: self.shadow.penumbra,
            sky_quadratic: self.sky_quadratic,
            inverse_view_proj: view_proj.inverse().to_cols_array_2d(),
            lamp_count: self.lamps.count,
            lamps: self.lamps.lamps,
            maps,
            lamp_shadow_view_proj: self.lamp_shadows.view_proj,
            lamp_shadow_scales: self.lamp_shadows.scales,
            lamp_atlas: self.lamp_shadows.atlas,
        }
    }
}

/// The width of the clear sky's map (without its sun) the surface pass reflects: 1.4° texels (the sky is smooth).
pub const LIGHTING_SKY_WIDTH: u32 = 256;

/// The environment the surface pass reflects at each pixel's mirror direction (`BINDING_ENV_LIGHT`).
struct EnvLighting {
    panorama: Panorama,
    sampler: Sampler,
    /// One black texel, bound until a view has an environment.
    fallback: Image,
}

impl EnvLighting {
    fn new(ctx: &Context) -> Result<Self> {
        let sampler = Guard::new(ctx, ctx.create_panorama_sampler("environment lighting")?);
        let black = crate::light::environment::EnvironmentMap { width: 1, height: 1, rgb: vec![[0.0; 3]] };
        let fallback = crate::render::background::upload(ctx, &black)?;
        let panorama = Panorama::new(false, LIGHTING_SKY_WIDTH);
        Ok(Self { panorama, sampler: sampler.keep(), fallback })
    }

    fn write(&self) -> DescriptorWrite<'_> {
        let image = self.panorama.image().unwrap_or(&self.fallback);
        DescriptorWrite::SampledImage(BINDING_ENV_LIGHT, image, &self.sampler)
    }

    /// # Safety
    /// The GPU must be done with it.
    unsafe fn destroy(self, ctx: &Context) {
        self.panorama.destroy(ctx);
        self.sampler.destroy(ctx);
        self.fallback.destroy(ctx);
    }
}

/// A scene's GPU state (see the module's header).
pub(crate) struct SceneGpu {
    pub materials: Vec<MaterialGpu>,
    pub objects: Vec<ObjectGpu>,
    pub formats: Formats,
    /// The sun's shadow map (1×1 and undrawn until a view casts a shadow).
    shadow: ShadowMap,
    /// The lamps' shadow maps (1×1 until a view's lamps cast a shadow).
    lamp_shadows: LampShadows,
    /// Which objects cast a shadow in the current view (empty: none).
    casters: Vec<bool>,
    /// The environment without its sun, which each pixel reflects at its mirror direction.
    lighting: EnvLighting,
    /// The environment drawn behind the objects, made when a view first shows one; whether this view does; and
    /// whether it is drawn under the objects' colours (the visibility path) rather than behind their depth.
    background: Option<BackgroundPass>,
    shows_background: bool,
    background_under: bool,
    /// A display-encoded target's exposure and tone curve (`display::tone::display_uniform`: the materials'
    /// `params.display`), for the background too.
    display: [f32; 4],
}

impl SceneGpu {
    /// Uploads `materials` and `objects` ((mesh, index into `materials`)); `background_under`: an environment is
    /// drawn under the objects' colours (the visibility path's frames) instead of behind their depth.
    pub fn new(
        ctx: &Context,
        materials: &[MaterialInput<'_>],
        objects: &[(&Mesh, usize)],
        formats: Formats,
        background_under: bool,
    ) -> Result<Self> {
        if let Some((i, &(_, m))) = objects.iter().enumerate().find(|(_, (_, m))| *m >= materials.len()) {
            return Err(Error::Invalid(format!("object {i} names material {m}, which does not exist")));
        }
        let mut gpu_materials = Guard::new(ctx, Vec::with_capacity(materials.len()));
        for (m, input) in materials.iter().enumerate() {
            let maps = objects.iter().any(|&(mesh, i)| i == m && !mesh.maps.is_empty());
            gpu_materials.push(MaterialGpu::new(ctx, input, formats.variant, maps)?);
        }
        let mut gpu_objects = Guard::new(ctx, Vec::with_capacity(objects.len()));
        for (i, &(mesh, material)) in objects.iter().enumerate() {
            gpu_objects.push(ObjectGpu::new(ctx, i, mesh, material)?);
        }
        let shadow = Guard::new(ctx, ShadowMap::new(ctx, objects.len(), 1)?);
        let lamp_shadows = Guard::new(ctx, LampShadows::new(ctx, 0, objects.len(), 1)?);
        let lighting = EnvLighting::new(ctx)?;
        Ok(Self {
            materials: gpu_materials.keep(),
            objects: gpu_objects.keep(),
            formats,
            shadow: shadow.keep(),
            lamp_shadows: lamp_shadows.keep(),
            casters: Vec::new(),
            lighting,
            background: None,
            shows_background: false,
            background_under,
            display: materials.first().map_or([1.0, 0.0, 0.0, 0.0], |m| m.material.params.display),
        })
    }

    /// Writes every object's uniforms for `view` (its camera, light, sky, placements and shadow casters) at
    /// `aspect`, places the shadow map (made full size the first time a view casts a shadow) and the environment;
    /// returns what its pipelines are specialized for (whether it casts shadows, how many lamps light it, whether
    /// the sun does). No submitted work may still read any of it.
    pub fn update(&mut self, ctx: &Context, view: &SceneView, aspect: f32) -> Result<ViewSpec> {
        let frame = self.fit_shadow(ctx, view, aspect)?;
        let lamp_frames = match view.shadow_casters {
            Some(_) => {
                self.lamp_shadows.fit(ctx, &view.lamps, &self.placed(view), view.camera.view_projection(aspect))?
            }
            None => Vec::new(),
        };
        let lamp_shadows = LampShadowUniforms::new(&lamp_frames, &view.lamps, self.lamp_shadows.size());
        let mut lit = [0.0; 3];
        if let Some(environment) = &view.lighting {
            if let Some((scale, rotation)) = self.lighting.panorama.update(ctx, environment, view.light_dir)? {
                lit = [scale as f32, rotation as f32, 1.0];
            }
        }
        let object_view = ObjectView {
            camera: &view.camera,
            aspect,
            light_dir: view.light_dir,
            sun: view.sun,
            ambient: view.ambient,
            sky_sh: view.sky_sh,
            sky_quadratic: crate::light::prefilter::sky_quadratic(&view.sky_sh),
            shadow: ShadowFrame::uniforms(frame.as_ref(), self.shadow.size()),
            lamps: view.lamps,
            lamp_shadows,
        };
        let mut all = Vec::with_capacity(self.objects.len());
        for (object, model) in self.objects.iter_mut().zip(&view.models) {
            let material = &self.materials[object.material];
            let mut u = object_view.uniforms(*model, &material.surface, object.material, object.maps.flags);
            // The environment diffracts where the material has its moments, its specular reflection read from the
            // map where the view has one.
            u.sky_quadratic[0][3] = if material.patch.has_moments { 1.0 } else { 0.0 };
            for (k, v) in lit.into_iter().enumerate() {
                u.sky_quadratic[k + 1][3] = v;
            }
            object.uniforms.write(bytemuck::bytes_of(&u))?;
            all.push(u);
        }
        let lamps_cast = lamp_frames.iter().any(Option::is_some);
        let spec =
            ViewSpec { shadows: frame.is_some() || lamps_cast, lamps: view.lamps.count[0] as u32, sun: view.sun > 0.0 };
        self.shadow.update(frame, &all)?;
        self.lamp_shadows.update(&lamp_frames, &all)?;
        self.update_background(ctx, view, aspect)?;
        Ok(spec)
    }

    /// Which objects cast a shadow under `view`, and where the shadow map lies (None: no shadow); the map made
    /// full size the first time a view casts one.
    fn fit_shadow(&mut self, ctx: &Context, view: &SceneView, aspect: f32) -> Result<Option<ShadowFrame>> {
        self.casters = match &view.shadow_casters {
            Some(casts) => (0..self.objects.len()).map(|i| casts.get(i).copied().unwrap_or(true)).collect(),
            None => Vec::new(),
        };
        // No sun (lamps alone), no sun's shadow.
        if view.shadow_casters.is_none() || view.sun <= 0.0 {
            return Ok(None);
        }
        let frame = ShadowFrame::of_objects(view.light_dir, &self.placed(view), view.camera.view_projection(aspect));
        if frame.is_some() && self.shadow.size() != SHADOW_SIZE {
            let full = ShadowMap::new(ctx, self.objects.len(), SHADOW_SIZE)?;
            // SAFETY: the caller promises no submitted work still uses this state.
            unsafe { std::mem::replace(&mut self.shadow, full).destroy(ctx) };
        }
        Ok(frame)
    }

    /// The objects' boxes placed by `view`, and whether each casts a shadow (as `fit_shadow` set `casters`).
    fn placed(&self, view: &SceneView) -> Vec<(Aabb, bool)> {
        (self.objects.iter().zip(&view.models).zip(&self.casters))
            .filter_map(|((o, m), &casts)| Some((o.bounds?.moved(*m), casts)))
            .collect()
    }

    /// The environment behind the objects, where `view` shows one (its pass made the first time).
    fn update_background(&mut self, ctx: &Context, view: &SceneView, aspect: f32) -> Result<()> {
        self.shows_background = view.behind.is_some();
        let Some(environment) = &view.behind else { return Ok(()) };
        let background = match &mut self.background {
            Some(pass) => pass,
            None => {
                let Formats { color, samples, variant, .. } = self.formats;
                let under = self.background_under;
                let pass = BackgroundPass::new(ctx, color, variant.display_output(), samples, under)?;
                let mut pass = Guard::new(ctx, pass);
                pass.set_display(self.display)?;
                self.background.insert(pass.keep())
            }
        };
        background.update(ctx, environment, view.light_dir, (&view.camera, aspect))
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

    /// The environment pass, where this view shows one.
    pub fn background(&self) -> Option<&BackgroundPass> {
        self.background.as_ref().filter(|_| self.shows_background)
    }

    /// Records the shadow maps (the sun's, the lamps') where the view's casters or placements changed since they
    /// were last drawn.
    pub fn record_shadow(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        let casts = |i: usize| self.casters.get(i) == Some(&true);
        self.shadow.record(ctx, cmd, self.objects.iter().enumerate().map(|(i, o)| (&o.mesh, casts(i))));
        self.lamp_shadows.record(ctx, cmd, self.objects.iter().enumerate().map(|(i, o)| (&o.mesh, casts(i))));
    }

    /// The descriptors object `i`'s shading reads: its uniforms, its material's patch, the lighting and the
    /// shadow map.
    pub fn object_writes(&self, i: usize) -> Vec<DescriptorWrite<'_>> {
        let object = &self.objects[i];
        let patch = &self.materials[object.material].patch;
        let mut writes = vec![DescriptorWrite::UniformBuffer(BINDING_FRAME, &object.uniforms)];
        writes.extend(patch.writes());
        writes.extend([patch.moments_write(), self.lighting.write()]);
        writes.extend(self.shadow.writes());
        writes.extend(self.lamp_shadows.writes());
        writes.extend(object.maps.writes());
        writes
    }

    /// What the uploads of the materials' tables (or Taylor terms) cost, material by material.
    pub fn uploads(&self) -> Vec<crate::render::diffraction::Upload> {
        self.materials.iter().map(|m| m.patch.upload).collect()
    }

    /// # Safety
    /// The GPU must be done with everything.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.shadow.destroy(ctx);
        self.lamp_shadows.destroy(ctx);
        self.background.destroy(ctx);
        self.lighting.destroy(ctx);
        self.materials.destroy(ctx);
        self.objects.destroy(ctx);
    }
}

crate::impl_destroy!(MaterialGpu, ObjectGpu, SceneGpu);
