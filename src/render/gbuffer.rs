//! The G-buffer: per pixel of a scene's frame, what it sees, unshaded — the patch-frame directions ω_i and ω_r,
//! the material and the pixel's footprint in (u, v) (`glsl/gbuffer.frag.glsl`, drawn with the surface pass's
//! vertex shader and rasteriser). It sizes each material's baked table to the views the frame shows
//! ([`GBuffer::reaches`]) and gives the profiler's exact CPU reference its inputs.

use ash::vk;
use glam::{DVec3, Vec3};

use crate::error::Result;
use crate::gpu::interface::SurfaceUniforms;
use crate::gpu::interface::Vertex;
use crate::gpu::interface::MAX_LAMPS;
use crate::gpu::interface::{BINDING_FRAME, SPEC_GBUFFER_PART};
use crate::gpu::shaders;
use crate::gpu::shaders::VERTEX_ATTRIBUTES;
use crate::gpu::vk::{
    Blend, Buffer, BufferDesc, Context, DepthTest, DescriptorWrite, GraphicsPipelineDesc, Guard, Pipeline,
    SpecConstants,
};
use crate::light::lamp::{widening_variance, Lamp};
use crate::material::Reach;
use crate::physics::baked::Domain;
use crate::physics::coherence::DEFAULT_COHERENCE_UM;
use crate::render::lamp_shadow::{LampShadowUniforms, LampShadows, LAMP_SHADOW_SIZE};
use crate::render::scene_gpu::{ObjectView, SurfaceMaterial};
use crate::render::shadow::{Aabb, ShadowFrame, ShadowMap, SHADOW_SIZE};
use crate::render::{begin_rendering, end_rendering, MeshBuffers, OffscreenTarget, DEPTH_FORMAT, LINEAR_FORMAT};
use crate::scene::camera::Camera;
use crate::scene::Scene;

/// The G-buffer's parts, drawn one after the other: (ω_i, material), (ω_r, footprint), (albedo, normal · up),
/// (world normal, the sun's visible share), (the patch's x axis in the world, its handedness), (the point in the
/// world), then the visible shares of lamps 1–4 and 5–8 (where lamps cast shadows).
const PARTS: u32 = 8;
/// The parts drawn `with_normals` before the lamps' shares.
const NORMAL_PARTS: u32 = 6;
/// The footprint percentile taken as a material's smallest (the very smallest are single pixels on a flat facet
/// seen at a glance, which would size a table for nothing else).
const FOOTPRINT_PERCENTILE: f64 = 0.05;

/// A pixel that shows a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seen {
    /// Patch-frame unit vectors towards the light and the viewer.
    pub omega_i: DVec3,
    pub omega_r: DVec3,
    pub material: usize,
    /// The pixel's footprint in (u, v) (`pixel_footprint` of glsl/include/footprint.glsl).
    pub footprint: f64,
    /// The pigment's linear RGB albedo here (the material's, tinted by the mesh).
    pub albedo: DVec3,
    /// cos of the angle between the shading normal and the world's up (how much of the sky it sees).
    pub normal_up: f64,
    /// The shading normal in the world (unit; what an environment's irradiance is read at); zero unless the
    /// G-buffer was drawn `with_normals` or the scene casts shadows.
    pub normal: DVec3,
    /// The share of the sun that no shadow hides here (the surface pass's `sun_visibility`, from the same
    /// shadow map); 1 where the scene has no shadows.
    pub sun_visible: f64,
    /// The patch frame in the world (columns x, y, z: d = frame·ω), where the G-buffer was drawn `with_normals`
    /// (zero otherwise): how the environment is seen from the patch.
    pub frame: glam::DMat3,
    /// The point in the world, where the G-buffer was drawn `with_normals` (zero otherwise): where the lamps are
    /// seen from.
    pub position: DVec3,
    /// The share of each lamp's disc that no shadow hides here (the surface pass's `lamp_visibility`); 1 where
    /// the lamps cast no shadows or the G-buffer was not drawn `with_normals`.
    pub lamp_visible: [f64; MAX_LAMPS as usize],
}

impl Seen {
    /// `lamp` as this pixel sees it (the G-buffer drawn `with_normals`): its patch-frame unit direction and its
    /// illuminance at normal incidence here (`Lamp::light_at`).
    pub fn lamp(&self, lamp: &Lamp) -> (DVec3, f64) {
        let (l, irradiance) = lamp.light_at(self.position);
        (self.frame.transpose() * l, irradiance)
    }
}

/// A frame's G-buffer: rows top first, None where no surface is seen.
pub struct GBuffer {
    pub pixels: Vec<Option<Seen>>,
}

/// The GPU objects of one G-buffer draw, destroyed together.
#[derive(Default)]
struct Parts {
    meshes: Vec<MeshBuffers>,
    maps: Vec<crate::render::maps::MapImages>,
    uniforms: Vec<Buffer>,
    pipelines: Vec<Pipeline>,
    target: Option<OffscreenTarget>,
    shadow: Option<ShadowMap>,
    lamp_shadows: Option<LampShadows>,
}

impl Parts {
    /// # Safety
    /// The GPU must be done with everything.
    unsafe fn destroy(self, ctx: &Context) {
        self.meshes.into_iter().for_each(|m| m.destroy(ctx));
        self.maps.into_iter().for_each(|m| m.destroy(ctx));
        self.uniforms.into_iter().for_each(|b| b.destroy(ctx));
        self.pipelines.into_iter().for_each(|p| p.destroy(ctx));
        if let Some(t) = self.target {
            t.destroy(ctx);
        }
        if let Some(s) = self.shadow {
            s.destroy(ctx);
        }
        if let Some(s) = self.lamp_shadows {
            s.destroy(ctx);
        }
    }
}

impl GBuffer {
    /// Draws `scene` from `camera` under `light_dir` (world, towards the light) at `width`×`height`; the world
    /// normals, patch frames and points too (a fourth, fifth and sixth pass, for the exact reference's sky and lamp
    /// terms) `with_normals`.
    pub fn draw(
        ctx: &Context,
        scene: &Scene,
        (camera, light_dir): (&Camera, Vec3),
        (width, height): (u32, u32),
        with_normals: bool,
    ) -> Result<Self> {
        let mut parts = Parts::default();
        // The lamps' shares where any lamp may cast a shadow: one part per four lamps.
        let lamp_parts =
            if scene.shadows && !scene.lamps.is_empty() { scene.lamps.len().div_ceil(4) as u32 } else { 0 };
        let count = if with_normals {
            NORMAL_PARTS + lamp_parts
        } else if scene.shadows {
            NORMAL_PARTS - 2
        } else {
            NORMAL_PARTS - 3
        };
        let drawn = Self::draw_parts(ctx, scene, camera, light_dir, (width, height), count, &mut parts);
        // SAFETY: draw_parts waited for its work (or failed before submitting it).
        unsafe { parts.destroy(ctx) };
        let [light, view, skin, normals, axes, points, lamps_low, lamps_high] = drawn?;
        let lamp_visible = |i: usize| -> [f64; MAX_LAMPS as usize] {
            std::array::from_fn(|k| {
                let part = if k < 4 { &lamps_low } else { &lamps_high };
                part.get(4 * i + k % 4).map_or(1.0, |&v| f64::from(v))
            })
        };
        let vec = |c: &[f32]| DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]));
        let pixels = light
            .chunks(4)
            .zip(view.chunks(4))
            .zip(skin.chunks(4))
            .enumerate()
            .map(|(i, ((l, v), p))| {
                let material = (l[3].round() as usize).checked_sub(1)?;
                Some(Seen {
                    omega_i: vec(l).normalize_or_zero(),
                    omega_r: vec(v).normalize_or_zero(),
                    material,
                    footprint: f64::from(v[3]),
                    albedo: vec(p),
                    normal_up: f64::from(p[3]),
                    normal: normals.get(4 * i..4 * i + 3).map_or(DVec3::ZERO, |n| vec(n).normalize_or_zero()),
                    sun_visible: normals.get(4 * i + 3).map_or(1.0, |&v| f64::from(v)),
                    frame: match (normals.get(4 * i..4 * i + 3), axes.get(4 * i..4 * i + 4)) {
                        (Some(n), Some(a)) => {
                            // As the surface pass has it (surface_shade.glsl's `patch_direction`): the axis made
                            // orthogonal to the interpolated normal.
                            let z = vec(n).normalize_or_zero();
                            let x = (vec(a) - z * z.dot(vec(a))).normalize_or_zero();
                            glam::DMat3::from_cols(x, z.cross(x) * f64::from(a[3]), z)
                        }
                        _ => glam::DMat3::ZERO,
                    },
                    position: points.get(4 * i..4 * i + 3).map_or(DVec3::ZERO, vec),
                    lamp_visible: lamp_visible(i),
                })
            })
            .collect();
        Ok(Self { pixels })
    }

    fn draw_parts(
        ctx: &Context,
        scene: &Scene,
        camera: &Camera,
        light_dir: Vec3,
        (width, height): (u32, u32),
        count: u32,
        parts: &mut Parts,
    ) -> Result<[Vec<f32>; PARTS as usize]> {
        let (shadow, lamp_shadows) = Self::upload(ctx, scene, (camera, light_dir), (width, height), parts)?;
        for part in 0..count {
            parts.pipelines.push(ctx.create_graphics_pipeline(&GraphicsPipelineDesc {
                name: "g-buffer",
                vertex: &shaders::SURFACE_VERT,
                fragment: Some(&shaders::GBUFFER_FRAG),
                specialization: SpecConstants::default().u32(SPEC_GBUFFER_PART, part),
                push_constant_size: 0,
                vertex_stride: std::mem::size_of::<Vertex>() as u32,
                vertex_attributes: &VERTEX_ATTRIBUTES,
                color_format: LINEAR_FORMAT,
                depth: Some((DEPTH_FORMAT, DepthTest::Write)),
                cull_back_faces: crate::render::culls_back_faces(scene.objects.iter().map(|o| &o.mesh)),
                samples: vk::SampleCountFlags::TYPE_1,
                blend: Blend::Replace,
            })?);
        }
        let target = parts.target.insert(OffscreenTarget::with_format(ctx, width, height, LINEAR_FORMAT, true)?);
        let shadow = parts.shadow.insert(shadow);
        let lamp_shadows = parts.lamp_shadows.insert(lamp_shadows);
        let mut out: [Vec<f32>; PARTS as usize] = Default::default();
        for (pipeline, out) in parts.pipelines.iter().zip(&mut out) {
            ctx.one_shot("g-buffer", |cmd| {
                // The map is drawn with the first part; the others find it drawn for the same sun and objects
                // (`ShadowMap::record`) and read it as it is.
                let casts = scene.objects.iter().map(|o| o.casts_shadow);
                shadow.record(ctx, cmd, parts.meshes.iter().zip(casts.clone()));
                lamp_shadows.record(ctx, cmd, parts.meshes.iter().zip(casts));
                target.begin(ctx, cmd);
                begin_rendering(ctx, cmd, &target.view(), Some([0.0; 4]), None);
                for ((mesh, uniforms), maps) in parts.meshes.iter().zip(&parts.uniforms).zip(&parts.maps) {
                    let [compare, depths] = shadow.writes();
                    let [lamp_compare, lamp_depths] = lamp_shadows.writes();
                    let [pigment, normal] = maps.writes();
                    let frame = DescriptorWrite::UniformBuffer(BINDING_FRAME, uniforms);
                    let writes = [frame, compare, depths, lamp_compare, lamp_depths, pigment, normal];
                    ctx.bind(cmd, pipeline, &writes, &[]);
                    mesh.draw(ctx, cmd);
                }
                end_rendering(ctx, cmd);
            })?;
            *out = bytemuck::pod_collect_to_vec(&target.read(ctx)?);
        }
        Ok(out)
    }

    /// Uploads the objects' meshes and their uniforms for `camera` and `light_dir` into `parts`, and returns the
    /// sun's shadow map and the lamps' placed as the surface pass places them (undrawn).
    fn upload(
        ctx: &Context,
        scene: &Scene,
        (camera, light_dir): (&Camera, Vec3),
        (width, height): (u32, u32),
        parts: &mut Parts,
    ) -> Result<(ShadowMap, LampShadows)> {
        let sky_sh = scene.environment.as_ref().map_or([[0.0; 4]; 9], |e| e.irradiance(light_dir));
        let placed: Vec<(Aabb, bool)> = scene
            .objects
            .iter()
            .filter_map(|o| Some((Aabb::of(&o.mesh.vertices)?.moved(o.model), o.casts_shadow)))
            .collect();
        let view_proj = camera.view_projection(width as f32 / height.max(1) as f32);
        let sun_shadow = scene.shadows && scene.sun_strength() > 0.0;
        let frame = sun_shadow.then(|| ShadowFrame::of_objects(light_dir, &placed, view_proj)).flatten();
        let size = if frame.is_some() { SHADOW_SIZE } else { 1 };
        let mut shadow = Guard::new(ctx, ShadowMap::new(ctx, scene.objects.len(), size)?);
        let lamps = crate::light::lamp::LampUniforms::new(&scene.lamps, scene.unit_luminance(light_dir));
        let lamp_frames = match scene.shadows {
            true => crate::render::lamp_shadow::fit_all(&lamps, &placed, view_proj),
            false => Vec::new(),
        };
        let lamps_cast = lamp_frames.iter().any(Option::is_some);
        let (tiles, tile) = if lamps_cast { (lamp_frames.len() as u32, LAMP_SHADOW_SIZE) } else { (0, 1) };
        let mut lamp_shadows = Guard::new(ctx, LampShadows::new(ctx, tiles, scene.objects.len(), tile)?);
        let view = ObjectView {
            camera,
            aspect: width as f32 / height as f32,
            light_dir,
            sun: scene.sun_strength(),
            ambient: scene.ambient,
            sky_sh,
            sky_quadratic: crate::light::prefilter::sky_quadratic(&sky_sh),
            shadow: ShadowFrame::uniforms(frame.as_ref(), size),
            lamps,
            lamp_shadows: LampShadowUniforms::new(&lamp_frames, &lamps, tile),
        };
        let mut all = Vec::with_capacity(scene.objects.len());
        for (i, object) in scene.objects.iter().enumerate() {
            parts.meshes.push(MeshBuffers::new(ctx, &object.mesh, &format!("object {i}"))?);
            parts.maps.push(crate::render::maps::MapImages::new(ctx, &object.mesh.maps)?);
            let size = std::mem::size_of::<SurfaceUniforms>() as u64;
            let desc = BufferDesc::upload(size, vk::BufferUsageFlags::UNIFORM_BUFFER);
            let mut uniforms = ctx.create_buffer(desc, &format!("object {i} uniforms (g-buffer)"))?;
            let material = &scene.materials[object.material];
            let u =
                view.uniforms(object.model, &SurfaceMaterial::of(material), object.material, object.mesh.maps.flags());
            all.push(u);
            let written = uniforms.write(bytemuck::bytes_of(&u));
            parts.uniforms.push(uniforms);
            written?;
        }
        shadow.update(frame, &all)?;
        lamp_shadows.update(&lamp_frames, &all)?;
        Ok((shadow.keep(), lamp_shadows.keep()))
    }

    /// Per material (of `count`): the box of (u, v, w) that its pixels lit from above the surface see, widened by
    /// their median footprint, and their small (5th-percentile) footprint; None for a material no pixel shows lit.
    pub fn reaches(&self, count: usize) -> Vec<Option<(Domain, f64)>> {
        self.reaches_under(count, true, &[])
    }

    /// [`Self::reaches`] under the scene's lights: the sun where `sun`, and each of `lamps` from its own direction
    /// at each pixel's point (the G-buffer drawn `with_normals`) where it lights the pixel, the box widened by 3σ
    /// of the widest Gaussian a lamp's coherence adds to a read there (`lamp::widening_variance`).
    pub fn reaches_under(&self, count: usize, sun: bool, lamps: &[Lamp]) -> Vec<Option<(Domain, f64)>> {
        (0..count)
            .map(|m| {
                let (mut points, mut footprints, mut spread) = (Vec::new(), Vec::new(), 0f64);
                for s in self.pixels.iter().flatten().filter(|s| s.material == m && s.omega_r.z > 0.0) {
                    let before = points.len();
                    if sun && s.omega_i.z > 0.0 {
                        points.push(-s.omega_i - s.omega_r);
                    }
                    for lamp in lamps {
                        let (omega_i, irradiance) = s.lamp(lamp);
                        if irradiance > 0.0 && omega_i.z > 0.0 {
                            points.push(-omega_i - s.omega_r);
                            let coherence = lamp.coherence_at(s.position);
                            spread = spread.max(widening_variance(coherence, DEFAULT_COHERENCE_UM).sqrt());
                        }
                    }
                    if points.len() > before && s.footprint.is_finite() {
                        footprints.push(s.footprint);
                    }
                }
                let domain = Domain::bounding(points)?;
                let small = crate::io::stats::percentile(&mut footprints, FOOTPRINT_PERCENTILE).max(0.0);
                let margin = crate::io::stats::percentile(&mut footprints, 0.5).max(3.0 * spread).max(0.0);
                Some((domain.widened(margin), small))
            })
            .collect()
    }
}

/// The reaches of one or more frames' G-buffers merged, per material: the union of the boxes and the smallest
/// footprint; a material no frame shows lit gets the smallest table (any will do).
pub(crate) fn merge_reaches(frames: &[Vec<Option<(Domain, f64)>>], count: usize) -> Vec<Reach> {
    (0..count)
        .map(|m| {
            let seen: Vec<(Domain, f64)> = frames.iter().filter_map(|f| f.get(m).copied().flatten()).collect();
            let Some(&(first, _)) = seen.first() else {
                return Reach::Seen { domain: Domain::POINT, footprint: crate::render::gbuffer::UNSEEN_FOOTPRINT };
            };
            let domain = seen.iter().fold(first, |d, (e, _)| d.union(e));
            let footprint = seen.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
            Reach::Seen { domain, footprint }
        })
        .collect()
}

/// The footprint a table for an unseen material is sized with (a coarse one: nothing reads it).
pub(crate) const UNSEEN_FOOTPRINT: f64 = 0.05;
