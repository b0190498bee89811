//! The numbers and layouts diffract's shaders and its Rust side must agree on: specialization-constant ids,
//! descriptor bindings (all in set 0), workgroup sizes, approach ids, the physical and colour constants both sides
//! use, the uniform and push-constant blocks, and the vertex layout. This crate is their one source: the library
//! uses it as `gpu::interface`, and diffract's `build.rs` (a build-dependency) writes the shaders' GLSL from its
//! declarations (nothing here is parsed as text):
//! - `interface.glsl`: every constant declared in `shared!` (`#define NAME value`, arrays as `const` GLSL
//!   values), with its documentation;
//! - a std140 uniform block for each of [`UNIFORM_BLOCKS`] and a push-constant block for each of [`PUSH_BLOCKS`],
//!   refused where GLSL's layout rules would place a field elsewhere than `repr(C)` does;
//! - the vertex shaders' inputs, [`VERTEX_INPUTS`] of [`Vertex`] at locations 0, 1, ….
//!
//! Its one dependency is bytemuck (its Cargo.toml): a number or a field changes here, and both sides follow.

/// A GLSL type a shared field has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlslType {
    Float,
    Int,
    Uint,
    Vec2,
    Vec3,
    Vec4,
    IVec4,
    UVec4,
    Mat4,
    /// `vec4 name[N]` (std140 and std430 stride 16, as `[[f32; 4]; N]` in Rust).
    Vec4Array(usize),
}

impl GlslType {
    /// The type's GLSL name (an array's element type).
    pub const fn name(self) -> &'static str {
        match self {
            GlslType::Float => "float",
            GlslType::Int => "int",
            GlslType::Uint => "uint",
            GlslType::Vec2 => "vec2",
            GlslType::Vec3 => "vec3",
            GlslType::Vec4 | GlslType::Vec4Array(_) => "vec4",
            GlslType::IVec4 => "ivec4",
            GlslType::UVec4 => "uvec4",
            GlslType::Mat4 => "mat4",
        }
    }

    /// (base alignment, size) in bytes under std140 and std430, which agree for these types.
    pub const fn align_size(self) -> (usize, usize) {
        match self {
            GlslType::Float | GlslType::Int | GlslType::Uint => (4, 4),
            GlslType::Vec2 => (8, 8),
            GlslType::Vec3 => (16, 12),
            GlslType::Vec4 | GlslType::IVec4 | GlslType::UVec4 => (16, 16),
            GlslType::Mat4 => (16, 64),
            GlslType::Vec4Array(n) => (16, 16 * n),
        }
    }
}

/// The GLSL twin of a Rust field type.
pub trait Glsl {
    const TYPE: GlslType;
}

macro_rules! glsl_types {
    ($($rust:ty => $glsl:ident),* $(,)?) => {
        $(impl Glsl for $rust {
            const TYPE: GlslType = GlslType::$glsl;
        })*
    };
}
glsl_types!(f32 => Float, i32 => Int, u32 => Uint, [f32; 2] => Vec2, [f32; 3] => Vec3, [f32; 4] => Vec4,
    [i32; 4] => IVec4, [u32; 4] => UVec4);

impl<const N: usize> Glsl for [[f32; 4]; N] {
    // Four vec4s are a mat4 (a matrix in column-major order, as glam writes it); any other count an array.
    const TYPE: GlslType = if N == 4 { GlslType::Mat4 } else { GlslType::Vec4Array(N) };
}

/// One field of a shared struct, as `gpu_struct!` records it.
#[derive(Clone, Copy, Debug)]
pub struct Field {
    pub name: &'static str,
    /// Bytes from the struct's start (`repr(C)`).
    pub offset: usize,
    pub ty: GlslType,
    /// Its `///` lines.
    pub doc: &'static [&'static str],
}

/// Declares a `repr(C)`, `Pod` struct the shaders read, and its [`Field`]s as `FIELDS`.
macro_rules! gpu_struct {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $( $(#[doc = $doc:literal])* pub $field:ident : $ty:ty ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name {
            $( $(#[doc = $doc])* pub $field: $ty ),*
        }

        impl $name {
            /// The fields in order, with their offsets and GLSL types (build.rs writes the GLSL from them).
            pub const FIELDS: &'static [Field] = &[$(Field {
                name: stringify!($field),
                offset: std::mem::offset_of!($name, $field),
                ty: <$ty as Glsl>::TYPE,
                doc: &[$($doc),*],
            }),*];
        }
    };
}

/// A shared constant's value, as GLSL writes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// An integer: GLSL takes it in layout qualifiers and sizes.
    Int(u64),
    Float(f64),
    /// A 3×3 matrix by rows (GLSL builds its `mat3` from columns).
    Mat3([[f64; 3]; 3]),
}

/// A type whose constants build.rs can write as GLSL.
pub trait IntoValue: Copy {
    fn value(self) -> Value;
}

impl IntoValue for u32 {
    fn value(self) -> Value {
        Value::Int(self.into())
    }
}

impl IntoValue for usize {
    fn value(self) -> Value {
        Value::Int(self as u64)
    }
}

impl IntoValue for f64 {
    fn value(self) -> Value {
        Value::Float(self)
    }
}

impl IntoValue for [[f64; 3]; 3] {
    fn value(self) -> Value {
        Value::Mat3(self)
    }
}

/// One constant of `shared!`: the section it opens (if it does), its name, documentation and value.
#[derive(Clone, Copy)]
pub struct Constant {
    pub section: Option<&'static str>,
    pub name: &'static str,
    pub doc: &'static [&'static str],
    pub value: fn() -> Value,
}

/// Declares the shared constants, and [`CONSTANTS`], the list of them build.rs writes into `interface.glsl`.
/// `section "…";` before a constant opens a section (a comment in the GLSL).
macro_rules! shared {
    ($( $(section $section:literal;)? $(#[doc = $doc:literal])* pub const $name:ident : $ty:ty = $value:expr; )*) => {
        $( $(#[doc = $doc])* pub const $name: $ty = $value; )*

        /// Every constant of this module's `shared!`, in order: what build.rs writes into `interface.glsl`.
        pub const CONSTANTS: &[Constant] = &[$(Constant {
            section: shared!(@section $($section)?),
            name: stringify!($name),
            doc: &[$($doc),*],
            value: || IntoValue::value($name),
        }),*];
    };
    (@section $section:literal) => { Some($section) };
    (@section) => { None };
}

shared! {
    section "Specialization constants of the diffraction shaders (glsl/include/params.glsl).";
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
    /// `map.comp`'s workgroup side (`render::map::map_workgroup`): side² invocations, one per pixel.
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
    /// How many lamps the surface shaders shade (`SurfaceUniforms::lamp_count`), each written out at a constant
    /// index; 0 compiles them out (a view without lamps: on lavapipe a loop over them cost the default scene's frame
    /// 30 % even when it ran no lamp, and a lamp-lit frame 1.5× where its count was read from the uniforms).
    pub const SPEC_LAMPS: u32 = 13;
    /// 1: the surface shaders read an object's maps where its uniforms say it has them; 0 compiles the reads out (a
    /// material none of whose objects has a map).
    pub const SPEC_MAPS: u32 = 14;
    /// 1: the material is matte (pigment only): the surface shaders compile its diffraction, its skin and its
    /// footprint out (`SurfaceUniforms::orientation`'s w says the same at run time).
    pub const SPEC_MATTE: u32 = 15;
    /// 1: the sun's disc lights the view (`SurfaceUniforms::light_dir`'s w); 0 compiles its diffraction, its light
    /// on the pigment and its shadow out (lamps or an environment map alone: on lavapipe a branch that no pixel
    /// takes still runs, masked, and the sun's cost a lamp-lit frame 1.4×).
    pub const SPEC_SUN: u32 = 16;

    section "Specialization constants of single shaders.";
    /// Which part of the G-buffer `gbuffer.frag` writes.
    pub const SPEC_GBUFFER_PART: u32 = 0;
    /// The fetch probe's texture layers and taps per axis (`fetch_probe.frag`).
    pub const SPEC_PROBE_LAYERS: u32 = 0;
    pub const SPEC_PROBE_TAPS: u32 = 1;
    /// The self-test's scale factor (`selftest.comp`).
    pub const SPEC_SELFTEST_SCALE: u32 = 0;

    section "Descriptor bindings.";
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
    /// `map_env.comp`'s distributions (each a `light::sampling::Distribution2D`'s CDF then its densities: the baked
    /// table's texels, the environment's) and the environment's radiance.
    pub const BINDING_TABLE_SAMPLING: u32 = 11;
    pub const BINDING_ENV_SAMPLING: u32 = 12;
    pub const BINDING_ENV_RADIANCE: u32 = 13;
    /// A material's moments against the environment's light (`light::prefilter::Moments`), read by the surface pass.
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
    /// The most lamps a scene holds (`SurfaceUniforms::lamps`, `light::lamp`), and the vec4s each takes there.
    pub const MAX_LAMPS: u32 = 8;
    pub const LAMP_VEC4S: u32 = 3;
    /// The wavelength, µm, at which a lamp's shorter coherence widens the baked table's read (`light::lamp::
    /// widening_variance`; model.md §3.13): the window's lobes widen with λ, a read of the colour table once.
    pub const WIDENING_LAMBDA_UM: f64 = 0.55;
    /// The moments' grid per axis and texture layers (`light::prefilter::MOMENT_GRID`, `MOMENT_LAYERS`).
    pub const MOMENT_GRID: u32 = 32;
    pub const MOMENT_LAYERS: u32 = 23;
    /// The R2 sequence's steps in 32-bit fixed point, 2³²/g and 2³²/g² for the plastic number g (`light::sampling::r2`).
    pub const R2_STEP_X: u32 = 3242174889;
    pub const R2_STEP_Y: u32 = 2447445413;
    /// The self-test's input and output buffers (`selftest.comp`).
    pub const BINDING_SELFTEST_IN: u32 = 0;
    pub const BINDING_SELFTEST_OUT: u32 = 1;
    /// The twins' points and results (`twins.comp`: four vec4s in, one out per point). Above the bindings of the
    /// includes it shares with the frames.
    pub const BINDING_TWIN_IN: u32 = 21;
    pub const BINDING_TWIN_OUT: u32 = 22;
    /// An object's surface maps (`render::maps`, `glsl/include/maps.glsl`): its pigment map (sRGB) and its normal
    /// map (tangent space, linear), each mip-mapped and read through one repeating, anisotropic sampler; one
    /// white texel where the object has none.
    pub const BINDING_PIGMENT_MAP: u32 = 23;
    pub const BINDING_NORMAL_MAP: u32 = 24;
    /// The lamps' shadow maps (`render::lamp_shadow`): one depth atlas, a tile per lamp, read by comparison and as
    /// depths (the blocker search) as the sun's map is.
    pub const BINDING_LAMP_SHADOW: u32 = 25;
    pub const BINDING_LAMP_SHADOW_DEPTH: u32 = 26;

    section "The GLSL functions `twins.comp` evaluates (`TwinPush::function`; `reference::twins::Twin`).";
    pub const TWIN_FRESNEL_REFLECTANCE: u32 = 0;
    pub const TWIN_FRESNEL_RATIO: u32 = 1;
    pub const TWIN_GAIN_FACTOR: u32 = 2;
    pub const TWIN_SHADOW_MASK: u32 = 3;
    pub const TWIN_TRANSMITTANCE: u32 = 4;
    pub const TWIN_PIGMENT_RGB: u32 = 5;
    pub const TWIN_PIGMENT_SKY_RGB: u32 = 6;
    pub const TWIN_SKY_OVER_PI: u32 = 7;
    pub const TWIN_SRGB_OETF: u32 = 8;
    pub const TWIN_AGX: u32 = 9;
    pub const TWIN_DISPLAY_ENCODE: u32 = 10;
    pub const TWIN_XYZ_TO_LINEAR_SRGB: u32 = 11;
    pub const TWIN_SPECTRUM_AT: u32 = 12;
    pub const TWIN_PANORAMA_UV: u32 = 13;
    pub const TWIN_MAP_VIEW: u32 = 14;
    pub const TWIN_MOMENT_GRID_OF_VIEW: u32 = 15;
    pub const TWIN_SKY_COEFFICIENTS: u32 = 16;
    pub const TWIN_SAMPLE_CELL: u32 = 17;
    pub const TWIN_R2: u32 = 18;
    pub const TWIN_TENT: u32 = 19;
    pub const TWIN_TABLE_LOD: u32 = 20;
    pub const TWIN_TABLE_SEGMENT: u32 = 21;
    pub const TWIN_BAKED_XYZ: u32 = 22;
    pub const TWIN_SPOT_FACTOR: u32 = 23;
    pub const TWIN_LAMP_LIGHT: u32 = 24;
    pub const TWIN_LAMP_COHERENCE: u32 = 25;
    pub const TWIN_WIDENING_VARIANCE: u32 = 26;
    pub const TWIN_WIDEN_STEPS: u32 = 27;

    section "Workgroup sizes.";
    /// Invocations per workgroup of every compute shader (`local_size_x`); dispatches divide by it.
    pub const LOCAL_SIZE_X: u32 = 64;

    section "Approach ids: the value of SPEC_APPROACH (`material::Approach::id`).";
    pub const APPROACH_FLSS: u32 = 0;
    pub const APPROACH_NMM: u32 = 1;
    pub const APPROACH_PQ: u32 = 2;
    pub const APPROACH_GEM: u32 = 3;
    pub const APPROACH_BAKED: u32 = 4;

    section "Physical constants (f64 on the CPU, float literals in the shaders).";
    /// π, for the shaders (Rust code uses `std::f64::consts::PI` itself).
    pub const PI: f64 = std::f64::consts::PI;
    /// Refractive index of snake skin (model.md §1.9: "close to the measured value from snake sheds").
    pub const SKIN_INDEX: f64 = 1.5;
    /// The light a uniform sky sends through the skin's surface: 1 − R averaged over the hemisphere, cosine-weighted,
    /// for exact Fresnel at SKIN_INDEX (`physics::optics::SKY_TRANSMITTANCE`, whose test integrates it).
    pub const SKY_TRANSMITTANCE: f64 = 0.908_222_040_657_649;
    /// The sun's solid angle (0.53° across), sr: its diffuse contribution relative to its glint in a mirror.
    pub const SUN_SOLID_ANGLE: f64 = 6.8e-5;
    /// The largest factor a shadow lookup's normal offset grows by as the light grazes a surface (1/cos θ_i up to
    /// this; `render::shadow`).
    pub const SHADOW_MAX_OFFSET_GROWTH: f64 = 4.0;
    /// How far a shadow lookup pushes a point along its normal, in the map's texels there (at normal incidence).
    pub const SHADOW_NORMAL_OFFSET_TEXELS: f64 = 1.5;
    /// How much finer than a pixel's footprint F the baked table's mip level is chosen, log2 √3 (see
    /// `physics::baked::sample::FOOTPRINT_LOD_BIAS`).
    pub const FOOTPRINT_LOD_BIAS: f64 = 0.792_481_250_360_578_1;

    section "Colour: the tables' wavelengths, and XYZ to linear sRGB (physics::spectrum).";
    /// The colour-matching functions' and illuminants' tables: 1 nm rows over this range, nm.
    pub const TABLE_LAMBDA_MIN_NM: f64 = 380.0;
    pub const TABLE_LAMBDA_MAX_NM: f64 = 780.0;
    pub const TABLE_ROWS: usize = 401;
    /// XYZ → linear sRGB (D65), rows of the matrix of IEC 61966-2-1 derived from the primaries and the white point.
    pub const XYZ_TO_LINEAR_SRGB: [[f64; 3]; 3] =
        [[3.2404542, -1.5371385, -0.4985314], [-0.9692660, 1.8760108, 0.0415560], [0.0556434, -0.2040259, 1.0572252]];

    section "The real spherical harmonics up to l = 2 (physics::sh::basis): Y_00, Y_1m / (x, y, z), Y_2m / (xy, yz, xz), Y_20 / (3z² − 1), Y_22 / (x² − y²).";
    pub const SH_Y00: f64 = 0.282_095;
    pub const SH_Y1: f64 = 0.488_603;
    pub const SH_Y2: f64 = 1.092_548;
    pub const SH_Y20: f64 = 0.315_392;
    pub const SH_Y22: f64 = 0.546_274;
}

gpu_struct! {
    /// `map.frag`'s and `map.comp`'s push constants (`MapPush`): the map's square in pixels and its offset in the
    /// target; `origin`, the first pixel a compute dispatch covers (a band's first row; the fragment shader ignores it).
    pub struct MapPush {
        pub size: [f32; 2],
        pub offset: [f32; 2],
        pub origin: [f32; 2],
    }
}

gpu_struct! {
    /// `map_env.comp`'s push constants (`EnvMapPush`): the map's square, offset and band origin as in [`MapPush`]; the
    /// table proposal's texels (`nu`×`nv`, drawn by `light::sampling::TableProposal`), the environment's size and rotation
    /// (radians), the samples per pixel of each strategy, the gain K (sr⁻¹, `light::sampling::env_gain`), how many of
    /// the BRDF strategy's samples are drawn cosine-weighted, and the seed of the samples.
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
}

gpu_struct! {
    /// `brdf_eval.comp`'s push constants (`EvalPush`): the number of queries.
    pub struct EvalPush {
        pub count: u32,
    }
}

gpu_struct! {
    /// `selftest.comp`'s push constants (`SelftestPush`, as `pc`).
    pub struct SelftestPush {
        pub offset: f32,
        pub count: u32,
    }
}

gpu_struct! {
    /// `twins.comp`'s push constants (`TwinPush`, as `twin`): which function (`TWIN_*`) at how many points.
    pub struct TwinPush {
        pub function: u32,
        pub count: u32,
    }
}

gpu_struct! {
    /// The visibility buffer's push constants (`VisibilityPush`, every pass): the drawn object's index + 1 (the top
    /// bits of its samples' ids), the constant background the objects' colours are drawn over (linear RGBA; zero
    /// where an environment is drawn behind them instead), and which of a pixel's triangles an edge-pass dispatch
    /// shades (1: the second; 0 in the other passes).
    pub struct VisibilityPush {
        pub object: u32,
        pub background_r: f32,
        pub background_g: f32,
        pub background_b: f32,
        pub background_a: f32,
        pub edge: u32,
    }
}

gpu_struct! {
    /// A material's uniforms (`params`, read through `glsl/include/params.glsl`), filled by
    /// `material::Material::prepare`.
    #[derive(Default)]
    pub struct DiffractionParams {
        /// nx, ny, layers, 0.
        pub patch_px: [i32; 4],
        /// Lx, Ly, dx, dy in µm.
        pub patch_um: [f32; 4],
        /// σ_x, σ_y in bins, σ_f in cycles/µm, and the coherence length (µm) where it follows each light (a
        /// material at sunlight's default: `light::lamp::follows_light`), else 0.
        pub window: [f32; 4],
        /// λ_min nm, Δλ nm, Σ ȳSΔλ of that sampling, ∫ȳS dλ (1 nm).
        pub spectral: [f32; 4],
        /// ω_i in the patch frame (BRDF maps and the compute pass read it; geometry computes its own).
        pub light: [f32; 4],
        /// PQ: periods along x and y, 0, 0.
        pub pq: [f32; 4],
        /// gem: unit grating direction (x, y), spacing µm (0: none), order efficiency.
        pub gem: [f32; 4],
        /// 2^exposure, the tone curve (`display::Tone::gpu`: 0 clip, 1 filmic), 0, 0.
        pub display: [f32; 4],
        /// Baked table: u and v of its lower edges, its extent in u and v.
        pub table_uv: [f32; 4],
        /// Baked table: middle of its w-interval, 1/half-width, the texel width in (u, v), the coarsest mip level.
        pub table_w: [f32; 4],
        /// The light's white (a mirror's colour under its illuminant), linear sRGB with Y = 1: what lights the
        /// pigment; and the diffraction's gain (`spectrum::diffraction_gain`: 1 in relative units).
        pub light_white: [f32; 4],
    }
}

gpu_struct! {
    /// The surface pass's per-object uniforms (`frame`, read through `glsl/include/surface_frame.glsl`), filled by
    /// `render::surface`; the shadow, G-buffer and visibility passes read them too.
    pub struct SurfaceUniforms {
        pub view_proj: [[f32; 4]; 4],
        pub model: [[f32; 4]; 4],
        /// Inverse transpose of the model matrix's linear part (in a mat4 for std140).
        pub normal_matrix: [[f32; 4]; 4],
        /// World space.
        pub camera_pos: [f32; 4],
        /// World space, unit, towards the light; w: 1, or 0 where no sun lights the scene (a map alone).
        pub light_dir: [f32; 4],
        /// cos and sin of the patch's rotation about the normal, the material's index (the G-buffer writes it), and
        /// 1 for a matte material (pigment only: no grating, no skin over it), else 0.
        pub orientation: [f32; 4],
        /// Linear RGB albedo of the pigment under the grating, and the ambient (sky) radiance.
        pub pigment: [f32; 4],
        /// The environment's irradiance over π, nine SH coefficients (RGB; `physics::sh`), in units of the sun's
        /// radiance: zero where the scene has no environment.
        pub sky_sh: [[f32; 4]; 9],
        /// World → the sun's shadow map's clip space (`render::shadow::ShadowFrame`).
        pub shadow_view_proj: [[f32; 4]; 4],
        /// 1 where the map is drawn (0: every surface lit), the lookup's normal offset (world units), one texel in
        /// texture coordinates, 0.
        pub shadow: [f32; 4],
        /// The penumbra's scales: one texel in world units, the map's depth range in world units (far − near), the
        /// tangent of the sun's angular radius, 0.
        pub shadow_penumbra: [f32; 4],
        /// The environment's radiance to l = 2 as a quadratic form of the world direction (`light::prefilter::Quadratic`:
        /// c₀, c, Q), in units of the sun's radiance; `sky_quadratic[0].w` 1 where the material diffracts it.
        pub sky_quadratic: [[f32; 4]; 10],
        /// Clip space → world (`view_proj` inverted): where the visibility buffer's shading finds a pixel's point.
        pub inverse_view_proj: [[f32; 4]; 4],
        /// The number of lamps, 0, 0, 0.
        pub lamp_count: [f32; 4],
        /// The lamps (`light::lamp::LampUniforms`), LAMP_VEC4S each: (position (world), intensity over the
        /// frame's unit of luminance, m²), (a spot's axis from the lamp, its cone's half-angle in degrees; a point
        /// lamp's cone 360), (the edge's width in degrees, the disc's radius squared (m²), the coherence length times
        /// the angular radius that gives it (µm·rad: `coherence::of_light`), the disc's radius (m)).
        pub lamps: [[f32; 4]; 24],
        /// 1 where the object has a pigment map, 1 where it has a normal map (`scene::mesh::maps`), 0, 0.
        pub maps: [f32; 4],
        /// The lamps' shadows (`render::lamp_shadow`): world → each lamp's tile's clip space (a perspective from the
        /// lamp; four columns each), and each one's scales: the near and far planes' depths (world units along its
        /// axis; near 0: the lamp casts no shadow), a texel's width at depth 1, the disc's radius.
        pub lamp_shadow_view_proj: [[f32; 4]; 32],
        pub lamp_shadow_scales: [[f32; 4]; 8],
        /// The lamps' shadow atlas: its tiles (one per lamp it holds), one texel of a tile in the tile's texture
        /// coordinates, 0, 0.
        pub lamp_atlas: [f32; 4],
    }
}
const _: () = assert!(MAX_LAMPS * LAMP_VEC4S == 24, "SurfaceUniforms::lamps holds MAX_LAMPS lamps");
const _: () = assert!(MAX_LAMPS * 4 == 32, "SurfaceUniforms::lamp_shadow_view_proj holds MAX_LAMPS lamps");

gpu_struct! {
    /// The preview pass's per-frame uniforms (`frame`, read through `glsl/include/preview_frame.glsl`).
    pub struct FrameUniforms {
        pub view_proj: [[f32; 4]; 4],
        pub model: [[f32; 4]; 4],
        /// World space, w unused.
        pub camera_pos: [f32; 4],
        /// World space, unit, towards the light.
        pub light_dir: [f32; 4],
        /// Linear RGB.
        pub base_color: [f32; 4],
    }
}

gpu_struct! {
    /// The background pass's uniforms (`background`: `render::background`).
    pub struct BackgroundUniforms {
        /// Clip space → world (the camera's view-projection inverted).
        pub inverse_view_proj: [[f32; 4]; 4],
        /// The camera's position (world), 0.
        pub camera: [f32; 4],
        /// The factor from the map's texels to the frame's units, the map's turn about +y (radians), 0, 0.
        pub view: [f32; 4],
        /// 2^EV of a display-encoded target's exposure, its tone curve (`display::Tone::gpu`), 0, 0.
        pub display: [f32; 4],
    }
}

gpu_struct! {
    /// One vertex as the shaders read it (binding 0, interleaved): [`VERTEX_INPUTS`] are its attributes.
    pub struct Vertex {
        pub position: [f32; 3],
        pub normal: [f32; 3],
        pub tangent: [f32; 4],
        pub uv: [f32; 2],
        /// The skin's pigment here relative to the material's (linear RGB factors; `scene::mesh::UNTINTED`: the material's own).
        /// The procedural snake paints its pattern with it; an OBJ may carry it as vertex colours.
        pub pigment: [f32; 3],
    }
}

/// One block of GLSL generated from a struct of this module: its fields, size, the GLSL instance name, the include
/// file it is written to, and (a uniform block's) its descriptor binding.
#[derive(Clone, Copy, Debug)]
pub struct Block {
    pub name: &'static str,
    pub fields: &'static [Field],
    pub size: usize,
    pub instance: &'static str,
    pub file: &'static str,
    pub binding: Option<(&'static str, u32)>,
}

macro_rules! block {
    ($name:ident, $instance:literal, $file:literal $(, $binding:ident)?) => {
        Block {
            name: stringify!($name),
            fields: $name::FIELDS,
            size: std::mem::size_of::<$name>(),
            instance: $instance,
            file: $file,
            binding: block!(@binding $($binding)?),
        }
    };
    (@binding $binding:ident) => { Some((stringify!($binding), $binding)) };
    (@binding) => { None };
}

/// The std140 uniform blocks (set 0): the struct, the GLSL instance, the include file, the binding.
pub const UNIFORM_BLOCKS: [Block; 4] = [
    block!(DiffractionParams, "params", "diffraction_params.glsl", BINDING_PARAMS),
    block!(SurfaceUniforms, "frame", "surface_uniforms.glsl", BINDING_FRAME),
    block!(FrameUniforms, "frame", "preview_uniforms.glsl", BINDING_FRAME),
    block!(BackgroundUniforms, "background", "background_uniforms.glsl", BINDING_FRAME),
];

/// The push-constant blocks: the struct, the GLSL instance, the include file.
pub const PUSH_BLOCKS: [Block; 6] = [
    block!(MapPush, "map", "map_push.glsl"),
    block!(EnvMapPush, "map", "env_map_push.glsl"),
    block!(EvalPush, "eval", "eval_push.glsl"),
    block!(SelftestPush, "pc", "selftest_push.glsl"),
    block!(VisibilityPush, "visibility", "visibility_push.glsl"),
    block!(TwinPush, "twin", "twin_push.glsl"),
];

impl Default for Vertex {
    /// At the origin, facing +z with its tangent along +x, untinted (a pigment of 1 leaves the material's as it
    /// is: the library's `scene::mesh::UNTINTED`).
    fn default() -> Self {
        Self {
            position: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
            tangent: [1.0, 0.0, 0.0, 1.0],
            uv: [0.0; 2],
            pigment: [1.0; 3],
        }
    }
}

/// The vertex shaders' inputs: [`Vertex`]'s fields at locations 0, 1, … (`in_<field>` in the GLSL).
pub const VERTEX_INPUTS: [&str; 5] = ["position", "normal", "tangent", "pigment", "uv"];
