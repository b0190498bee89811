//! The environment's diffraction prefiltered for frames (model.md §3.11, which derives it): the environment (without
//! its sun) projected to l ≤ 2 is a quadratic form of the direction ([`Quadratic`]), which in a patch frame stays
//! one, so its integral against the BRDF is a sum of nine moments of the BRDF that depend on the view alone
//! ([`Moments`], tabulated per material on a grid of views from coarse tables for every pair of directions).
//!
//! The environment's RGB is upsampled to spectra in the [`basis`] of three smooth bands of D65, each band with its
//! own table, so a moment is a colour matrix from light RGB to reflected RGB and does not depend on the sun's
//! illuminant. Where a frame evaluates it is [`SkyAt`](crate::material::SkyAt): by default the nine diffraction
//! moments at the vertices, the specular moment and the environment's own light at the mirror direction per pixel
//! (`glsl/include/sky_diffraction.glsl`, whose functions are twins of this module's).

use glam::{DMat3, DVec3};

use crate::physics::baked::BakedTable;
use crate::physics::sh::Irradiance;

/// Points of the moments' grid per axis of ω_r.xy ∈ [−1, 1]².
pub const MOMENT_GRID: usize = crate::gpu::interface::MOMENT_GRID as usize;
/// The nine monomials' count.
pub const MONOMIALS: usize = 9;
/// RGBA layers of the moments' texture: the nine moments' colour matrices, then the specular reflectance's (90
/// scalars).
pub const MOMENT_LAYERS: usize = crate::gpu::interface::MOMENT_LAYERS as usize;

/// The monomials m_j of a direction in the patch frame, in the order of [`Moments`].
pub fn monomials(w: DVec3) -> [f64; MONOMIALS] {
    [1.0, w.x, w.y, w.z, w.x * w.x, w.y * w.y, w.x * w.y, w.x * w.z, w.y * w.z]
}

/// A smooth light as a quadratic form of the direction per channel: L(d) = c₀ + c·d + dᵀQd (world frame).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quadratic {
    pub c0: DVec3,
    /// c's x, y and z components, each RGB.
    pub c: [DVec3; 3],
    /// Q (symmetric), each entry RGB.
    pub q: [[DVec3; 3]; 3],
}

impl Quadratic {
    /// The radiance whose irradiance `irradiance` is, up to l = 2 (its nine coefficients unconvolved), written out
    /// in the basis of `sh::basis`.
    pub fn of_irradiance(irradiance: &Irradiance) -> Self {
        let l = irradiance.radiance_coefficients();
        // sh::basis: 0.282095; 0.488603·(y, z, x); 1.092548·xy, 1.092548·yz, 0.315392·(3z² − 1), 1.092548·xz,
        // 0.546274·(x² − y²).
        let (a1, a2, a20, a22) = (0.488_603, 1.092_548, 0.315_392, 0.546_274);
        let c0 = l[0] * 0.282_095 - l[6] * a20;
        let c = [l[3] * a1, l[1] * a1, l[2] * a1];
        let mut q = [[DVec3::ZERO; 3]; 3];
        q[0][0] = l[8] * a22;
        q[1][1] = -l[8] * a22;
        q[2][2] = l[6] * (3.0 * a20);
        q[0][1] = l[4] * (a2 / 2.0);
        q[1][0] = q[0][1];
        q[1][2] = l[5] * (a2 / 2.0);
        q[2][1] = q[1][2];
        q[0][2] = l[7] * (a2 / 2.0);
        q[2][0] = q[0][2];
        Self { c0, c, q }
    }

    /// As the shaders' uniforms (`SurfaceUniforms::sky_quadratic`): c₀, c_x, c_y, c_z, Q_xx, Q_yy, Q_zz, Q_xy,
    /// Q_xz, Q_yz, each RGB; `w` of the first is `on` (1: the frame diffracts the environment).
    pub fn to_vec4s(&self, on: bool) -> [[f32; 4]; 10] {
        let q = &self.q;
        let all = [self.c0, self.c[0], self.c[1], self.c[2], q[0][0], q[1][1], q[2][2], q[0][1], q[0][2], q[1][2]];
        let mut out = all.map(|v| [v.x as f32, v.y as f32, v.z as f32, 0.0]);
        out[0][3] = if on { 1.0 } else { 0.0 };
        out
    }

    /// L(d) per channel.
    pub fn radiance(&self, d: DVec3) -> DVec3 {
        let d = [d.x, d.y, d.z];
        let mut sum = self.c0;
        for a in 0..3 {
            sum += self.c[a] * d[a];
            for b in 0..3 {
                sum += self.q[a][b] * (d[a] * d[b]);
            }
        }
        sum
    }

    /// The coefficients a_j of the monomials of ω in the frame whose columns `frame` are the patch's x, y and z
    /// axes in the world (d = frame·ω): L(frame·ω) = Σ_j a_j m_j(ω) for unit ω.
    pub fn coefficients(&self, frame: DMat3) -> [DVec3; MONOMIALS] {
        let t = [frame.x_axis, frame.y_axis, frame.z_axis];
        let dot = |v: DVec3, c: &[DVec3; 3]| c[0] * v.x + c[1] * v.y + c[2] * v.z;
        // c' = Tᵀc, Q' = TᵀQT.
        let cp: [DVec3; 3] = std::array::from_fn(|i| dot(t[i], &self.c));
        let qt: [[DVec3; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|j| dot(t[j], &self.q[a])));
        let qp = |i: usize, j: usize| qt[0][j] * t[i].x + qt[1][j] * t[i].y + qt[2][j] * t[i].z;
        let zz = qp(2, 2);
        [
            self.c0 + zz,
            cp[0],
            cp[1],
            cp[2],
            qp(0, 0) - zz,
            qp(1, 1) - zz,
            qp(0, 1) * 2.0,
            qp(0, 2) * 2.0,
            qp(1, 2) * 2.0,
        ]
    }
}

/// The spectral basis an RGB environment's light is upsampled into (see the module's note), in physical units.
pub fn basis() -> [crate::physics::illuminant::Illuminant; 3] {
    std::array::from_fn(|k| crate::physics::illuminant::Illuminant::d65_band(k).physical())
}

/// A: its columns are the basis lights' colours (linear sRGB of a mirror under each, `spectrum::white_rgb`), so
/// that the light Σ c_k B_k has the colour A·c.
pub fn basis_colours() -> DMat3 {
    let [b0, b1, b2] = basis().map(crate::physics::spectrum::white_rgb);
    DMat3::from_cols(b0, b1, b2)
}

/// How the moments are integrated: the tables' spectral step and texels, and whether the views read blocks of
/// 2×2 texels away from the specular disc and the horizon. [`Self::FAST`] is what scenes use; [`Self::CAREFUL`]
/// (the previous way, 2.4× slower from cold) is there to measure it against: on the Elaphe and Xenopeltis scans at
/// 20 µm their radiance under a clear sky differs by 0.09 % on average, 0.7 % at worst (beyond 70°), and the
/// specular disc's share by 1.2 % (docs/performance.md, "The sky's first cost").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadrature {
    /// The tables' wavelength step, nm: with each wavelength weighing its bin (`Sampling::binned_weights`) when
    /// `mass_only`, at its point otherwise.
    pub lambda_step_nm: f64,
    /// The tables' texels hold only the mass of their light (`TablePlan::mass_only`): the moments integrate it
    /// against factors that change little across a texel.
    pub mass_only: bool,
    /// Blocks of 2×2 texels where the factors change slowly (away from the specular disc and the horizon).
    pub blocks: bool,
}

impl Quadrature {
    pub const FAST: Self = Self { lambda_step_nm: 10.0, mass_only: true, blocks: true };
    pub const CAREFUL: Self = Self { lambda_step_nm: 5.0, mass_only: false, blocks: false };
}

/// Bumped whenever the moments' definition changes: cached moments of other versions are recomputed.
pub(crate) const MOMENTS_VERSION: u64 = 5;

/// Appends to a cache key what the moments depend on beyond their tables: the grid and the sizes that
/// [`Moments::new`] integrates with.
pub(crate) fn key_tail(p: &mut crate::io::cache::PlanBytes, quadrature: &Quadrature) {
    p.u64(MOMENT_GRID as u64).f64(MOMENT_TEXEL).f64(SPECULAR_RADIUS).u64(FACTOR_SUBSAMPLES as u64);
    p.u64(u64::from(quadrature.blocks));
}

/// The shaders' `sky_quadratic` (off) for an environment whose irradiance is `sky_sh` (`SurfaceUniforms::sky_sh`):
/// all zero where it is (no environment).
pub fn sky_quadratic(sky_sh: &[[f32; 4]; 9]) -> [[f32; 4]; 10] {
    let coefficients = sky_sh.map(|c| DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])));
    Quadratic::of_irradiance(&Irradiance { coefficients }).to_vec4s(false)
}

/// The moments M_j(ω_r) of a material's BRDF on a grid of views, each a colour matrix N_j (light RGB → reflected
/// linear sRGB) of ∫ ρ·K·m_j dω_i over the hemisphere, the light upsampled in the spectral [`basis`] (the
/// environment's units per unit of its coefficients).
///
/// The grid is square over p ∈ [−1, 1]², p = (ω_r.xy/|ω_r.xy|)·θ_r/(π/2): uniform in the angle from the normal, so
/// that the rim, where Fresnel's rise and the horizon change the moments fastest, gets as many points as the
/// middle. Points with |p| > 1 hold the value at θ_r = 89.9°.
#[derive(Clone, Debug, PartialEq)]
pub struct Moments {
    /// Points per axis: p = −1 + 2i/(grid − 1).
    pub grid: usize,
    // (Values and specular are stored over [`mirror_fresnel`] at their view, which [`Moments::at`] multiplies
    // back: Fresnel's rise towards grazing is steeper than a grid of 5.8° can interpolate, 4.8 % off at 70°.)
    /// Row-major (x fastest), each point's nine moments of the light that leaves the specular disc.
    pub values: Vec<[DMat3; MONOMIALS]>,
    /// Each point's specular reflectance: ∫ ρ·K dω_i over the texels within [`SPECULAR_RADIUS`] of (u, v) = 0, the
    /// light the environment sends from (within a degree of) the mirror direction, which a frame reads from the
    /// environment itself rather than from its l ≤ 2 projection. It depends on θ_r alone (the disc's texels at
    /// w = −2 cos θ_r, the factors at the mirror direction).
    pub specular: Vec<DMat3>,
}

impl Moments {
    /// The moments of the basis' `tables` (each built for every pair of directions, under band k of [`basis`],
    /// with its gain K, sr⁻¹: `light::sampling::env_gain`), integrated over a level of each table whose texels are
    /// about [`MOMENT_TEXEL`] wide, in blocks of 2×2 texels where the factors change slowly if `blocks`.
    pub fn new(tables: &[(&BakedTable, f64); 3], grid: usize, blocks: bool) -> Self {
        use rayon::prelude::*;
        let shared = same_level(tables[0].0, tables[1].0) && same_level(tables[0].0, tables[2].0);
        let packed: Vec<Packed> = if shared {
            vec![Packed::new(&[(tables[0].0, tables[0].1), (tables[1].0, tables[1].1), (tables[2].0, tables[2].1)])]
        } else {
            tables.iter().map(|&(table, gain)| Packed::new(&[(table, gain)])).collect()
        };
        let to_light = basis_colours().inverse();
        let (values, specular) = (0..grid * grid)
            .into_par_iter()
            .map(|i| {
                let at = |k: usize| -1.0 + 2.0 * k as f64 / (grid - 1) as f64;
                let omega_r = view_of_grid(at(i % grid), at(i / grid));
                let bands: Vec<_> = packed.iter().flat_map(|p| moments_of_bands(p, omega_r, blocks)).collect();
                let f = 1.0 / mirror_fresnel(omega_r);
                let matrix = |col: &dyn Fn(usize) -> DVec3| DMat3::from_cols(col(0), col(1), col(2)) * to_light * f;
                let values = std::array::from_fn(|j| matrix(&|k| bands[k].0[j]));
                (values, matrix(&|k| bands[k].1))
            })
            .unzip();
        Self { grid, values, specular }
    }

    /// The cache's payload: the grid, then every point's moments and specular reflectance, each matrix column by
    /// column (f64, little-endian).
    pub(crate) fn to_bytes(&self) -> Vec<u8> {
        let mut p = crate::io::cache::PlanBytes::default();
        p.u64(self.grid as u64);
        for (values, specular) in self.values.iter().zip(&self.specular) {
            for m in values.iter().chain(std::iter::once(specular)) {
                m.to_cols_array().iter().for_each(|&v| {
                    p.f64(v);
                });
            }
        }
        p.0
    }

    /// The moments [`Self::to_bytes`] wrote; None for anything else.
    pub(crate) fn from_bytes(bytes: &[u8]) -> Option<Self> {
        let mut r = crate::io::cache::Reader::new(bytes);
        let grid = usize::try_from(r.u64()?).ok().filter(|&g| (2..=1024).contains(&g))?;
        let mut matrix = || {
            let mut cols = [0.0; 9];
            for v in &mut cols {
                *v = r.f64().filter(|v| v.is_finite())?;
            }
            Some(DMat3::from_cols_array(&cols))
        };
        let mut values = Vec::with_capacity(grid * grid);
        let mut specular = Vec::with_capacity(grid * grid);
        for _ in 0..grid * grid {
            let mut point = [DMat3::ZERO; MONOMIALS];
            for m in &mut point {
                *m = matrix()?;
            }
            values.push(point);
            specular.push(matrix()?);
        }
        r.finished().then_some(Self { grid, values, specular })
    }

    /// The moments at `omega_r` (patch frame), bilinear between grid points, then the specular reflectance.
    pub fn at(&self, omega_r: DVec3) -> ([DMat3; MONOMIALS], DMat3) {
        let g = (self.grid - 1) as f64;
        let p = grid_of_view(omega_r);
        let fx = ((p.0 + 1.0) / 2.0 * g).clamp(0.0, g);
        let fy = ((p.1 + 1.0) / 2.0 * g).clamp(0.0, g);
        let (x0, y0) = ((fx.floor() as usize).min(self.grid - 2), (fy.floor() as usize).min(self.grid - 2));
        let (tx, ty) = (fx - x0 as f64, fy - y0 as f64);
        let lerp = |v: &dyn Fn(usize, usize) -> DMat3| {
            let top = v(x0, y0) * (1.0 - tx) + v(x0 + 1, y0) * tx;
            let bottom = v(x0, y0 + 1) * (1.0 - tx) + v(x0 + 1, y0 + 1) * tx;
            top * (1.0 - ty) + bottom * ty
        };
        let f = mirror_fresnel(omega_r);
        let moments = std::array::from_fn(|j| lerp(&|x, y| self.values[y * self.grid + x][j]) * f);
        (moments, lerp(&|x, y| self.specular[y * self.grid + x]) * f)
    }

    /// The texture the shaders read (`glsl/include/sky_diffraction.glsl`): `MOMENT_LAYERS` RGBA layers of grid²
    /// texels, scalar 9j + 3c + r of a point being row r of column c (the reflection of the light's channel c) of
    /// moment j's matrix (j = 9: the specular reflectance).
    pub fn gpu_texels(&self) -> Vec<f32> {
        let n = self.grid * self.grid;
        let mut out = vec![0.0f32; MOMENT_LAYERS * n * 4];
        for i in 0..n {
            for j in 0..=MONOMIALS {
                let m = if j < MONOMIALS { self.values[i][j] } else { self.specular[i] };
                for (e, x) in m.to_cols_array().into_iter().enumerate() {
                    let s = 9 * j + e;
                    out[((s / 4) * n + i) * 4 + s % 4] = x as f32;
                }
            }
        }
        out
    }

    /// The radiance towards `omega_r` (patch frame) under `light` seen in `frame` (columns: the patch's axes in
    /// the world), with `mirror` the environment's own radiance from the mirror direction.
    pub fn radiance(&self, omega_r: DVec3, light: &Quadratic, frame: DMat3, mirror: DVec3) -> DVec3 {
        let a = light.coefficients(frame);
        let (m, specular) = self.at(omega_r);
        (0..MONOMIALS).map(|j| m[j] * a[j]).sum::<DVec3>().max(DVec3::ZERO) + specular * mirror
    }
}

/// Fresnel's R/R₀ (exact) for the mirror direction of `omega_r` (`optics::fresnel_ratio` there): the moments' steepest
/// dependence on the view, divided out of the grid and multiplied back at the view itself.
pub fn mirror_fresnel(omega_r: DVec3) -> f64 {
    let mirror = DVec3::new(-omega_r.x, -omega_r.y, omega_r.z);
    crate::physics::optics::fresnel_ratio(mirror, omega_r, crate::physics::optics::SKIN_INDEX)
}

/// The view at grid coordinates p (see [`Moments`]), θ_r at most 89.9°.
pub fn view_of_grid(px: f64, py: f64) -> DVec3 {
    let r = (px * px + py * py).sqrt();
    let theta = (r.min(1.0) * std::f64::consts::FRAC_PI_2).min(89.9f64.to_radians());
    if r == 0.0 {
        return DVec3::Z;
    }
    DVec3::new(px / r * theta.sin(), py / r * theta.sin(), theta.cos())
}

/// The grid coordinates of a view (the inverse of [`view_of_grid`] below 89.9°).
pub fn grid_of_view(omega_r: DVec3) -> (f64, f64) {
    let s = (omega_r.x * omega_r.x + omega_r.y * omega_r.y).sqrt();
    if s == 0.0 {
        return (0.0, 0.0);
    }
    let r = s.atan2(omega_r.z) / std::f64::consts::FRAC_PI_2;
    (omega_r.x / s * r, omega_r.y / s * r)
}

/// The widest texel, in (u, v), of the table level the moments are integrated over: the factors beside the table's
/// colour (the gain, the shadowing, 1/cos θ_i, the monomials) change little across it.
pub const MOMENT_TEXEL: f64 = 0.02;
/// The disc of (u, v) about 0 whose light counts as specular ([`Moments::specular`]): 0.02 in (u, v) is about a
/// degree about the mirror direction, four lobe widths at 65 µm.
pub const SPECULAR_RADIUS: f64 = 0.02;
/// Sub-samples per texel axis of those factors in texels at the rim (its partial texels, 1/cos θ_i's rise).
const FACTOR_SUBSAMPLES: usize = 4;

/// The table level the moments read, and its texel width in (u, v).
fn moment_level(table: &BakedTable) -> (usize, f64) {
    let extent = table.grid.nu as f64 * table.grid.texel;
    let level = (0..table.levels.len())
        .find(|&l| extent / table.levels[l].width as f64 >= MOMENT_TEXEL)
        .map_or(table.levels.len() - 1, |l| l.saturating_sub(1));
    (level, extent / table.levels[level].width as f64)
}

/// The moments' level of tables whose levels share one geometry ([`same_level`]), packed for the views' loop: per
/// texel and segment of w, each Chebyshev term's X, Y and Z of every band side by side (zero where a band's texel
/// holds no colour), so that a texel's colours at a w are one pass over a few contiguous lines; and which texels
/// any band lights (the rest are skipped: a grating's light lies on a few lines of (u, v)). Beside it the same of
/// blocks of 2×2 texels (their mean), which the views read away from the specular disc and the horizon.
struct Packed<'a> {
    /// The first band's table: the geometry (grid, moment level) every band shares.
    first: &'a BakedTable,
    texel: f64,
    bands: usize,
    terms: usize,
    gains: Vec<f64>,
    fine: Texels,
    blocks: Texels,
}

/// Texels of [`Packed`]: per texel, where its coefficients start (none: no band lights it).
struct Texels {
    width: usize,
    height: usize,
    start: Vec<Option<u32>>,
    coefficients: Vec<f32>,
}

impl Texels {
    fn push(&mut self, line: Option<&[f32]>) {
        self.start.push(line.map(|line| {
            let at = self.coefficients.len() as u32;
            self.coefficients.extend_from_slice(line);
            at
        }));
    }
}

impl<'a> Packed<'a> {
    fn new(bands: &[(&'a BakedTable, f64)]) -> Self {
        let first = bands[0].0;
        let (level, texel) = moment_level(first);
        let l = &first.levels[level];
        let terms = bands.iter().map(|(table, _)| table.terms).max().unwrap_or(1);
        let segments = first.grid.segments.max(1);
        let stride = segments * terms * 3 * bands.len();
        let (width, height) = (l.width, l.height);
        let mut fine = Texels { width, height, start: Vec::with_capacity(width * height), coefficients: Vec::new() };
        let mut line = vec![0.0f32; stride];
        let own: Vec<_> = bands.iter().map(|(table, _)| &table.levels[moment_level(table).0]).collect();
        for i in 0..width * height {
            line.fill(0.0);
            let mut lit = false;
            for (k, (table, _)) in bands.iter().enumerate() {
                let values: Vec<f64> = table.texel_coefficients(own[k], i).collect();
                if !values.iter().any(|c| c.abs() > crate::physics::baked::INVISIBLE) {
                    continue;
                }
                lit = true;
                // texel_coefficients: segment by segment, term d's X, Y, Z at 3d + c.
                for (s, v) in values.iter().enumerate() {
                    let (segment, d, c) = (s / (3 * table.terms), (s % (3 * table.terms)) / 3, s % 3);
                    line[(segment * terms + d) * 3 * bands.len() + 3 * k + c] = *v as f32;
                }
            }
            fine.push(lit.then_some(line.as_slice()));
        }
        let (bw, bh) = (width.div_ceil(2), height.div_ceil(2));
        let mut blocks = Texels { width: bw, height: bh, start: Vec::with_capacity(bw * bh), coefficients: Vec::new() };
        let mut sum = vec![0.0f64; stride];
        for i in 0..bw * bh {
            sum.fill(0.0);
            let mut lit = false;
            for (x, y) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (a, b) = (2 * (i % bw) + x, 2 * (i / bw) + y);
                if let Some(at) = (a < width && b < height).then(|| fine.start[b * width + a]).flatten() {
                    lit = true;
                    for (s, &c) in sum.iter_mut().zip(&fine.coefficients[at as usize..][..stride]) {
                        *s += 0.25 * f64::from(c);
                    }
                }
            }
            line.iter_mut().zip(&sum).for_each(|(l, s)| *l = *s as f32);
            blocks.push(lit.then_some(line.as_slice()));
        }
        let gains = bands.iter().map(|b| b.1).collect();
        Self { first, texel, bands: bands.len(), terms, gains, fine, blocks }
    }

    /// Each band's XYZ in the texel whose coefficients start at `at` in `texels`, at w, times its gain, clamped at
    /// 0 as `BakedTable::level_xyz` is.
    fn colours(&self, texels: &Texels, at: u32, w: f64, out: &mut [DVec3; 3]) {
        let (segment, t) = self.first.grid.segment_of(w);
        let width = 3 * self.bands;
        let line = &texels.coefficients[at as usize + segment * self.terms * width..][..self.terms * width];
        let mut sums = [0.0f64; 9];
        let (mut previous, mut current) = (1.0, t);
        for (d, term) in line.chunks_exact(width).enumerate() {
            let td = match d {
                0 => 1.0,
                1 => t,
                _ => {
                    let next = 2.0 * t * current - previous;
                    (previous, current) = (current, next);
                    next
                }
            };
            for (sum, &c) in sums.iter_mut().zip(term) {
                *sum += f64::from(c) * td;
            }
        }
        for (k, colour) in out.iter_mut().enumerate().take(self.bands) {
            *colour = DVec3::new(sums[3 * k], sums[3 * k + 1], sums[3 * k + 2]).max(DVec3::ZERO) * self.gains[k];
        }
    }
}

/// What one view's sums hold per band: the nine moments and the specular reflectance, in XYZ.
type Sums = Vec<([DVec3; MONOMIALS], DVec3)>;

/// The nine moments at one view and the specular reflectance, for each band of `packed`: over the texels of a
/// coarse level of the tables in (u, v) (each texel's colour its average, exact in mass), times the factors
/// averaged over the part of the texel whose ω_i lies above the surface (du dv = cos θ_i dω_i). The factors depend
/// on the geometry alone, so the bands share them. Away from the specular disc and the horizon, where the factors
/// change slowly, a block of 2×2 texels is taken at once if `by_blocks` (its mean colour, the factors at its centre:
/// within 0.1 % of the texels one by one on the Elaphe scan's moments); summed in XYZ, turned into linear sRGB at
/// the end.
fn moments_of_bands(packed: &Packed, omega_r: DVec3, by_blocks: bool) -> Sums {
    use crate::physics::colour::xyz_to_linear_srgb;
    let (first, texel) = (packed.first, packed.texel);
    let (u0, v0) = (first.grid.u0, first.grid.v0);
    let mut out = vec![([DVec3::ZERO; MONOMIALS], DVec3::ZERO); packed.bands];
    let block = 2.0 * texel;
    // Only the blocks of the box around the disc of (u, v) = −ω_i.xy − ω_r.xy, |ω_i.xy| < 1.
    let range = |lo: f64, centre: f64, n: usize| {
        let first = ((centre - 1.0 - lo) / block).floor().max(0.0) as usize;
        let last = (((centre + 1.0 - lo) / block).ceil().max(0.0) as usize).min(n);
        first..last
    };
    let blocks = &packed.blocks;
    for b in range(v0, -omega_r.y, blocks.height) {
        for a in range(u0, -omega_r.x, blocks.width) {
            let Some(at) = blocks.start[b * blocks.width + a] else { continue };
            let (uc, vc) = (u0 + (a as f64 + 0.5) * block, v0 + (b as f64 + 0.5) * block);
            let (x, y) = (-uc - omega_r.x, -vc - omega_r.y);
            let r = (x * x + y * y).sqrt();
            if r > 1.0 + block {
                continue;
            }
            // Texel by texel where a texel of the block meets the specular disc or needs the horizon's
            // sub-samples (the texels' own tests below), or the block is cut by the level's edge.
            let whole = 2 * a + 1 < packed.fine.width && 2 * b + 1 < packed.fine.height;
            let near = (uc * uc + vc * vc).sqrt() < SPECULAR_RADIUS + 1.5 * texel || r > 1.0 - 3.0 * texel;
            if !by_blocks || !whole || near {
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    texel_sums(packed, 2 * a + dx, 2 * b + dy, omega_r, &mut out);
                }
                continue;
            }
            let omega_i = DVec3::new(x, y, (1.0 - r * r).sqrt());
            let f = factor(omega_i, omega_r) * block * block;
            let mut xyz = [DVec3::ZERO; 3];
            packed.colours(blocks, at, -omega_i.z - omega_r.z, &mut xyz);
            let m = monomials(omega_i);
            for (o, c) in out.iter_mut().zip(&xyz) {
                for (s, m) in o.0.iter_mut().zip(m) {
                    *s += *c * (f * m);
                }
            }
        }
    }
    for o in &mut out {
        o.0 = o.0.map(xyz_to_linear_srgb);
        o.1 = xyz_to_linear_srgb(o.1);
    }
    out
}

/// The factors beside a texel's colour at ω_i, per unit area of (u, v): the gain, the shadowing, 1/cos θ_i.
fn factor(omega_i: DVec3, omega_r: DVec3) -> f64 {
    use crate::physics::optics::{gain_factor, shadow_mask};
    gain_factor(omega_i, omega_r) * shadow_mask(omega_i, omega_r) / omega_i.z
}

/// Adds texel (a, b) of `packed`'s level to `out` (the sums of [`moments_of_bands`]), when it lies in the level.
fn texel_sums(packed: &Packed, a: usize, b: usize, omega_r: DVec3, out: &mut Sums) {
    let (first, texel, fine) = (packed.first, packed.texel, &packed.fine);
    if a >= fine.width || b >= fine.height {
        return;
    }
    // Skip the texel where no band is bright there or no ω_i of it is above the surface.
    let Some(at) = fine.start[b * fine.width + a] else { return };
    let (ua, va) = (first.grid.u0 + a as f64 * texel, first.grid.v0 + b as f64 * texel);
    let (cx, cy) = (-(ua + 0.5 * texel) - omega_r.x, -(va + 0.5 * texel) - omega_r.y);
    if (cx * cx + cy * cy).sqrt() > 1.0 + texel {
        return;
    }
    let mut xyz = [DVec3::ZERO; 3];
    let (uc, vc) = (ua + 0.5 * texel, va + 0.5 * texel);
    if (uc * uc + vc * vc).sqrt() < SPECULAR_RADIUS {
        // All of it leaves along the mirror direction, which is above the surface even where part of the texel is
        // not (beyond ~76°: counting only that part lost a quarter of a mirror's light at 87°); its factors there
        // (a texel's centre can lie half a texel off it, where at 70° the factors differ by 5 %).
        let mirror = DVec3::new(-omega_r.x, -omega_r.y, omega_r.z);
        packed.colours(fine, at, -2.0 * omega_r.z, &mut xyz);
        let f = factor(mirror, omega_r) * texel * texel;
        for (o, c) in out.iter_mut().zip(&xyz) {
            o.1 += *c * f;
        }
        return;
    }
    let mut factors = [0.0; MONOMIALS];
    let mut w_sum = (0.0, 0.0);
    // Sub-samples only where the texel meets the rim (its partial coverage, 1/cos θ_i's rise).
    let sub = if (cx * cx + cy * cy).sqrt() > 1.0 - 2.0 * texel { FACTOR_SUBSAMPLES } else { 1 };
    let sub_area = (texel / sub as f64).powi(2);
    for k in 0..sub * sub {
        let u = ua + ((k % sub) as f64 + 0.5) / sub as f64 * texel;
        let v = va + ((k / sub) as f64 + 0.5) / sub as f64 * texel;
        let (x, y) = (-u - omega_r.x, -v - omega_r.y);
        let r2 = x * x + y * y;
        if r2 >= 1.0 {
            continue;
        }
        let omega_i = DVec3::new(x, y, (1.0 - r2).sqrt());
        let f = factor(omega_i, omega_r) * sub_area;
        for (s, m) in factors.iter_mut().zip(monomials(omega_i)) {
            *s += f * m;
        }
        w_sum = (w_sum.0 + f, w_sum.1 + f * (-omega_i.z - omega_r.z));
    }
    if w_sum.0 <= 0.0 {
        return;
    }
    // The texel's colour at its factors' mean w.
    packed.colours(fine, at, w_sum.1 / w_sum.0, &mut xyz);
    for (o, c) in out.iter_mut().zip(&xyz) {
        for (s, f) in o.0.iter_mut().zip(factors) {
            *s += *c * f;
        }
    }
}

/// Whether two tables' moment levels lie on one geometry (origin, texel and size), so that their moments can share
/// the factors ([`moments_of_bands`]).
fn same_level(a: &BakedTable, b: &BakedTable) -> bool {
    let ((la, ta), (lb, tb)) = (moment_level(a), moment_level(b));
    let (x, y) = (&a.levels[la], &b.levels[lb]);
    ta == tb
        && (a.grid.u0, a.grid.v0, a.grid.w, a.grid.segments) == (b.grid.u0, b.grid.v0, b.grid.w, b.grid.segments)
        && (x.width, x.height) == (y.width, y.height)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_survive_the_cache_and_a_damaged_payload_is_refused() {
        let grid = 3;
        let values = (0..grid * grid)
            .map(|i| {
                std::array::from_fn(|j| DMat3::from_cols_array(&std::array::from_fn(|e| (i * 100 + j * 10 + e) as f64)))
            })
            .collect();
        let specular = (0..grid * grid).map(|i| DMat3::from_diagonal(DVec3::splat(i as f64 * 0.25))).collect();
        let m = Moments { grid, values, specular };
        let bytes = m.to_bytes();
        assert_eq!(Moments::from_bytes(&bytes), Some(m.clone()));
        assert_eq!(Moments::from_bytes(&bytes[..bytes.len() - 8]), None, "truncated");
        let mut nan = bytes.clone();
        nan[16..24].copy_from_slice(&f64::NAN.to_le_bytes());
        assert_eq!(Moments::from_bytes(&nan), None, "a NaN moment");
        assert_eq!(Moments::from_bytes(&[bytes.clone(), vec![0; 8]].concat()), None, "trailing bytes");
    }

    /// The basis' bands sum to D65: a D65-coloured light is the three bands in D65's own proportions (each band's
    /// share of its luminance: the tables are per unit luminance of their band), whatever its luminance; the
    /// bands' colours are far enough apart that A⁻¹ amplifies a colour's error by little (its condition number).
    #[test]
    fn the_spectral_basis_gives_back_d65_and_is_well_conditioned() {
        use crate::physics::illuminant::Illuminant;
        use crate::physics::spectrum::{white_rgb, Sampling};
        let a = basis_colours();
        let c = a.inverse() * (white_rgb(Illuminant::d65()) * 0.37);
        let bands = [0, 1, 2].map(Illuminant::d65_band);
        let luminance = |i: Illuminant| Sampling::visible_under(1.0, i).y_norm();
        let share = DVec3::from(bands.map(luminance)) / luminance(Illuminant::d65());
        assert!((c - share * 0.37).abs().max_element() < 1e-9, "{c} against {}", share * 0.37);
        // Each band positive, and the three D65 again, at every row of the table.
        for (i, d) in Illuminant::d65().spd.iter().enumerate() {
            assert!(bands.iter().all(|b| b.spd[i] > 0.0));
            assert!((bands.iter().map(|b| b.spd[i]).sum::<f64>() - d).abs() < 1e-9 * d);
        }
        // Frobenius norms, the columns made unit vectors (their scale is each band's luminance, a choice of units):
        // an upper bound of the 2-norm condition number.
        let unit = DMat3::from_cols(a.x_axis.normalize(), a.y_axis.normalize(), a.z_axis.normalize());
        let norm = |m: DMat3| m.to_cols_array().iter().map(|v| v * v).sum::<f64>().sqrt();
        let condition = norm(unit) * norm(unit.inverse());
        assert!(condition < 5.0, "condition number ≤ {condition}: {a}");
    }

    #[test]
    fn the_quadratic_form_is_the_projected_light_in_any_frame() {
        // A light within l ≤ 2: its projection is itself, and the quadratic form gives it back in any frame.
        let light = |d: DVec3| DVec3::new(1.0 + 0.5 * d.y + 0.3 * d.x * d.z, 2.0 - d.z * d.z, 0.5 + 0.25 * d.x);
        let irradiance = Irradiance::of(light, 400);
        let q = Quadratic::of_irradiance(&irradiance);
        let frame = DMat3::from_quat(glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7));
        for d in [DVec3::Y, DVec3::X, DVec3::new(0.3, -0.5, 0.81).normalize(), DVec3::new(-0.7, 0.1, -0.7).normalize()]
        {
            assert!((q.radiance(d) - light(d)).abs().max_element() < 2e-3, "{d}: {} vs {}", q.radiance(d), light(d));
            let w = frame.transpose() * d;
            let a = q.coefficients(frame);
            let by_monomials: DVec3 = a.iter().zip(monomials(w)).map(|(a, m)| *a * m).sum();
            assert!((by_monomials - q.radiance(d)).abs().max_element() < 1e-9);
        }
    }
}
