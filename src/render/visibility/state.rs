//! The visibility path's GPU state for one frame size: the ids' target, the coverage depth, each object's vertex
//! outputs and edge lists, and the barriers between the path's passes and between its frames.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::interface::{
    VERTEX_OUTPUT_VEC4S, VISIBILITY_EDGE_GROUP, VISIBILITY_MAX_SAMPLES, VISIBILITY_OBJECT_SHIFT,
};
use crate::gpu::vk::{Buffer, BufferDesc, Context, Guard, Image, ImageDesc, ImageState, MemoryState, Sampler};
use crate::render::MeshBuffers;

/// The vertex shader's storage writes, before the shading pass's fragment shader reads them.
pub(crate) const VERTEX_STORAGE_WRITE: MemoryState =
    MemoryState { stage: vk::PipelineStageFlags2::VERTEX_SHADER, access: vk::AccessFlags2::SHADER_STORAGE_WRITE };

/// Where the previous frame left the ids (read by its shading pass), the coverage depth (tested there) and the
/// vertex outputs (read there): this frame's raster pass writes them anew only after those reads.
pub(crate) const IDS_READ: ImageState =
    ImageState::new(vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::FRAGMENT_SHADER, vk::AccessFlags2::NONE);
pub(crate) const COVERAGE_TESTED: ImageState = ImageState::new(
    vk::ImageLayout::UNDEFINED,
    vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw() | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
    ),
    vk::AccessFlags2::NONE,
);
pub(crate) const OUTPUTS_READ: MemoryState =
    MemoryState { stage: vk::PipelineStageFlags2::FRAGMENT_SHADER, access: vk::AccessFlags2::NONE };

/// The raster pass's depth writes and its resolve, before the shading pass tests against the result.
pub(crate) const DEPTH_WRITTEN: MemoryState = MemoryState {
    stage: vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw()
            | vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT.as_raw(),
    ),
    access: vk::AccessFlags2::from_raw(
        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw() | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE.as_raw(),
    ),
};
pub(crate) const DEPTH_TESTED: MemoryState = MemoryState {
    stage: vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw() | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
    ),
    access: vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
};

/// An edge-pass dispatch adding to the frame's colour (a storage image) and listing pixels for the next one...
pub(crate) const EDGES_ADDED: MemoryState = MemoryState {
    stage: vk::PipelineStageFlags2::COMPUTE_SHADER,
    access: vk::AccessFlags2::from_raw(
        vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw() | vk::AccessFlags2::SHADER_STORAGE_READ.as_raw(),
    ),
};
/// ... before the next dispatch reads its size, its list and the colour (or the next frame resets the lists).
pub(crate) const EDGES_NEXT: MemoryState = MemoryState {
    stage: vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw() | vk::PipelineStageFlags2::DRAW_INDIRECT.as_raw(),
    ),
    access: vk::AccessFlags2::from_raw(
        vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw()
            | vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
            | vk::AccessFlags2::INDIRECT_COMMAND_READ.as_raw(),
    ),
};

// Every Vulkan device runs work groups of 128 invocations (maxComputeWorkGroupSize[0] and
// maxComputeWorkGroupInvocations are at least that): the edge pass's groups need no check at run time.
const _: () = assert!(VISIBILITY_EDGE_GROUP <= 128);

/// An edge list's header as the shading pass starts it: the indirect dispatch's (x, y, z) work groups and the
/// number of pixels listed (glsl/include/visibility_shade.glsl).
const EDGES_EMPTY: [u32; 4] = [0, 1, 1, 0];

/// The largest triangle index a sample's id can hold.
const MAX_TRIANGLES: u64 = (1 << VISIBILITY_OBJECT_SHIFT) - 1;
/// The most objects the ids can tell apart (0 means none).
const MAX_OBJECTS: usize = (1 << (32 - VISIBILITY_OBJECT_SHIFT)) - 1;

/// The GPU state of the path for one frame size: the ids' target and each object's vertex outputs.
pub(crate) struct VisibilityState {
    pub ids: Image,
    pub sampler: Sampler,
    /// Where a multisampled frame's depth is resolved to one sample per pixel, above 0 (the far plane, reversed
    /// depth) wherever a sample shows an object (`resolve`: MAX, or AVERAGE, whose mean of depths ≥ 0 is above 0
    /// just as well), so that the
    /// shading pass's full-screen triangle at the far plane skips the pixels no object covers (lavapipe then
    /// skips whole blocks of them unshaded). None at one sample, where the frame's own depth serves.
    pub coverage: Option<Image>,
    /// How the depth is resolved; None where the device offers neither mode (every pixel is then shaded, and the
    /// shader finds nothing to do where no object is).
    pub resolve: Option<vk::ResolveModeFlags>,
    /// Per object, in the scene's order.
    pub outputs: Vec<Buffer>,
    /// Per object where the frame has several samples (else empty): the pixels that see more than one of its
    /// triangles, listed by the shading pass for the edge pass, one list for each further triangle a pixel may
    /// see ([`Self::edge_lists`] of [`edge_list_bytes`]: `EDGES_EMPTY`'s header, then a pixel a word).
    pub edges: Vec<Buffer>,
}

/// Whether `ctx`'s device and a frame of `samples` per pixel over objects of `triangles` each can take the path:
/// else the reason, in one line.
pub fn check(
    ctx: &Context,
    samples: vk::SampleCountFlags,
    triangles: impl ExactSizeIterator<Item = u32>,
) -> Result<()> {
    if !ctx.has_visibility_buffer() {
        return Err(Error::unsupported(
            &ctx.info.name,
            format!(
                "{} cannot draw a visibility buffer (it lacks geometryShader, vertexPipelineStoresAndAtomics or \
                 fragmentStoresAndAtomics): use the forward path",
                ctx.info.name
            ),
        ));
    }
    if samples.as_raw() > VISIBILITY_MAX_SAMPLES {
        return Err(Error::setting(
            "samples",
            format!(
                "the visibility buffer takes at most {VISIBILITY_MAX_SAMPLES} samples per pixel, not {}",
                samples.as_raw()
            ),
        ));
    }
    if triangles.len() > MAX_OBJECTS {
        return Err(Error::TooLarge(format!(
            "the visibility buffer tells at most {MAX_OBJECTS} objects apart; the scene has {}",
            triangles.len()
        )));
    }
    if let Some((i, n)) = triangles.enumerate().find(|&(_, n)| u64::from(n) > MAX_TRIANGLES) {
        return Err(Error::TooLarge(format!(
            "object {i} has {n} triangles; the visibility buffer takes at most {MAX_TRIANGLES} per object"
        )));
    }
    Ok(())
}

impl VisibilityState {
    /// Makes the path's target (`extent`, `samples`) and the objects' output buffers, once [`check`] has passed.
    pub fn new(
        ctx: &Context,
        extent: vk::Extent2D,
        samples: vk::SampleCountFlags,
        meshes: &[&MeshBuffers],
    ) -> Result<Self> {
        check(ctx, samples, meshes.iter().map(|m| m.index_count / 3))?;
        let mut desc =
            ImageDesc::render_target(extent.width, extent.height, vk::Format::R32_UINT).multisampled(samples);
        desc.usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let ids = Guard::new(ctx, ctx.create_image(desc, "visibility ids")?);
        let sampler = Guard::new(ctx, ctx.create_sampler("visibility ids")?);
        let multisampled = samples != vk::SampleCountFlags::TYPE_1;
        let resolve = if multisampled { depth_resolve_mode(ctx) } else { None };
        let coverage = match multisampled {
            true => Some(ctx.create_image(ImageDesc::depth(extent.width, extent.height), "visibility coverage")?),
            false => None,
        };
        let coverage = Guard::new(ctx, coverage);
        let mut outputs = Guard::new(ctx, Vec::with_capacity(meshes.len()));
        for (i, mesh) in meshes.iter().enumerate() {
            let size = u64::from(mesh.vertex_count) * u64::from(VERTEX_OUTPUT_VEC4S) * 16;
            let desc = BufferDesc::gpu_only(size, vk::BufferUsageFlags::STORAGE_BUFFER);
            outputs.push(ctx.create_buffer(desc, &format!("object {i} vertex outputs"))?);
        }
        let mut edges = Guard::new(ctx, Vec::new());
        if multisampled {
            let size = u64::from(samples.as_raw() - 1) * edge_list_bytes(extent);
            let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::INDIRECT_BUFFER;
            for i in 0..meshes.len() {
                edges.push(ctx.create_buffer(BufferDesc::gpu_only(size, usage), &format!("object {i} edge pixels"))?);
            }
        }
        let (ids, sampler, coverage, outputs, edges) =
            (ids.keep(), sampler.keep(), coverage.keep(), outputs.keep(), edges.keep());
        Ok(Self { ids, sampler, coverage, resolve, outputs, edges })
    }

    /// # Safety
    /// The GPU must be done with it.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.ids.destroy(ctx);
        self.sampler.destroy(ctx);
        if let Some(coverage) = self.coverage {
            coverage.destroy(ctx);
        }
        for b in self.outputs.into_iter().chain(self.edges) {
            b.destroy(ctx);
        }
    }

    /// Lists in each of [`Self::edges`]: one for each triangle after a pixel's first.
    pub fn edge_lists(&self) -> u32 {
        self.ids.desc.samples.as_raw() - 1
    }

    /// Empties every object's edge list (after the previous frame's edge pass has read it), before the shading
    /// pass appends to them.
    pub fn reset_edges(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        if self.edges.is_empty() {
            return;
        }
        // The previous frame's edge pass is done with them.
        ctx.barrier_memory(cmd, EDGES_NEXT, MemoryState::TRANSFER_WRITE);
        for lists in &self.edges {
            for k in 0..u64::from(self.edge_lists()) {
                let offset = k * edge_list_bytes(self.ids.extent());
                // SAFETY: cmd is recording outside a rendering scope; the list's header lies in the live buffer.
                unsafe { ctx.device().cmd_update_buffer(cmd, lists.raw, offset, bytemuck::cast_slice(&EDGES_EMPTY)) };
            }
        }
        ctx.barrier_memory(cmd, MemoryState::TRANSFER_WRITE, MemoryState::FRAGMENT_STORAGE);
    }
}

/// Begins rendering into `color` and `depth` (images in attachment layouts) over the whole `extent`.
pub(crate) fn begin(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    color: &[vk::RenderingAttachmentInfo<'_>],
    depth: &vk::RenderingAttachmentInfo<'_>,
    extent: vk::Extent2D,
) {
    let full = vk::Rect2D { offset: vk::Offset2D::default(), extent };
    let info =
        vk::RenderingInfo::default().render_area(full).layer_count(1).color_attachments(color).depth_attachment(depth);
    // SAFETY: cmd is recording and the caller's attachments are in their attachment layouts.
    unsafe { crate::render::begin_rendering_info(ctx, cmd, &info, extent, full) };
}

/// Bytes of one edge list for frames of `extent`: its header, then room for every pixel.
pub(crate) fn edge_list_bytes(extent: vk::Extent2D) -> u64 {
    16 + 4 * u64::from(extent.width) * u64::from(extent.height)
}

/// The depth resolve that tells covered pixels from empty ones: MAX (depth is reversed), else AVERAGE
/// (lavapipe's), else none.
fn depth_resolve_mode(ctx: &Context) -> Option<vk::ResolveModeFlags> {
    let mut resolve = vk::PhysicalDeviceDepthStencilResolveProperties::default();
    let mut props = vk::PhysicalDeviceProperties2::default().push_next(&mut resolve);
    // SAFETY: a plain query on the context's physical device.
    unsafe { ctx.instance().get_physical_device_properties2(ctx.info.raw, &mut props) };
    let modes = resolve.supported_depth_resolve_modes;
    [vk::ResolveModeFlags::MAX, vk::ResolveModeFlags::AVERAGE].into_iter().find(|&m| modes.contains(m))
}

crate::impl_destroy!(VisibilityState);
