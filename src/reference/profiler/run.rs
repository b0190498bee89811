//! The profiler's loop: for each [`Config`], prepare the subject's materials, draw warm-up and timed frames,
//! count the fetches, and measure the image against the exact reference of its size (computed once per size).
//! The command line parses and prints; everything measured is decided here.

use std::path::PathBuf;
use std::time::Instant;

use ash::vk;
use glam::DVec3;

use crate::display::AutoExposure;
use crate::error::{Error, Result};
use crate::gpu::interface::MAX_LAMPS;
use crate::gpu::vk::Context;
use crate::io::stats::Spread;
use crate::material::Settings;
use crate::material::{Material, Reach};
use crate::physics::heightfield::HeightField;
use crate::physics::illuminant::Illuminant;
use crate::physics::{optics, spectrum};
use crate::reference::exact_image;
use crate::reference::exact_image::{PixelLamp, PixelQuery, ReferenceImage, ReferenceJob, ReferenceMaterial};
use crate::reference::profiler::{Config, Row, TableSummary, MAX_SIZE};
use crate::render::capture::{material_inputs, prepare_materials, scene_objects, scene_reaches};
use crate::render::diffraction::Upload;
use crate::render::gbuffer::{GBuffer, Seen};
use crate::render::map::{MapShader, MapSpec};
use crate::render::offscreen::FrameTarget;
use crate::render::visibility::ShadingPath;
use crate::render::workload::{Counts, FrameSample, MapWorkload, ProbeResult, SceneWorkload, Workload};
use crate::render::SceneView;
use crate::scene::Scene;

/// What is profiled.
pub enum Subject {
    /// The BRDF map of a height field lit from `light` (the patch frame), its material `settings` before each
    /// configuration's overrides; `name` and `light_deg` (θ_i, φ_i) describe it.
    Map { heightfield: HeightField, light: DVec3, settings: Settings, name: String, light_deg: (f64, f64) },
    /// A scene; its images are `aspect` (height over width) as tall as wide; with `any_view`, its baked tables
    /// serve any light and view (the viewer's and a sequence's), else the profiled frame's views.
    Scene { scene: Box<Scene>, name: String, aspect: f64, any_view: bool },
}

impl Subject {
    /// One line for the report's header.
    pub fn describe(&self) -> String {
        match self {
            Subject::Map { heightfield: hf, settings, name, light_deg: (theta, phi), .. } => {
                let (lx, ly) = hf.size_um();
                format!(
                    "BRDF map of {name} ({}×{} px, {lx:.1}×{ly:.1} µm), light θ_i = {theta}°, φ_i = {phi}°, coherence {} µm",
                    hf.nx, hf.ny, settings.coherence_um
                )
            }
            Subject::Scene { scene, name, any_view, .. } => format!(
                "scene {name} ({} objects, {} materials; each material's approach, Taylor order, Δλ and window radius set \
                 by the configuration{})",
                scene.objects.len(),
                scene.materials.len(),
                if *any_view { "; baked tables for any light and view" } else { "" }
            ),
        }
    }

    /// A few words for a plot's title.
    pub fn short_name(&self) -> String {
        match self {
            Subject::Map { name, .. } => {
                let file = std::path::Path::new(name).file_name().map_or(String::new(), |n| n.to_string_lossy().into());
                format!("BRDF map of {file}")
            }
            Subject::Scene { name, .. } => format!("scene {name}"),
        }
    }

    /// The image of `config`: a map is square; a scene's height follows the width at its aspect.
    pub fn image_size(&self, config: &Config) -> (u32, u32) {
        match self {
            Subject::Map { .. } => (config.size, config.size),
            Subject::Scene { aspect, .. } => {
                (config.size, ((f64::from(config.size) * aspect).round() as u32).clamp(1, MAX_SIZE))
            }
        }
    }

    /// Refuses a map shader asked of a scene (a BRDF map's pipeline is as asked, else the device's:
    /// [`MapShader::for_device`]) and a frame target asked of a map (a map's pixels are linear).
    pub fn check_frame_keys(&self, config: &Config) -> Result<()> {
        match self {
            Subject::Scene { .. } if config.shader.is_some() => {
                Err(Error::setting("sweep", "--sweep shader= is for BRDF maps: a scene is always rasterised".into()))
            }
            Subject::Map { .. } if config.target.is_some() => Err(Error::setting(
                "sweep",
                "--sweep target= is for scenes (what `render` or `view` draws into): a BRDF map is linear".into(),
            )),
            Subject::Map { .. } if config.path.is_some() => Err(Error::setting(
                "sweep",
                "--sweep path= is for scenes: a BRDF map has no triangles to raster".into(),
            )),
            Subject::Scene { .. }
                if config.path == Some(ShadingPath::Visibility) && config.target == Some(FrameTarget::Display) =>
            {
                Err(Error::setting(
                    "sweep",
                    "--sweep path=visibility draws linear frames (as `render` does): not with target=display".into(),
                ))
            }
            _ => Ok(()),
        }
    }

    /// Samples per pixel of the timed frames: as asked, else the scene's; a map has one.
    pub fn frame_samples(&self, asked: Option<u32>) -> Result<u32> {
        match self {
            Subject::Map { .. } if asked.is_some_and(|n| n > 1) => Err(Error::setting(
                "samples",
                "--samples is for scenes: a BRDF map's pixels are directions (--reference-samples averages them)"
                    .into(),
            )),
            Subject::Map { .. } => Ok(1),
            Subject::Scene { scene, .. } => Ok(asked.unwrap_or(scene.render.samples)),
        }
    }

    /// The exposure the error is measured at unless one is asked for: the scene's, a map's 0; None where the
    /// scene sets none (then it is measured from the first reference image).
    pub fn exposure(&self) -> Option<f64> {
        match self {
            Subject::Map { .. } => Some(0.0),
            Subject::Scene { scene, .. } => scene.render.exposure_ev,
        }
    }

    /// The materials `config` asks for (the Taylor terms and everything else the GPU needs). A scene's materials
    /// are sized (baked tables) for the views its frame at `size` shows.
    fn prepare(&self, ctx: &Context, config: &Config, size: (u32, u32), options: &Options) -> Result<Vec<Material>> {
        match self {
            Subject::Map { heightfield, light, settings, .. } => {
                let reach = Reach::Map { light: *light, size: config.size, filtered: map_filtered(options) };
                Ok(vec![Material::prepare(heightfield, config.overrides.apply(*settings), &reach)?])
            }
            Subject::Scene { scene, any_view, .. } => {
                let reaches = if *any_view {
                    vec![Reach::ANY]
                } else {
                    scene_reaches(ctx, scene, &[(scene.camera, scene.light_dir)], size.0, size.1)?
                };
                prepare_materials(scene, &config.overrides, &reaches)
            }
        }
    }

    /// Each material's coherence length and light under `config`: what the exact reference depends on besides the
    /// size (every other setting is an approximation the reference does without).
    fn reference_lights(&self, config: &Config) -> Vec<(f64, Illuminant)> {
        let of = |s: Settings| (s.coherence_um, s.illuminant);
        match self {
            Subject::Map { settings, .. } => vec![of(config.overrides.apply(*settings))],
            Subject::Scene { scene, .. } => {
                scene.materials.iter().map(|m| of(scene.material_settings(m, &config.overrides))).collect()
            }
        }
    }

    /// The exact reference at `size` under each material's coherence length and light. With `samples` > 1 it is evaluated at `samples`² positions per pixel (an
    /// image that many times larger) and averaged.
    fn reference(
        &self,
        ctx: &Context,
        size: (u32, u32),
        lights: &[(f64, Illuminant)],
        options: &ReferenceOptions,
    ) -> Result<ReferenceImage> {
        let samples = options.samples;
        let fine = (size.0 * samples, size.1 * samples);
        let mut job = match self {
            Subject::Map { heightfield, light, .. } => ReferenceJob {
                materials: vec![ReferenceMaterial { heightfield, coherence_um: lights[0].0, illuminant: lights[0].1 }],
                width: fine.0,
                height: fine.1,
                pixels: ReferenceJob::map_pixels(fine.0, *light),
            },
            Subject::Scene { scene, .. } => ReferenceJob {
                materials: scene
                    .materials
                    .iter()
                    .zip(lights)
                    .map(|(m, &(coherence_um, illuminant))| ReferenceMaterial {
                        heightfield: &m.heightfield,
                        coherence_um,
                        illuminant,
                    })
                    .collect(),
                width: fine.0,
                height: fine.1,
                pixels: scene_pixels(ctx, scene, fine, lights)?,
            },
        };
        let turn = match self {
            Subject::Scene { scene, .. } if samples > 1 => normal_turn(ctx, scene, fine, samples)?,
            _ => None,
        };
        let sampled = options.pixels.map(|n| job.keep_random_pixels(n, samples));
        let mut image = job.compute(options.cache.as_deref())?.downsample(samples);
        if let Some((median, p90)) = turn {
            image.description += &format!(
                "; within a pixel the diffracting surface's normal turns by up to {median:.1}° (median over its \
                 pixels; 90th percentile {p90:.1}°): what a footprint filter must follow"
            );
        }
        if let Some((kept, covered)) = sampled {
            image.sampled = sampled;
            image.description += &format!(
                "; {kept} of the {covered} covered pixels, chosen at random (seed {:#x}): ΔE00 figures are estimates",
                exact_image::SAMPLE_SEED
            );
        }
        Ok(image)
    }

    /// The GPU side of one configuration's frames (a map's pipeline and a scene's target as `config` asks).
    fn workload<'a>(
        &'a self,
        ctx: &Context,
        materials: &'a [Material],
        (size, samples): ((u32, u32), vk::SampleCountFlags),
        config: &Config,
        options: &Options,
    ) -> Result<Box<dyn Workload + 'a>> {
        self.check_frame_keys(config)?;
        Ok(match self {
            Subject::Map { light, .. } => {
                let shader = config.shader.unwrap_or_else(|| MapShader::for_device(ctx));
                let spec = MapSpec {
                    material: &materials[0],
                    size: size.0,
                    light: *light,
                    footprint: map_filtered(options),
                    shader,
                };
                Box::new(MapWorkload::new(ctx, &spec)?)
            }
            Subject::Scene { scene, .. } => {
                let view = SceneView::of(scene);
                let inputs = material_inputs(scene, materials);
                let frame = (samples, config.target.unwrap_or_default(), config.path.unwrap_or_default());
                Box::new(SceneWorkload::new(ctx, inputs, scene_objects(scene), view, size, frame)?)
            }
        })
    }
}

/// Whether a baked map averages each pixel over its footprint: against an area-sampled reference, as the
/// reference averages its pixels.
fn map_filtered(options: &Options) -> bool {
    options.reference.as_ref().is_some_and(|r| r.samples > 1)
}

/// How far the normal of the diffracting surfaces turns within a pixel of `scene` at `fine` / `samples`: per pixel
/// whose `samples`² positions all show one, the largest angle between a position's normal and the first's, in
/// degrees; (median, 90th percentile), or None where no pixel does.
fn normal_turn(ctx: &Context, scene: &Scene, fine: (u32, u32), samples: u32) -> Result<Option<(f64, f64)>> {
    let gbuffer = GBuffer::draw(ctx, scene, (&scene.camera, scene.light_dir), fine, true)?;
    let normal = |x: u32, y: u32| {
        gbuffer.pixels[(y * fine.0 + x) as usize].filter(|seen| !scene.materials[seen.material].matte).map(|s| s.normal)
    };
    let mut turns: Vec<f64> = Vec::new();
    for py in 0..fine.1 / samples {
        for px in 0..fine.0 / samples {
            let positions: Option<Vec<DVec3>> = (0..samples * samples)
                .map(|k| normal(px * samples + k % samples, py * samples + k / samples))
                .collect();
            if let Some(normals) = positions {
                let first = normals[0];
                turns.push(
                    normals.iter().map(|n| first.dot(*n).clamp(-1.0, 1.0).acos().to_degrees()).fold(0.0, f64::max),
                );
            }
        }
    }
    if turns.is_empty() {
        return Ok(None);
    }
    let median = crate::io::stats::percentile(&mut turns, 0.5);
    Ok(Some((median, crate::io::stats::percentile(&mut turns, 0.9))))
}

/// Each lamp of `scene` as a pixel that shows `seen` sees it: its patch-frame direction, the weight of its light
/// (its irradiance at normal incidence over Ω_sun times the frame's unit luminance `unit`: what the sun's is 1 of,
/// times the share of its disc no shadow hides there)
/// and, where the material's coherence `material_um` follows the light and the lamp's is shorter there, the
/// widening of its lobes — as glsl/include/lamps.glsl and surface_shade.glsl's `lamp_colour` have them.
fn lamp_lights(scene: &Scene, seen: &Seen, unit: f64, material_um: f64) -> [PixelLamp; MAX_LAMPS as usize] {
    let mut out = crate::reference::exact_image::NO_LAMPS;
    let follows = crate::light::lamp::follows_light(material_um);
    for ((lamp, slot), visible) in scene.lamps.iter().zip(&mut out).zip(seen.lamp_visible) {
        let (omega_i, irradiance) = seen.lamp(lamp);
        *slot = PixelLamp {
            omega_i,
            weight: irradiance / unit / optics::SUN_SOLID_ANGLE * visible,
            widening: match follows {
                true => crate::light::lamp::widening_variance(lamp.coherence_at(seen.position), material_um),
                false => 0.0,
            },
        };
    }
    out
}

/// What each pixel of `scene` at `size` asks of the exact reference: the directions come from the GPU's
/// rasteriser (the same triangles, the same fragments as the frames); everything after them (the BRDF, the
/// pigment term) is evaluated on the CPU.
fn scene_pixels(
    ctx: &Context,
    scene: &Scene,
    size: (u32, u32),
    lights: &[(f64, Illuminant)],
) -> Result<Vec<Option<PixelQuery>>> {
    // The pigment is lit by the light's white (the shaders' `params.light_white`).
    let whites: Vec<DVec3> = lights.iter().map(|&(_, illuminant)| spectrum::white_rgb(illuminant)).collect();
    let gbuffer = GBuffer::draw(ctx, scene, (&scene.camera, scene.light_dir), size, true)?;
    let ambient = f64::from(scene.ambient);
    let unit = scene.unit_luminance(scene.light_dir);
    // The environment's irradiance, as the shaders have it (the same nine coefficients, in f32).
    let sky = crate::physics::sh::Irradiance {
        coefficients: scene
            .environment
            .as_ref()
            .map_or([[0.0; 4]; 9], |e| e.irradiance(scene.light_dir))
            .map(|c| DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]))),
    };
    // The environment's diffraction, from the materials' moments (the same as the frames': light::prefilter) and
    // the environment's l ≤ 2 radiance as the shaders have it.
    let quadratic = crate::light::prefilter::Quadratic::of_irradiance(&sky);
    // The environment without its sun, which each pixel reflects at its mirror direction (the surface pass's map).
    let panorama = match &scene.environment {
        Some(e) => e.panorama(scene.light_dir, false, crate::render::scene_gpu::LIGHTING_SKY_WIDTH)?,
        None => None,
    };
    let moments: Vec<Option<crate::light::prefilter::Moments>> = scene
        .materials
        .iter()
        .zip(lights)
        .map(|(m, &(coherence_um, illuminant))| {
            if scene.environment.is_none() || m.matte {
                return Ok(None);
            }
            let settings = Settings { coherence_um, illuminant, ..m.settings };
            crate::material::moments_of(&m.heightfield, &settings).map(Some)
        })
        .collect::<Result<_>>()?;
    Ok(gbuffer
        .pixels
        .iter()
        .map(|seen| {
            let Seen { omega_i, omega_r, material, albedo, normal_up, normal, sun_visible, frame, .. } = (*seen)?;
            // A matte material's pixels (a ground's pigment) are the same in every approach: they are left out of
            // the comparison, whose figures are then the diffracting surfaces' alone.
            if scene.materials[material].matte {
                return None;
            }
            let lit = optics::Lit { sun_visible, coated: true };
            let sky_diffraction = moments[material].as_ref().filter(|_| omega_r.z > 0.0).map_or(DVec3::ZERO, |m| {
                let d = frame * DVec3::new(-omega_r.x, -omega_r.y, omega_r.z);
                let mirror = match &panorama {
                    Some((map, scale, rotation)) => map.bilinear(d, *rotation) * *scale,
                    None => quadratic.radiance(d).max(DVec3::ZERO),
                };
                m.radiance(omega_r, &quadratic, frame, mirror)
            });
            let lamps = lamp_lights(scene, seen.as_ref()?, unit, lights[material].0);
            let lamps_rgb: DVec3 = lamps
                .iter()
                .filter(|l| l.weight > 0.0)
                .map(|l| optics::pigment_rgb(l.omega_i, omega_r, 0.0, albedo, 0.0, optics::Lit::OPEN) * l.weight)
                .sum();
            let extra_rgb = optics::pigment_rgb(omega_i, omega_r, normal_up, albedo, ambient, lit) * whites[material]
                + optics::pigment_sky_rgb(omega_r, albedo, sky.over_pi(normal), true)
                + sky_diffraction
                + lamps_rgb * whites[material];
            let diffracted = sun_visible;
            let extra_xyz = crate::physics::colour::linear_srgb_to_xyz(extra_rgb);
            Some(PixelQuery { omega_i, omega_r, material, diffracted, lamps, extra_xyz })
        })
        .collect())
}

/// The exact reference's settings.
#[derive(Clone, Debug)]
pub struct ReferenceOptions {
    /// Positions per pixel axis.
    pub samples: u32,
    /// Evaluate and compare only this many pixels, chosen at random among those the surface covers (None: all).
    pub pixels: Option<usize>,
    /// Folder of cached reference images (None: compute and keep nothing).
    pub cache: Option<PathBuf>,
}

/// How every configuration is measured.
pub struct Options {
    /// Timed frames (at least one) after `warmup` untimed ones.
    pub frames: u32,
    pub warmup: u32,
    /// Exposure (EV) of the images as displayed, at which ΔE00 is measured; None: measured from the first
    /// reference image as `render` measures a frame ([`crate::display::AutoExposure`]).
    pub exposure: Option<f64>,
    /// Samples per pixel of a scene's timed frames.
    pub samples: vk::SampleCountFlags,
    /// None: time only, no error columns.
    pub reference: Option<ReferenceOptions>,
    /// The device's texel-fetch peak, for each row's share of it.
    pub probe: Option<ProbeResult>,
}

/// What the loop tells its caller as it goes.
pub enum Progress<'a> {
    /// Configuration `index` of `count` (from 1) is at step `what` (transient).
    Step { index: usize, count: usize, label: &'a str, what: &'a str },
    /// A line to keep.
    Line(String),
}

/// Every configuration's row, and the description of each reference image by size.
pub struct Report {
    pub rows: Vec<Row>,
    pub references: Vec<((u32, u32), String)>,
    /// The exposure ΔE00 was measured at, and whether it was measured from the reference (None: no reference).
    pub exposure: Option<(f64, bool)>,
}

/// What an exact reference image depends on in a profile: its size and each material's coherence length and light.
type ReferenceKey = ((u32, u32), Vec<(f64, Illuminant)>);

/// Measures `subject` under each of `configs`.
pub fn run(
    ctx: &Context,
    subject: &Subject,
    configs: &[Config],
    options: &Options,
    progress: &dyn Fn(Progress<'_>),
) -> Result<Report> {
    let mut exposure = options.exposure.map(|ev| (ev, false));
    // One reference per size and coherence lengths (a sweep of coherence_um needs one each).
    let mut references: Vec<(ReferenceKey, ReferenceImage)> = Vec::new();
    let mut rows = Vec::with_capacity(configs.len());
    let count = configs.len();
    for (i, config) in configs.iter().enumerate() {
        let index = i + 1;
        let label = config.label();
        let step = |what: &str| progress(Progress::Step { index, count, label: &label, what });
        let in_config = |e: Error| Error::Configuration { label: label.clone(), cause: Box::new(e) };
        let size = subject.image_size(config);
        step("precomputing");
        let start = Instant::now();
        let materials = subject.prepare(ctx, config, size, options).map_err(in_config)?;
        let precompute_ms = start.elapsed().as_secs_f64() * 1e3;
        for line in materials.iter().filter_map(Material::table_line) {
            progress(Progress::Line(format!("[{index}/{count}] {line}")));
        }
        let key = (size, subject.reference_lights(config));
        if let Some(r) = options.reference.as_ref().filter(|_| !references.iter().any(|(k, _)| *k == key)) {
            let start = Instant::now();
            let image = subject.reference(ctx, size, &key.1, r)?;
            let seconds = start.elapsed().as_secs_f64();
            progress(Progress::Line(format!(
                "reference {}×{} ({seconds:.1} s): {}",
                size.0, size.1, image.description
            )));
            references.push((key.clone(), image));
        }
        let reference = references.iter().find(|(k, _)| *k == key).map(|r| &r.1);
        // Set, or measured once from the first reference (its lit pixels' luminance) and kept for every row.
        if exposure.is_none() {
            exposure = reference.map(|r| {
                let lit = r.xyz.iter().zip(&r.mask).filter(|(_, &m)| m).map(|(xyz, _)| xyz.y);
                (AutoExposure::of_luminance(lit).map_or(0.0, |a| a.ev), true)
            });
        }
        let ev = exposure.map_or(0.0, |(ev, _)| ev);
        let measured = Measured { materials: &materials, precompute_ms, reference, exposure: ev };
        let row = measure_config(ctx, subject, config, size, options, &measured, &step).map_err(in_config)?;
        progress(Progress::Line(format!(
            "[{index}/{count}] {}: GPU {} ms{}",
            row.label(),
            row.gpu_ms.map_or("n/a".into(), |s| crate::reference::profiler::ms(s.median)),
            row.error.map(|e| format!(", ΔE00 mean {}", crate::reference::profiler::mean_de(&e))).unwrap_or_default()
        )));
        rows.push(row);
    }
    let references = references.into_iter().map(|((size, _), image)| (size, image.description)).collect();
    Ok(Report { rows, references, exposure })
}

/// What one configuration is measured with and against.
struct Measured<'a> {
    materials: &'a [Material],
    precompute_ms: f64,
    reference: Option<&'a ReferenceImage>,
    /// The exposure ΔE00 is measured at.
    exposure: f64,
}

fn measure_config(
    ctx: &Context,
    subject: &Subject,
    config: &Config,
    size: (u32, u32),
    options: &Options,
    with: &Measured<'_>,
    step: &dyn Fn(&str),
) -> Result<Row> {
    let Measured { materials, precompute_ms, reference, exposure } = *with;
    let target = config.target.unwrap_or(FrameTarget::Linear);
    let samples = match config.samples {
        Some(n) => ctx.sample_count(subject.frame_samples(Some(n))?, target.format())?,
        None => options.samples,
    };
    let mut workload = subject.workload(ctx, materials, (size, samples), config, options)?;
    let map_shader = workload.map_shader();
    let measured = frames(ctx, workload.as_mut(), options, step);
    let uploads = workload.uploads();
    // A display target's frames are exposed and encoded for a screen: only linear frames meet the reference.
    let reference = reference.filter(|_| target == FrameTarget::Linear);
    let result = measured.and_then(|(samples, image, fetches)| {
        let error = reference.map(|r| exact_image::image_error(r, &image, exposure)).transpose()?;
        Ok((samples, error, fetches))
    });
    // SAFETY: every frame was waited for.
    unsafe { workload.destroy(ctx) };
    let (frame_samples, error, fetches) = result?;
    let samples_per_pixel = samples.as_raw();
    let samples = frame_samples;
    let gpu: Vec<f64> = samples.iter().filter_map(FrameSample::gpu_ms).collect();
    let gpu_ms = (gpu.len() == samples.len()).then(|| Spread::of(&gpu)).flatten();
    let passes = pass_spreads(&samples);
    let cpu_ms = Spread::of(&samples.iter().map(|s| s.cpu_ms).collect::<Vec<_>>())
        .ok_or_else(|| Error::Invalid("no timed frame".into()))?;
    let total_fetches: u64 = fetches.iter().map(|c| u64::from(c.fetches)).sum();
    // Covered pixels are those shaded at least once (the counting shaders run only where the surface is seen).
    let covered = fetches.iter().filter(|c| c.shaded > 0).count();
    let shaded: u64 = fetches.iter().map(|c| u64::from(c.shaded)).sum();
    let fetches_per_s = gpu_ms.filter(|s| s.median > 0.0).map(|s| total_fetches as f64 / (s.median * 1e-3));
    let m = &materials[0];
    Ok(Row {
        config: *config,
        settings: m.settings,
        width: size.0,
        height: size.1,
        samples: samples_per_pixel,
        map_shader,
        frame_target: matches!(subject, Subject::Scene { .. }).then_some(target),
        shading_path: matches!(subject, Subject::Scene { .. }).then_some(config.path.unwrap_or_default()),
        order: m.plan.map(|p| p.order),
        lambda_count: m.sampling.count,
        taps: 2 * m.window.radius_x.max(m.window.radius_y) as u32 + 1,
        frames: samples.len(),
        precompute_ms,
        gpu_ms,
        passes,
        upload: uploads.iter().copied().reduce(|a, b| Upload {
            bytes: a.bytes + b.bytes,
            gpu_ms: a.gpu_ms.zip(b.gpu_ms).map(|(x, y)| x + y),
            wall_ms: a.wall_ms + b.wall_ms,
        }),
        cpu_ms,
        fragment_invocations: samples.last().and_then(|s| s.fragment_invocations),
        shaded_per_pixel: shaded as f64 / covered.max(1) as f64,
        fetches_per_pixel: total_fetches as f64 / f64::from(size.0 * size.1),
        fetches_per_s,
        // The probe measures unfiltered RG32F fetches, the Taylor terms' reads; the baked table's filtered RGBA32F
        // reads have no probe of their own, and a share of the wrong roof (it read 116–196 % on lavapipe) is none.
        roofline_fraction: fetches_per_s
            .zip(options.probe.as_ref())
            .filter(|_| m.settings.approach != crate::material::Approach::Baked)
            .map(|(rate, p)| rate / p.fetches_per_s),
        error,
        table: TableSummary::of(m),
    })
}

/// The median (and spread) of each pass's time over the frames, passes in frame order; empty unless every frame
/// timed the same passes.
fn pass_spreads(samples: &[FrameSample]) -> Vec<(String, Spread)> {
    let Some(first) = samples.first().and_then(|s| s.times.as_ref()) else { return Vec::new() };
    let names: Vec<&str> = first.passes.iter().map(|p| p.name.as_str()).collect();
    let same = |s: &FrameSample| s.times.as_ref().is_some_and(|t| t.passes.iter().map(|p| &p.name).eq(names.iter()));
    if !samples.iter().all(same) {
        return Vec::new();
    }
    (0..names.len())
        .filter_map(|i| {
            let ms: Vec<f64> = samples.iter().filter_map(|s| s.times.as_ref()).map(|t| t.passes[i].ms).collect();
            Some((names[i].to_string(), Spread::of(&ms)?))
        })
        .collect()
}

/// Warm-up, timed frames, the last frame's image and one counting frame.
fn frames(
    ctx: &Context,
    workload: &mut dyn Workload,
    options: &Options,
    step: &dyn Fn(&str),
) -> Result<(Vec<FrameSample>, Vec<f32>, Vec<Counts>)> {
    for w in 0..options.warmup {
        step(&format!("warm-up {}/{}", w + 1, options.warmup));
        workload.frame(ctx)?;
    }
    let mut samples = Vec::with_capacity(options.frames as usize);
    for f in 0..options.frames {
        step(&format!("frame {}/{}", f + 1, options.frames));
        samples.push(workload.frame(ctx)?);
    }
    let image = workload.image(ctx)?;
    if let Some(bad) = image.iter().position(|v| !v.is_finite()) {
        return Err(Error::Precision(format!(
            "pixel {} of the image is not a finite number (a bug in diffract)",
            bad / 4
        )));
    }
    step("counting fetches");
    let fetches = workload.count_fetches(ctx)?;
    Ok((samples, image, fetches))
}
