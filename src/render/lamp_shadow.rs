//! The lamps' shadows (model.md §3.9): for each lamp a perspective depth map drawn from the lamp's centre, fitted
//! to the casters that lie between it and what the camera sees ([`LampShadowFrame::fit`]), the maps side by side
//! in one atlas (a tile per lamp), redrawn only when a lamp, the placements or the casters change. The surface
//! pass and the G-buffer read them (`lamp_visibility` in glsl/include/shadow.glsl) as they read the sun's: a point
//! pushed off its surface by `SHADOW_NORMAL_OFFSET_TEXELS` of the tile's texels there, the mean depth of the
//! casters in front of it setting the penumbra of the lamp's disc (`radius_m`). A map opens at most
//! [`MAX_HALF_ANGLE_DEG`] from its axis; a lamp inside a caster's box casts no shadow, said once.

use std::cell::RefCell;

use ash::vk;
use glam::{Mat4, Vec3, Vec4};

use crate::error::Result;
use crate::gpu::interface::{SurfaceUniforms, BINDING_LAMP_SHADOW, BINDING_LAMP_SHADOW_DEPTH, MAX_LAMPS};
use crate::gpu::vk::{Buffer, BufferDesc, Context, DescriptorWrite, Guard};
use crate::light::lamp::LampUniforms;
use crate::render::shadow::{Aabb, DepthMap};
use crate::render::MeshBuffers;

/// Texels along each edge of a lamp's tile (D32: 4 MiB a lamp).
pub const LAMP_SHADOW_SIZE: u32 = 1024;
/// The widest a lamp's map opens (half-angle from its axis, towards the casters' centre): casters spread wider
/// (a floor under the lamp) cast shadows within that cone only.
pub const MAX_HALF_ANGLE_DEG: f32 = 60.0;
/// The pass's name (labels, timings).
pub const NAME: &str = "lamp shadow maps";

/// Where one lamp's map lies: its view-projection (world → the tile's clip space: depth 0 at the near plane, 1 at
/// the far one; w the depth along the lamp's axis), the planes' depths along the axis, and the width of a texel at
/// depth 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LampShadowFrame {
    pub view_proj: Mat4,
    pub near: f32,
    pub far: f32,
    pub texel_at_unit_depth: f32,
}

/// Why a lamp casts no shadow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoShadow {
    /// No caster lies between it and what the camera sees.
    NothingCasts,
    /// It lies within a caster's box.
    AmongCasters,
}

impl LampShadowFrame {
    /// The map of a lamp at `position` (world) over `boxes` (placed objects, whether each casts) of which the
    /// camera sees `seen` (the receivers' box cut to the view): aimed at the casters that lie in the box around
    /// the lamp and `seen` (only they can shadow a point the camera sees), just wide enough for them (two texels'
    /// margin for the filter) but at most [`MAX_HALF_ANGLE_DEG`] from its axis, from before the nearest caster to
    /// past the farthest point seen.
    pub fn fit(position: Vec3, boxes: &[(Aabb, bool)], seen: &Aabb, size: u32) -> std::result::Result<Self, NoShadow> {
        let reach = seen.union(&Aabb { min: position, max: position });
        let casters: Vec<Aabb> = boxes.iter().filter(|b| b.1).filter_map(|b| b.0.intersection(&reach)).collect();
        if casters.is_empty() {
            return Err(NoShadow::NothingCasts);
        }
        // The nearest any caster comes to the lamp (0: the lamp is inside one's box).
        let nearest = casters.iter().map(|b| b.distance_to(position)).fold(f32::INFINITY, f32::min);
        if nearest <= 0.0 {
            return Err(NoShadow::AmongCasters);
        }
        let all = casters.iter().skip(1).fold(casters[0], |a, b| a.union(b));
        let axis = (0.5 * (all.min + all.max) - position).try_normalize().ok_or(NoShadow::AmongCasters)?;
        let up = if axis.y.abs() < 0.99 { Vec3::Y } else { Vec3::Z };
        let view = crate::scene::camera::look_at(position, position + axis, up);
        // Just wide enough for every caster's corners, at most MAX_HALF_ANGLE_DEG (a caster that reaches
        // beside or behind the lamp — a floor under it — is covered within that cone).
        let max_tan = MAX_HALF_ANGLE_DEG.to_radians().tan();
        let mut tan = 0f32;
        for v in casters.iter().flat_map(|b| b.corners()).map(|c| view.transform_point3(c)) {
            let depth = -v.z;
            tan = match depth > 0.0 {
                true => tan.max(v.x.abs().max(v.y.abs()) / depth),
                false => max_tan,
            };
            if tan >= max_tan {
                break;
            }
        }
        // Two texels of margin each side.
        let tan = tan.clamp(1e-6, max_tan) * size as f32 / (size as f32 - 4.0).max(1.0);
        // The near plane before every caster point within the map (the frustum's corner is the widest angle from
        // the axis); the far one past every caster and every point seen.
        let near = 0.99 * nearest * (std::f32::consts::SQRT_2 * tan).atan().cos();
        let far = (casters.iter().chain([seen]))
            .flat_map(|b| b.corners())
            .map(|c| -view.transform_point3(c).z)
            .fold(near * 1.01, f32::max)
            * 1.01;
        let proj = perspective(tan, near, far);
        Ok(Self { view_proj: proj * view, near, far, texel_at_unit_depth: 2.0 * tan / size as f32 })
    }

    /// The uniforms' share of a lamp's shadow: its view-projection's columns, and (near, far, a texel at depth 1,
    /// the disc's radius `radius_m`).
    fn columns_and_scales(&self, radius_m: f32) -> ([[f32; 4]; 4], [f32; 4]) {
        (self.view_proj.to_cols_array_2d(), [self.near, self.far, self.texel_at_unit_depth, radius_m])
    }
}

/// A perspective projection looking down −z (the half-field's tangent `tan` both ways) to Vulkan's clip space:
/// depth 0 at `near`, 1 at `far`; w the depth along the axis.
fn perspective(tan: f32, near: f32, far: f32) -> Mat4 {
    let range = far - near;
    Mat4::from_cols(
        Vec4::new(1.0 / tan, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0 / tan, 0.0, 0.0),
        Vec4::new(0.0, 0.0, -far / range, -1.0),
        Vec4::new(0.0, 0.0, -far * near / range, 0.0),
    )
}

/// What the surface uniforms hold of the lamps' shadows (`SurfaceUniforms::lamp_shadow_view_proj`,
/// `lamp_shadow_scales` and `lamp_atlas`); a lamp that casts none has zero scales.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LampShadowUniforms {
    pub view_proj: [[f32; 4]; 32],
    pub scales: [[f32; 4]; 8],
    pub atlas: [f32; 4],
}

impl LampShadowUniforms {
    /// No lamp casts a shadow.
    pub const NONE: Self = Self { view_proj: [[0.0; 4]; 32], scales: [[0.0; 4]; 8], atlas: [1.0, 1.0, 0.0, 0.0] };

    /// `frames` (one per lamp of `lamps`) in an atlas of tiles `size` texels square; [`Self::NONE`] where none
    /// casts a shadow.
    pub fn new(frames: &[Option<LampShadowFrame>], lamps: &LampUniforms, size: u32) -> Self {
        if frames.iter().all(Option::is_none) {
            return Self::NONE;
        }
        let mut out = Self { atlas: [frames.len().max(1) as f32, 1.0 / size as f32, 0.0, 0.0], ..Self::NONE };
        for (k, (frame, (_, radius))) in frames.iter().zip(discs(lamps)).take(MAX_LAMPS as usize).enumerate() {
            if let Some(f) = frame {
                let (columns, scales) = f.columns_and_scales(radius);
                out.view_proj[4 * k..4 * k + 4].copy_from_slice(&columns);
                out.scales[k] = scales;
            }
        }
        out
    }
}

/// Each lamp's position (world) and disc radius, from the surface uniforms' lamps.
fn discs(lamps: &LampUniforms) -> impl Iterator<Item = (Vec3, f32)> + '_ {
    let stride = crate::gpu::interface::LAMP_VEC4S as usize;
    (0..lamps.count[0] as usize).map(move |k| {
        let [x, y, z, _] = lamps.lamps[stride * k];
        (Vec3::new(x, y, z), lamps.lamps[stride * k + 2][3])
    })
}

/// Each of `lamps`' frames over `boxes` (placed objects, whether each casts) seen through the camera's
/// `view_proj`; a lamp among the casters is said once a process.
pub fn fit_all(lamps: &LampUniforms, boxes: &[(Aabb, bool)], view_proj: Mat4) -> Vec<Option<LampShadowFrame>> {
    let seen = crate::render::shadow::seen_box(boxes, view_proj);
    discs(lamps)
        .enumerate()
        .map(|(k, (position, _))| {
            let seen = seen.as_ref()?;
            match LampShadowFrame::fit(position, boxes, seen, LAMP_SHADOW_SIZE) {
                Ok(frame) => Some(frame),
                Err(NoShadow::NothingCasts) => None,
                Err(NoShadow::AmongCasters) => {
                    static SAID: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
                    if !SAID.swap(true, std::sync::atomic::Ordering::Relaxed) {
                        log::warn!(
                            "lamp {} casts no shadows: it lies within the box of an object that casts them; move it \
                             outside",
                            k + 1
                        );
                    }
                    None
                }
            }
        })
        .collect()
}

/// The lamps' shadow atlas on the GPU: its depth image (1×1 while no lamp casts a shadow), the comparison and
/// depth samplers, the depth-only pipeline and one uniform buffer per lamp and object.
pub struct LampShadows {
    map: DepthMap,
    /// Per lamp (tile), per object.
    uniforms: Vec<Vec<Buffer>>,
    /// The objects it draws.
    objects: usize,
    frames: Vec<Option<LampShadowFrame>>,
    models: Vec<[[f32; 4]; 4]>,
    drawn: RefCell<Option<Drawn>>,
}

/// What the atlas's depths depend on (the camera only through the frames).
#[derive(Clone, Debug, PartialEq)]
struct Drawn {
    frames: Vec<Option<LampShadowFrame>>,
    models: Vec<[[f32; 4]; 4]>,
    casts: Vec<bool>,
}

impl LampShadows {
    /// An atlas of `tiles` tiles (`size` texels square; 1×1 for none) for `objects` objects.
    pub fn new(ctx: &Context, tiles: u32, objects: usize, size: u32) -> Result<Self> {
        let (width, height) = if tiles == 0 { (1, 1) } else { (tiles * size, size) };
        let map = Guard::new(ctx, DepthMap::new(ctx, width, height, NAME)?);
        let mut uniforms = Guard::new(ctx, Vec::with_capacity(tiles as usize));
        for k in 0..tiles {
            let mut each = Vec::with_capacity(objects);
            for i in 0..objects {
                let desc = BufferDesc::upload(
                    std::mem::size_of::<SurfaceUniforms>() as u64,
                    vk::BufferUsageFlags::UNIFORM_BUFFER,
                );
                match ctx.create_buffer(desc, &format!("object {i} uniforms (lamp {k}'s shadow)")) {
                    Ok(b) => each.push(b),
                    Err(e) => {
                        // SAFETY: just made, never used.
                        each.into_iter().for_each(|b: Buffer| unsafe { b.destroy(ctx) });
                        return Err(e);
                    }
                }
            }
            uniforms.push(each);
        }
        Ok(Self {
            map: map.keep(),
            uniforms: uniforms.keep(),
            objects,
            frames: Vec::new(),
            models: Vec::new(),
            drawn: RefCell::new(None),
        })
    }

    /// The tiles it holds (0 for the 1×1 stand-in).
    pub fn tiles(&self) -> u32 {
        self.uniforms.len() as u32
    }

    /// Texels along a tile's edge.
    pub fn size(&self) -> u32 {
        self.map.image.extent().height
    }

    /// Where each of `lamps`' maps lies over `boxes` (placed objects, whether each casts) seen through the
    /// camera's `view_proj` ([`fit_all`]); the atlas made anew, a tile per lamp, the first time they cast one. No
    /// submitted work may still read it.
    pub fn fit(
        &mut self,
        ctx: &Context,
        lamps: &LampUniforms,
        boxes: &[(Aabb, bool)],
        view_proj: Mat4,
    ) -> Result<Vec<Option<LampShadowFrame>>> {
        if lamps.count[0] < 1.0 {
            return Ok(Vec::new());
        }
        let frames = fit_all(lamps, boxes, view_proj);
        if frames.iter().any(Option::is_some) && self.tiles() != frames.len() as u32 {
            let atlas = Self::new(ctx, frames.len() as u32, self.objects, LAMP_SHADOW_SIZE)?;
            // SAFETY: the caller promises no submitted work still uses it.
            unsafe { std::mem::replace(self, atlas).destroy(ctx) };
        }
        Ok(frames)
    }

    /// Places the maps for this frame and writes each lamp's objects' uniforms (`objects`: the surface pass's, the
    /// view-projection replaced by the lamp's); no submitted work may still read them.
    pub fn update(&mut self, frames: &[Option<LampShadowFrame>], objects: &[SurfaceUniforms]) -> Result<()> {
        self.frames = frames.to_vec();
        self.models = objects.iter().map(|u| u.model).collect();
        for (frame, buffers) in frames.iter().zip(&mut self.uniforms) {
            let Some(f) = frame else { continue };
            for (buffer, u) in buffers.iter_mut().zip(objects) {
                buffer
                    .write(bytemuck::bytes_of(&SurfaceUniforms { view_proj: f.view_proj.to_cols_array_2d(), ..*u }))?;
            }
        }
        Ok(())
    }

    /// Records the atlas (each lamp's casters in its tile) and leaves it ready to sample, unless it already holds
    /// the same frames, placements and casters (as `ShadowMap::record`, whose ordering rules hold here too).
    pub(crate) fn record<'a>(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        meshes: impl Iterator<Item = (&'a MeshBuffers, bool)>,
    ) {
        let meshes: Vec<(&MeshBuffers, bool)> = meshes.collect();
        let now = Drawn {
            frames: self.frames.clone(),
            models: self.models.clone(),
            casts: meshes.iter().map(|m| m.1).collect(),
        };
        if self.drawn.borrow().as_ref() == Some(&now) {
            return;
        }
        self.map.begin(ctx, cmd, NAME);
        let size = self.size();
        for (k, (frame, buffers)) in self.frames.iter().zip(&self.uniforms).enumerate() {
            if frame.is_none() {
                continue;
            }
            let x = k as u32 * size;
            let viewport = vk::Viewport {
                x: x as f32,
                y: 0.0,
                width: size as f32,
                height: size as f32,
                min_depth: 0.0,
                max_depth: 1.0,
            };
            let tile = vk::Rect2D {
                offset: vk::Offset2D { x: x as i32, y: 0 },
                extent: vk::Extent2D { width: size, height: size },
            };
            // SAFETY: inside the rendering begun above; the pipeline sets the viewport and scissor dynamically.
            unsafe {
                ctx.device().cmd_set_viewport(cmd, 0, &[viewport]);
                ctx.device().cmd_set_scissor(cmd, 0, &[tile]);
            }
            self.map.draw_casters(ctx, cmd, &meshes, buffers);
        }
        self.map.end(ctx, cmd);
        *self.drawn.borrow_mut() = Some(now);
    }

    /// The descriptors that bind it for reading.
    pub fn writes(&self) -> [DescriptorWrite<'_>; 2] {
        self.map.writes(BINDING_LAMP_SHADOW, BINDING_LAMP_SHADOW_DEPTH)
    }

    /// # Safety
    /// The GPU must be done with it.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.map.destroy(ctx);
        self.uniforms.into_iter().flatten().for_each(|b| b.destroy(ctx));
    }
}

crate::impl_destroy!(LampShadows);

#[cfg(test)]
mod tests {
    use super::*;

    fn cube(centre: Vec3, half: f32) -> Aabb {
        Aabb { min: centre - Vec3::splat(half), max: centre + Vec3::splat(half) }
    }

    #[test]
    fn a_lamps_map_holds_its_casters_and_reaches_past_what_is_seen() {
        let lamp = Vec3::new(0.0, 2.0, 0.0);
        let ball = cube(Vec3::new(0.5, 1.0, 0.0), 0.1);
        let ground = Aabb { min: Vec3::new(-5.0, 0.0, -5.0), max: Vec3::new(5.0, 0.0, 5.0) };
        let f = LampShadowFrame::fit(lamp, &[(ball, true), (ground, false)], &ground, 256).unwrap();
        for c in ball.corners() {
            let q = f.view_proj * c.extend(1.0);
            let ndc = q.truncate() / q.w;
            assert!(ndc.x.abs() < 1.0 && ndc.y.abs() < 1.0 && (0.0..=1.0).contains(&ndc.z), "{c} → {ndc}");
        }
        // The ray from the lamp through the ball's centre meets the ground at x = 1: the same texel, deeper.
        let (at_ball, on_ground) =
            (f.view_proj * Vec4::new(0.5, 1.0, 0.0, 1.0), f.view_proj * Vec4::new(1.0, 0.0, 0.0, 1.0));
        let (a, g) = (at_ball.truncate() / at_ball.w, on_ground.truncate() / on_ground.w);
        assert!((a.x - g.x).abs() < 1e-5 && (a.y - g.y).abs() < 1e-5 && a.z < g.z && g.z <= 1.0, "{a} {g}");
        // w is the depth along the axis: the linear depth the penumbra works in.
        assert!(
            (on_ground.w
                - (lamp - Vec3::new(1.0, 0.0, 0.0)).dot((ball.min + ball.max) * 0.5 - lamp).abs()
                    / ((ball.min + ball.max) * 0.5 - lamp).length())
            .abs()
                < 1e-4
        );
        // No caster: no map; a lamp inside a caster: none either.
        assert_eq!(LampShadowFrame::fit(lamp, &[(ground, false)], &ground, 256), Err(NoShadow::NothingCasts));
        assert_eq!(LampShadowFrame::fit(lamp, &[(cube(lamp, 1.0), true)], &ground, 256), Err(NoShadow::AmongCasters));
        // A floor that casts, spread beside and under the lamp: a map within the widest cone, its near plane before
        // the floor's nearest point (the lamp's foot, 2 below).
        let floor = LampShadowFrame::fit(lamp, &[(ball, true), (ground, true)], &ground, 256).unwrap();
        let opened = floor.texel_at_unit_depth * 256.0 / 2.0;
        assert!(opened <= MAX_HALF_ANGLE_DEG.to_radians().tan() * 1.02 && opened > 1.0, "{opened}");
        assert!(floor.near > 0.0 && floor.near < 2.0 && floor.far > 2.0, "{floor:?}");
        let foot = floor.view_proj * Vec4::new(0.0, 0.0, 0.0, 1.0);
        assert!((0.0..=1.0).contains(&(foot.z / foot.w)), "{foot}");
    }
}
