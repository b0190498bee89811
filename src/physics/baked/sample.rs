//! Reading a baked table as the shader does (`baked_xyz` in glsl/include/baked.glsl, same names): texel
//! coordinates of (u, v), the mip level of a footprint, bilinear filtering with clamped edges within a level and
//! between two levels or from the nearest one ([`MipFilter`]), and the Chebyshev sum in w. The CPU twin lets tests
//! read the table the GPU reads without a GPU.

use glam::DVec3;

use crate::physics::baked::{BakedTable, TableLevel, LAYER_CHANNELS};

/// How much finer than a pixel's footprint F the mip level is chosen, log2 √3: a trilinear fetch averages a
/// level's texels (a box of variance T²/12) and interpolates bilinearly between them (a tent, T²/6); together they
/// match the pixel's box (F²/12) for T = F/√3. Without it the filter spans about twice the footprint (measured on a
/// 16² map against a 3×3-sampled reference: mean ΔE00 6.3 unbiased, 1.1 biased, 2.6 for point sampling). One
/// source with the shaders' (`shaders::interface`).
pub const FOOTPRINT_LOD_BIAS: f64 = crate::gpu::interface::FOOTPRINT_LOD_BIAS;
use crate::physics::chebyshev;

/// How a read of the table goes between its mip levels (the sampler's mipmap mode, `render::diffraction`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MipFilter {
    /// Trilinear: the two levels either side of the LOD, each read bilinearly, blended by its fraction (8 texels a
    /// read).
    Linear,
    /// The level nearest the LOD, read bilinearly (4 texels a read: half). A LOD exactly halfway between two levels
    /// may go to either (Vulkan lets a device round it either way).
    Nearest,
}

/// Which [`MipFilter`] the surface and map passes read the table with (the `table_mips` setting).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TableMips {
    /// Nearest on a CPU device (lavapipe), where a trilinear read costs two bilinear ones; linear on a GPU, whose
    /// texture units blend two levels at no extra cost.
    #[default]
    Auto,
    Linear,
    Nearest,
}

impl MipFilter {
    /// Texels one read takes: 2 × 2 in each of two levels, or in one.
    pub fn texels_per_read(self) -> u32 {
        match self {
            MipFilter::Linear => 8,
            MipFilter::Nearest => 4,
        }
    }
}

impl TableMips {
    pub const ALL: [TableMips; 3] = [TableMips::Auto, TableMips::Linear, TableMips::Nearest];

    pub fn name(self) -> &'static str {
        match self {
            TableMips::Auto => "auto",
            TableMips::Linear => "linear",
            TableMips::Nearest => "nearest",
        }
    }

    /// The filter on a device that is a CPU (`cpu_device`) or not.
    pub fn filter(self, cpu_device: bool) -> MipFilter {
        match self {
            TableMips::Linear => MipFilter::Linear,
            TableMips::Nearest => MipFilter::Nearest,
            TableMips::Auto if cpu_device => MipFilter::Nearest,
            TableMips::Auto => MipFilter::Linear,
        }
    }
}

impl BakedTable {
    /// Level-0 texel coordinates of (u, v), texel centres at integers + ½ (the sampler's convention).
    pub fn texel_coords(&self, u: f64, v: f64) -> (f64, f64) {
        let g = &self.grid;
        ((u - g.u0) / g.texel, (v - g.v0) / g.texel)
    }

    /// The mip level for a pixel whose footprint in (u, v) is `footprint` (see [`FOOTPRINT_LOD_BIAS`]), clamped
    /// to the levels there are.
    pub fn lod(&self, footprint: f64) -> f64 {
        let levels = (self.levels.len() - 1) as f64;
        // NaN and footprints within a texel read level 0.
        match footprint.partial_cmp(&self.grid.texel) {
            Some(std::cmp::Ordering::Greater) => {
                ((footprint / self.grid.texel).log2() - FOOTPRINT_LOD_BIAS).clamp(0.0, levels)
            }
            _ => 0.0,
        }
    }

    /// XYZ (relative to a D65 mirror, before the gain and the shadowing) at `uvw`, mip level `lod`, trilinear.
    pub fn xyz(&self, uvw: DVec3, lod: f64) -> DVec3 {
        self.xyz_filtered(uvw, lod, MipFilter::Linear)
    }

    /// [`Self::xyz`] read between the mip levels as `filter` says.
    pub fn xyz_filtered(&self, uvw: DVec3, lod: f64, filter: MipFilter) -> DVec3 {
        let lod = lod.clamp(0.0, (self.levels.len() - 1) as f64);
        let lod = match filter {
            MipFilter::Linear => lod,
            MipFilter::Nearest => (lod + 0.5).floor(),
        };
        let (lo, frac) = (lod.floor() as usize, lod - lod.floor());
        let (x, y) = self.texel_coords(uvw.x, uvw.y);
        let (nx, ny) = (x / self.grid.nu as f64, y / self.grid.nv as f64);
        let (segment, t) = self.grid.segment_of(uvw.z);
        let mut scalars = self.bilinear(&self.levels[lo], nx, ny, segment);
        if frac > 0.0 && lo + 1 < self.levels.len() {
            let hi = self.bilinear(&self.levels[lo + 1], nx, ny, segment);
            for (s, h) in scalars.iter_mut().zip(hi) {
                *s += frac * (h - *s);
            }
        }
        self.sum(&scalars, t)
    }

    /// Texel (a, b) of mip level `level` at w, without filtering.
    pub fn level_xyz(&self, level: usize, a: usize, b: usize, w: f64) -> DVec3 {
        let level = &self.levels[level];
        let (segment, t) = self.grid.segment_of(w);
        let i = b * level.width + a;
        // Σ_d a_d·T_d(t) with the recurrence on the stack.
        let (mut previous, mut current) = (1.0, 1.0);
        let mut xyz = [0.0; 3];
        for d in 0..self.terms {
            let td = match d {
                0 => 1.0,
                1 => t,
                _ => 2.0 * t * current - previous,
            };
            if d > 0 {
                (previous, current) = (current, td);
            }
            for (c, v) in xyz.iter_mut().enumerate() {
                *v += self.scalar(level, i, segment, 3 * d + c) * td;
            }
        }
        DVec3::from(xyz).max(DVec3::ZERO)
    }

    /// The level-0 texel (a, b) at w, without filtering.
    pub fn texel_xyz(&self, a: usize, b: usize, w: f64) -> DVec3 {
        self.level_xyz(0, a, b, w)
    }

    /// Scalar `s` (coefficient s / 3 of channel s % 3) of `segment` in texel `i` (row-major) of `level`.
    fn scalar(&self, level: &TableLevel, i: usize, segment: usize, s: usize) -> f64 {
        let n = level.width * level.height;
        let layer = segment * self.layers_per_read() + s / LAYER_CHANNELS;
        f64::from(level.texels[(layer * n + i) * LAYER_CHANNELS + s % LAYER_CHANNELS])
    }

    /// Every stored coefficient of texel `i` (row-major) of `level`, over every segment.
    pub fn texel_coefficients<'a>(&'a self, level: &'a TableLevel, i: usize) -> impl Iterator<Item = f64> + 'a {
        (0..self.grid.segments)
            .flat_map(move |segment| (0..3 * self.terms).map(move |s| self.scalar(level, i, segment, s)))
    }

    /// Σ_d a_d·T_d(t) per channel, clamped at 0 (XYZ of light is never negative; interpolation can ring).
    fn sum(&self, scalars: &[f64], t: f64) -> DVec3 {
        let t = chebyshev::polynomials(t, self.terms);
        let mut xyz = [0.0; 3];
        for (s, &a) in scalars.iter().enumerate().take(3 * self.terms) {
            xyz[s % 3] += a * t[s / 3];
        }
        DVec3::from(xyz).max(DVec3::ZERO)
    }

    /// Every scalar of a segment of a level at normalised coordinates, bilinear between texel centres, edges
    /// clamped.
    fn bilinear(&self, level: &TableLevel, nx: f64, ny: f64, segment: usize) -> Vec<f64> {
        let (w, h) = (level.width, level.height);
        let (fx, fy) = (nx * w as f64 - 0.5, ny * h as f64 - 0.5);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let clamp = |i: f64, n: usize| (i.max(0.0) as usize).min(n - 1);
        let (xa, xb, ya, yb) = (clamp(x0, w), clamp(x0 + 1.0, w), clamp(y0, h), clamp(y0 + 1.0, h));
        (0..3 * self.terms)
            .map(|s| {
                let at = |x: usize, y: usize| self.scalar(level, y * w + x, segment, s);
                let top = at(xa, ya) + tx * (at(xb, ya) - at(xa, ya));
                let bottom = at(xa, yb) + tx * (at(xb, yb) - at(xa, yb));
                top + ty * (bottom - top)
            })
            .collect()
    }
}
