//! The numbers the shaders and the Rust side must agree on: specialization-constant ids, descriptor bindings
//! (all in set 0), workgroup sizes, approach ids, the physical constants both sides use, and the push-constant
//! blocks. This file is their one source: build.rs reads every `pub const NAME: u32 | f64 = value;` line here and
//! writes the shaders' `interface.glsl` (`#define NAME value`) into `$OUT_DIR` before compiling them, so a number
//! changes in one place and the GLSL follows.

// Specialization constants of the diffraction shaders (glsl/include/params.glsl).
/// Taylor terms F_0..F_{TERMS−1}; the baked approach: Chebyshev terms in w.
pub const SPEC_TERMS: u32 = 0;
/// Window taps either side of the nearest DFT bin.
pub const SPEC_WINDOW_RADIUS: u32 = 1;
/// Uniform wavelength samples (FLSS, PQ, gem's specular spot).
pub const SPEC_LAMBDA_COUNT: u32 = 2;
/// The approach (`Approach::id`).
pub const SPEC_APPROACH: u32 = 3;
/// 0: linear scene-referred RGB out; 1: exposure and the sRGB transfer function applied in the shader.
pub const SPEC_DISPLAY_OUTPUT: u32 = 4;
/// The counting variants' row stride of the per-pixel fetch counters.
pub const SPEC_COUNT_STRIDE: u32 = 5;
/// 1: the baked shaders filter over the pixel's footprint; 0: they read the table's finest level.
pub const SPEC_FOOTPRINT: u32 = 8;
/// `map.comp`'s workgroup side (`render::diffraction::map_workgroup`): side² invocations, one per pixel.
pub const SPEC_MAP_LOCAL_SIZE: u32 = 9;
/// Where the surface pass diffracts the environment (the material has its moments): `SKY_DIFFRACTION_*`. With
/// `SKY_DIFFRACTION_NONE` the code is compiled out (a CPU device runs both sides of a branch, so a uniform switch
/// alone would still cost every pixel).
pub const SPEC_SKY_DIFFRACTION: u32 = 10;
/// No environment's diffraction (the material has no moments).
pub const SKY_DIFFRACTION_NONE: u32 = 0;
/// The smooth part at the vertices (the `surface_sky.vert` variant reads the moments), interpolated; the
/// specular reflection of the environment's map per pixel.
pub const SKY_DIFFRACTION_VERTEX: u32 = 1;
/// All of it per pixel (the fragment shader reads the moments).
pub const SKY_DIFFRACTION_PIXEL: u32 = 2;
/// 1: the surface pass looks up the sun's shadow map (the view casts shadows); 0 compiles the lookups out (a
/// CPU device would run the soft shadows' loops for nothing).
pub const SPEC_SHADOWS: u32 = 11;
/// Texels one read of the baked table takes (`physics::baked::sample::MipFilter::texels_per_read`): what the
/// counting variants add per read.
pub const SPEC_TABLE_TEXELS: u32 = 12;

// Specialization constants of single shaders.
/// Which part of the G-buffer `gbuffer.frag` writes.
pub const SPEC_GBUFFER_PART: u32 = 0;
/// The fetch probe's texture layers and taps per axis (`fetch_probe.frag`).
pub const SPEC_PROBE_LAYERS: u32 = 0;
pub const SPEC_PROBE_TAPS: u32 = 1;
/// The self-test's scale factor (`selftest.comp`).
pub const SPEC_SELFTEST_SCALE: u32 = 0;

// Descriptor bindings.
/// A pass's per-object or per-frame uniforms (surface, G-buffer, preview).
pub const BINDING_FRAME: u32 = 0;
/// The diffraction parameters' uniform block (`DiffractionParams`).
pub const BINDING_PARAMS: u32 = 1;
/// The patch's texture: Taylor terms or the baked table (and the fetch probe's texture).
pub const BINDING_TABLE: u32 = 2;
/// The wavelength table (colour-matching functions × illuminant).
pub const BINDING_SPECTRUM: u32 = 3;
/// The counting variants' per-pixel fetch counters.
pub const BINDING_FETCH_COUNTS: u32 = 4;
/// The BRDF evaluation's queries and results (`brdf_eval.comp`).
pub const BINDING_QUERIES: u32 = 5;
pub const BINDING_RESULTS: u32 = 6;
/// `map.comp`'s storage image (the map written by a compute shader).
pub const BINDING_MAP_IMAGE: u32 = 7;
/// The sun's shadow map (a depth-comparison sampler: `render::shadow`).
pub const BINDING_SHADOW: u32 = 8;
/// The environment map drawn behind a scene (`render::background`).
pub const BINDING_ENVIRONMENT: u32 = 9;
/// The same shadow map read as depths (its blocker search: `render::shadow`).
pub const BINDING_SHADOW_DEPTH: u32 = 10;
/// `map_env.comp`'s distributions (each a `env_light::Distribution2D`'s CDF then its densities: the baked
/// table's texels, the environment's) and the environment's radiance.
pub const BINDING_TABLE_SAMPLING: u32 = 11;
pub const BINDING_ENV_SAMPLING: u32 = 12;
pub const BINDING_ENV_RADIANCE: u32 = 13;
/// A material's moments against the environment's light (`env_prefilter::Moments`), read by the surface pass.
pub const BINDING_MOMENTS: u32 = 14;
/// The environment without its sun, read by the surface pass at each pixel's mirror direction (its specular
/// reflection: `render::surface`, `glsl/include/sky_diffraction.glsl`).
pub const BINDING_ENV_LIGHT: u32 = 15;
/// The visibility buffer (`render::visibility`): each sample's object and triangle (`VISIBILITY_OBJECT_SHIFT`), the
/// vertex shader's outputs per vertex (`VERTEX_OUTPUT_VEC4S` each), and the mesh's indices, which the shading pass
/// reads to rebuild a pixel's inputs.
pub const BINDING_VISIBILITY_IDS: u32 = 16;
pub const BINDING_VERTEX_OUTPUTS: u32 = 17;
pub const BINDING_MESH_INDICES: u32 = 18;
/// The visibility buffer's edge pass (`render::visibility`): the pixels that see more than one of an object's
/// triangles, listed by the shading pass, and the frame's one-sample colour it adds their further triangles to.
pub const BINDING_VISIBILITY_EDGES: u32 = 19;
pub const BINDING_VISIBILITY_TARGET: u32 = 20;
/// Invocations per work group of the edge pass (and pixels per group the shading pass counts).
pub const VISIBILITY_EDGE_GROUP: u32 = 64;
/// A visibility sample's id: (the object's index + 1) << this | the triangle's index in its mesh; 0 where no
/// object is. So at most 255 objects of at most 2²⁴ − 1 triangles each.
pub const VISIBILITY_OBJECT_SHIFT: u32 = 24;
/// vec4s per vertex in the vertex outputs: the clip position, then the surface shader's inputs.
pub const VERTEX_OUTPUT_VEC4S: u32 = 7;
/// The most samples per pixel the visibility buffer's shading pass reads.
pub const VISIBILITY_MAX_SAMPLES: u32 = 8;
/// The moments' grid per axis and texture layers (`env_prefilter::MOMENT_GRID`, `MOMENT_LAYERS`).
pub const MOMENT_GRID: u32 = 32;
pub const MOMENT_LAYERS: u32 = 23;
/// The R2 sequence's steps in 32-bit fixed point, 2³²/g and 2³²/g² for the plastic number g (`env_light::r2`).
pub const R2_STEP_X: u32 = 3242174889;
pub const R2_STEP_Y: u32 = 2447445413;
/// The self-test's input and output buffers (`selftest.comp`).
pub const BINDING_SELFTEST_IN: u32 = 0;
pub const BINDING_SELFTEST_OUT: u32 = 1;

// Workgroup sizes.
/// Invocations per workgroup of every compute shader (`local_size_x`); dispatches divide by it.
pub const LOCAL_SIZE_X: u32 = 64;

// Approach ids: the value of SPEC_APPROACH (`shading::Approach::id`).
pub const APPROACH_FLSS: u32 = 0;
pub const APPROACH_NMM: u32 = 1;
pub const APPROACH_PQ: u32 = 2;
pub const APPROACH_GEM: u32 = 3;
pub const APPROACH_BAKED: u32 = 4;

// Physical constants (f64 on the CPU, float literals in the shaders).
/// π, for the shaders (Rust code uses `std::f64::consts::PI`).
#[allow(clippy::approx_constant, dead_code)]
pub const PI: f64 = 3.141_592_653_589_793;
/// Refractive index of snake skin (model.md §1.9: "close to the measured value from snake sheds").
pub const SKIN_INDEX: f64 = 1.5;
/// The sun's solid angle (0.53° across), sr: its diffuse contribution relative to its glint in a mirror.
pub const SUN_SOLID_ANGLE: f64 = 6.8e-5;
/// The largest factor a shadow lookup's normal offset grows by as the light grazes a surface (1/cos θ_i up to
/// this; `render::shadow`).
pub const SHADOW_MAX_OFFSET_GROWTH: f64 = 4.0;
/// How much finer than a pixel's footprint F the baked table's mip level is chosen, log2 √3 (see
/// `physics::baked::sample::FOOTPRINT_LOD_BIAS`).
pub const FOOTPRINT_LOD_BIAS: f64 = 0.792_481_250_360_578_1;

/// `map.frag`'s and `map.comp`'s push constants (`MapPush`): the map's square in pixels and its offset in the
/// target; `origin`, the first pixel a compute dispatch covers (a band's first row; the fragment shader ignores it).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MapPush {
    pub size: [f32; 2],
    pub offset: [f32; 2],
    pub origin: [f32; 2],
}

/// `map_env.comp`'s push constants (`EnvMapPush`): the map's square, offset and band origin as in [`MapPush`]; the
/// table proposal's texels (`nu`×`nv`, drawn by `env_light::TableProposal`), the environment's size and rotation
/// (radians), the samples per pixel of each strategy, the gain K (sr⁻¹, `env_light::env_gain`), how many of
/// the BRDF strategy's samples are drawn cosine-weighted, and the seed of the samples.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct EnvMapPush {
    pub size: [f32; 2],
    pub offset: [f32; 2],
    pub origin: [f32; 2],
    pub nu: u32,
    pub nv: u32,
    pub env_width: u32,
    pub env_height: u32,
    pub rotation: f32,
    pub n_brdf: u32,
    pub n_env: u32,
    pub gain: f32,
    pub n_floor: u32,
    pub seed: u32,
    pub first: u32,
    pub chunk: u32,
}

/// `brdf_eval.comp`'s push constants (`EvalPush`): the number of queries.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct EvalPush {
    pub count: u32,
}

/// `selftest.comp`'s push constants (`Push`).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SelftestPush {
    pub offset: f32,
    pub count: u32,
}

/// The visibility buffer's push constants (`VisibilityPush`, every pass): the drawn object's index + 1 (the top
/// bits of its samples' ids), the constant background the objects' colours are drawn over (linear RGBA; zero
/// where an environment is drawn behind them instead), and which of a pixel's triangles an edge-pass dispatch
/// shades (1: the second; 0 in the other passes).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct VisibilityPush {
    pub object: u32,
    pub background_r: f32,
    pub background_g: f32,
    pub background_b: f32,
    pub background_a: f32,
    pub edge: u32,
}

// The push-constant blocks are generated from these structs by build.rs (PUSH_BLOCKS), which refuses a field GLSL
// would place elsewhere; their sizes, for the pipelines' push-constant ranges:
const _: () = assert!(std::mem::size_of::<MapPush>() == 24);
const _: () = assert!(std::mem::size_of::<EvalPush>() == 4);
const _: () = assert!(std::mem::size_of::<EnvMapPush>() == 72);
const _: () = assert!(std::mem::size_of::<SelftestPush>() == 8);
const _: () = assert!(std::mem::size_of::<VisibilityPush>() == 24);
