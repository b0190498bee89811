//! Shader modules, graphics pipelines (dynamic rendering) and compute pipelines, each with a push-descriptor
//! set layout (set 0) and one push-constant range; shader variants come from specialization constants.

use std::ffi::CStr;

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::vk::{Buffer, Context, Guard, Image, Sampler};

const ENTRY: &CStr = c"main";

/// A compiled shader: its SPIR-V and the descriptor bindings (set 0) it declares, both from build.rs
/// (`gpu::shaders`).
#[derive(Debug)]
pub struct Shader {
    /// `<name>.<stage>` of its source or variant (a debug label).
    pub name: &'static str,
    pub spirv: &'static [u8],
    pub bindings: &'static [ShaderBinding],
}

/// One descriptor binding of set 0, as a shader's SPIR-V declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaderBinding {
    pub binding: u32,
    pub kind: vk::DescriptorType,
}

/// A descriptor pushed at record time.
pub enum DescriptorWrite<'a> {
    StorageBuffer(u32, &'a Buffer),
    UniformBuffer(u32, &'a Buffer),
    SampledImage(u32, &'a Image, &'a Sampler),
    StorageImage(u32, &'a Image),
    /// A storage image known by its view only (a render target's, `render::TargetView::storage`).
    StorageView(u32, vk::ImageView),
}

impl DescriptorWrite<'_> {
    /// The binding it writes.
    pub fn binding(&self) -> u32 {
        match *self {
            DescriptorWrite::StorageBuffer(b, _)
            | DescriptorWrite::UniformBuffer(b, _)
            | DescriptorWrite::SampledImage(b, _, _)
            | DescriptorWrite::StorageImage(b, _)
            | DescriptorWrite::StorageView(b, _) => b,
        }
    }
}

/// Specialization-constant values (id → 4-byte value), shared by every stage of a pipeline.
#[derive(Clone, Debug, Default)]
pub struct SpecConstants {
    entries: Vec<vk::SpecializationMapEntry>,
    data: Vec<u8>,
}

impl SpecConstants {
    pub fn u32(mut self, id: u32, value: u32) -> Self {
        self.push(id, value.to_ne_bytes());
        self
    }

    pub fn i32(mut self, id: u32, value: i32) -> Self {
        self.push(id, value.to_ne_bytes());
        self
    }

    pub fn f32(mut self, id: u32, value: f32) -> Self {
        self.push(id, value.to_ne_bytes());
        self
    }

    fn push(&mut self, id: u32, bytes: [u8; 4]) {
        let offset = self.data.len() as u32;
        self.entries.push(vk::SpecializationMapEntry { constant_id: id, offset, size: 4 });
        self.data.extend_from_slice(&bytes);
    }

    fn info(&self) -> vk::SpecializationInfo<'_> {
        vk::SpecializationInfo::default().map_entries(&self.entries).data(&self.data)
    }
}

/// One vertex attribute of the single interleaved vertex buffer.
#[derive(Clone, Copy, Debug)]
pub struct VertexAttribute {
    pub location: u32,
    pub format: vk::Format,
    pub offset: u32,
}

/// How a graphics pipeline uses the depth attachment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthTest {
    /// Nearer fragments pass and write their depth: GREATER, a camera's depth being reversed (near 1, far 0:
    /// `scene::camera::perspective`).
    Write,
    /// Smaller depths pass (LESS) and are written: the shadow map's, 0 at the light.
    WriteLess,
    /// Only fragments at exactly the stored depth pass, without writing: the shading pass after a depth
    /// pre-pass, which so shades each pixel once (the vertex shader must declare `invariant gl_Position`).
    Equal,
    /// Only fragments behind the stored depth pass (LESS, reversed), without writing: a full-screen triangle at the
    /// far plane that runs only where something was drawn (the visibility buffer's shading).
    Behind,
    /// The attachment is there but not tested.
    Off,
}

/// How a graphics pipeline's colour output meets what the target holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Blend {
    /// The output replaces it.
    Replace,
    /// The output is added to it (colour and alpha): the visibility buffer's objects, each adding its share of a
    /// pixel.
    Add,
    /// The output is added under it, weighed by what its alpha leaves (1 − the target's alpha): a background
    /// drawn after objects that wrote premultiplied colour and their coverage.
    Under,
}

/// A graphics pipeline; its descriptor set layout is its shaders' bindings (each with the stages that declare it).
pub struct GraphicsPipelineDesc<'a> {
    pub name: &'a str,
    pub vertex: &'a Shader,
    /// None: a depth-only pipeline (no fragment stage, colour writes masked).
    pub fragment: Option<&'a Shader>,
    pub specialization: SpecConstants,
    pub push_constant_size: u32,
    /// Stride of the vertex buffer; 0 means no vertex input (a full-screen triangle).
    pub vertex_stride: u32,
    pub vertex_attributes: &'a [VertexAttribute],
    /// UNDEFINED: no colour attachment (a depth-only pass such as the shadow map's).
    pub color_format: vk::Format,
    /// The depth attachment's format and how it is tested, if there is one.
    pub depth: Option<(vk::Format, DepthTest)>,
    pub cull_back_faces: bool,
    /// Samples per pixel of the attachments it draws into.
    pub samples: vk::SampleCountFlags,
    pub blend: Blend,
}

/// A compute pipeline; its descriptor set layout is its shader's bindings.
pub struct ComputePipelineDesc<'a> {
    pub name: &'a str,
    pub shader: &'a Shader,
    pub specialization: SpecConstants,
    pub push_constant_size: u32,
}

pub struct Pipeline {
    pub raw: vk::Pipeline,
    pub layout: vk::PipelineLayout,
    pub set_layout: vk::DescriptorSetLayout,
    pub bind_point: vk::PipelineBindPoint,
    pub push_stages: vk::ShaderStageFlags,
    /// The bindings of its set layout: [`Context::bind`] pushes only the writes to these (a binding an optimised
    /// shader does not read is not in its layout).
    pub bindings: Vec<u32>,
}

impl Pipeline {
    /// # Safety
    /// No pending work may use the pipeline.
    pub unsafe fn destroy(self, ctx: &Context) {
        ctx.device().destroy_pipeline(self.raw, None);
        ctx.device().destroy_pipeline_layout(self.layout, None);
        ctx.device().destroy_descriptor_set_layout(self.set_layout, None);
    }
}

/// Everything created before the pipeline itself, each guarded: destroyed again if a later step fails; the
/// modules also once the pipeline exists (it no longer needs them).
struct Parts<'a> {
    layout: Guard<'a, vk::PipelineLayout>,
    set_layout: Guard<'a, vk::DescriptorSetLayout>,
    modules: Guard<'a, Vec<vk::ShaderModule>>,
    bindings: Vec<u32>,
}

impl Context {
    fn create_shader_module(&self, spirv: &[u8], name: &str) -> Result<vk::ShaderModule> {
        let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))
            .map_err(|cause| Error::Spirv { name: name.into(), cause })?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: `words` is SPIR-V produced by shaderc at build time.
        let module = unsafe { self.device().create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
        self.set_name(module, name);
        Ok(module)
    }

    /// The shader modules (each with its stage, in stage order) and the layouts of a pipeline: set 0 holds every
    /// binding its shaders declare, visible to the stages that declare it.
    fn prepare(
        &self,
        name: &str,
        shaders: &[(&Shader, vk::ShaderStageFlags)],
        push_size: u32,
        stages: vk::ShaderStageFlags,
    ) -> Result<Parts<'_>> {
        let mut modules = Guard::new(self, Vec::with_capacity(shaders.len()));
        let mut raw_bindings: Vec<vk::DescriptorSetLayoutBinding<'_>> = Vec::new();
        for &(shader, stage) in shaders {
            modules.push(self.create_shader_module(shader.spirv, &format!("{name} ({})", shader.name))?);
            for b in shader.bindings {
                match raw_bindings.iter_mut().find(|r| r.binding == b.binding) {
                    Some(r) if r.descriptor_type == b.kind => r.stage_flags |= stage,
                    Some(r) => {
                        return Err(Error::Invalid(format!(
                            "pipeline {name}: binding {} is a {:?} in one stage and a {:?} in another",
                            b.binding, r.descriptor_type, b.kind
                        )))
                    }
                    None => raw_bindings.push(
                        vk::DescriptorSetLayoutBinding::default()
                            .binding(b.binding)
                            .descriptor_type(b.kind)
                            .descriptor_count(1)
                            .stage_flags(stage),
                    ),
                }
            }
        }
        let bindings = raw_bindings.iter().map(|b| b.binding).collect();
        let set_info = vk::DescriptorSetLayoutCreateInfo::default()
            .flags(vk::DescriptorSetLayoutCreateFlags::PUSH_DESCRIPTOR_KHR)
            .bindings(&raw_bindings);
        // SAFETY: plain creates on a live device.
        let set_layout =
            unsafe { self.device().create_descriptor_set_layout(&set_info, None) }.vk("vkCreateDescriptorSetLayout")?;
        let set_layout = Guard::new(self, set_layout);
        self.set_name(*set_layout, name);
        let ranges = [vk::PushConstantRange::default().stage_flags(stages).size(push_size)];
        let set_layouts = [*set_layout];
        let mut layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        if push_size > 0 {
            layout_info = layout_info.push_constant_ranges(&ranges);
        }
        // SAFETY: as above.
        let layout =
            unsafe { self.device().create_pipeline_layout(&layout_info, None) }.vk("vkCreatePipelineLayout")?;
        let layout = Guard::new(self, layout);
        self.set_name(*layout, name);
        Ok(Parts { layout, set_layout, modules, bindings })
    }

    fn finish_pipeline(
        &self,
        name: &str,
        created: std::result::Result<Vec<vk::Pipeline>, (Vec<vk::Pipeline>, vk::Result)>,
        parts: Parts<'_>,
        bind_point: vk::PipelineBindPoint,
        push_stages: vk::ShaderStageFlags,
    ) -> Result<Pipeline> {
        // On failure every part is destroyed; on success the modules are (the pipeline no longer needs them).
        let raw = created.map_err(|(_, result)| Error::Vulkan { call: "vkCreate*Pipelines", result })?[0];
        self.set_name(raw, name);
        let (layout, set_layout) = (parts.layout.keep(), parts.set_layout.keep());
        Ok(Pipeline { raw, layout, set_layout, bind_point, push_stages, bindings: parts.bindings })
    }

    pub fn create_graphics_pipeline(&self, desc: &GraphicsPipelineDesc<'_>) -> Result<Pipeline> {
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let mut shaders = vec![(desc.vertex, vk::ShaderStageFlags::VERTEX)];
        shaders.extend(desc.fragment.map(|f| (f, vk::ShaderStageFlags::FRAGMENT)));
        let parts = self.prepare(desc.name, &shaders, desc.push_constant_size, stages)?;
        let spec = desc.specialization.info();
        let shader_stages: Vec<_> = [vk::ShaderStageFlags::VERTEX, vk::ShaderStageFlags::FRAGMENT]
            .into_iter()
            .zip(parts.modules.iter())
            .map(|(stage, &module)| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(stage)
                    .module(module)
                    .name(ENTRY)
                    .specialization_info(&spec)
            })
            .collect();
        let vb = [vk::VertexInputBindingDescription::default().binding(0).stride(desc.vertex_stride)];
        let attrs: Vec<_> = desc.vertex_attributes.iter().map(attribute).collect();
        let mut vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        if desc.vertex_stride > 0 {
            vertex_input = vertex_input.vertex_binding_descriptions(&vb).vertex_attribute_descriptions(&attrs);
        }
        let assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        let raster = raster_state(desc.cull_back_faces);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(desc.samples);
        let (depth_format, test) = desc.depth.unzip();
        let depth = depth_state(test);
        // A depth-only target (`color_format` UNDEFINED, the shadow map) has no colour attachment at all.
        let colorless = desc.color_format == vk::Format::UNDEFINED;
        let blend_attachment = [blend_attachment(desc.blend, desc.fragment.is_some())];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(if colorless {
            &[]
        } else {
            &blend_attachment
        });
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let color_formats = [desc.color_format];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(if colorless { &[] } else { &color_formats })
            .depth_attachment_format(depth_format.unwrap_or(vk::Format::UNDEFINED));
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&shader_stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(*parts.layout)
            .push_next(&mut rendering);
        // SAFETY: every pointer in `info` outlives the call.
        let created = unsafe { self.device().create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
        self.finish_pipeline(desc.name, created, parts, vk::PipelineBindPoint::GRAPHICS, stages)
    }

    pub fn create_compute_pipeline(&self, desc: &ComputePipelineDesc<'_>) -> Result<Pipeline> {
        let stages = vk::ShaderStageFlags::COMPUTE;
        let parts = self.prepare(desc.name, &[(desc.shader, stages)], desc.push_constant_size, stages)?;
        let spec = desc.specialization.info();
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(stages)
            .module(parts.modules[0])
            .name(ENTRY)
            .specialization_info(&spec);
        let info = vk::ComputePipelineCreateInfo::default().stage(stage).layout(*parts.layout);
        // SAFETY: every pointer in `info` outlives the call.
        let created = unsafe { self.device().create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
        self.finish_pipeline(desc.name, created, parts, vk::PipelineBindPoint::COMPUTE, stages)
    }

    /// Binds `pipeline`, pushes its descriptors (the writes to bindings its layout has) and its push constants.
    pub fn bind(&self, cmd: vk::CommandBuffer, pipeline: &Pipeline, writes: &[DescriptorWrite<'_>], push: &[u8]) {
        let device = self.device();
        let writes: Vec<&DescriptorWrite<'_>> =
            writes.iter().filter(|w| pipeline.bindings.contains(&w.binding())).collect();
        let mut buffer_infos = Vec::with_capacity(writes.len());
        let mut image_infos = Vec::with_capacity(writes.len());
        for w in &writes {
            match w {
                DescriptorWrite::StorageBuffer(_, b) | DescriptorWrite::UniformBuffer(_, b) => {
                    buffer_infos.push([vk::DescriptorBufferInfo::default().buffer(b.raw).range(vk::WHOLE_SIZE)]);
                }
                DescriptorWrite::SampledImage(_, i, s) => image_infos.push([vk::DescriptorImageInfo::default()
                    .image_view(i.view)
                    .sampler(s.raw)
                    .image_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)]),
                DescriptorWrite::StorageImage(_, i) => image_infos.push([vk::DescriptorImageInfo::default()
                    .image_view(i.view)
                    .image_layout(vk::ImageLayout::GENERAL)]),
                DescriptorWrite::StorageView(_, view) => image_infos.push([vk::DescriptorImageInfo::default()
                    .image_view(*view)
                    .image_layout(vk::ImageLayout::GENERAL)]),
            }
        }
        let (mut bi, mut ii) = (buffer_infos.iter(), image_infos.iter());
        let raw_writes: Vec<_> = writes
            .iter()
            .map(|w| {
                let base = vk::WriteDescriptorSet::default().dst_binding(w.binding());
                match w {
                    DescriptorWrite::StorageBuffer(..) => base
                        .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                        .buffer_info(bi.next().expect("one info per buffer write")),
                    DescriptorWrite::UniformBuffer(..) => base
                        .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                        .buffer_info(bi.next().expect("one info per buffer write")),
                    DescriptorWrite::SampledImage(..) => base
                        .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                        .image_info(ii.next().expect("one info per image write")),
                    DescriptorWrite::StorageImage(..) | DescriptorWrite::StorageView(..) => base
                        .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
                        .image_info(ii.next().expect("one info per image write")),
                }
            })
            .collect();
        // SAFETY: cmd is recording; the descriptors match the pipeline's push-descriptor set layout.
        unsafe {
            device.cmd_bind_pipeline(cmd, pipeline.bind_point, pipeline.raw);
            if !raw_writes.is_empty() {
                self.device.push_descriptor.cmd_push_descriptor_set(
                    cmd,
                    pipeline.bind_point,
                    pipeline.layout,
                    0,
                    &raw_writes,
                );
            }
            if !push.is_empty() {
                device.cmd_push_constants(cmd, pipeline.layout, pipeline.push_stages, 0, push);
            }
        }
    }
}

/// A vertex attribute of binding 0.
fn attribute(a: &VertexAttribute) -> vk::VertexInputAttributeDescription {
    vk::VertexInputAttributeDescription::default().location(a.location).binding(0).format(a.format).offset(a.offset)
}

/// The colour attachment's blend state for `blend`; every channel written where the pipeline has a fragment shader
/// (`writes`), none where it draws depth only.
fn blend_attachment(blend: Blend, writes: bool) -> vk::PipelineColorBlendAttachmentState {
    let mask = if writes { vk::ColorComponentFlags::RGBA } else { vk::ColorComponentFlags::empty() };
    let attachment = vk::PipelineColorBlendAttachmentState::default().color_write_mask(mask);
    let (src, dst) = match blend {
        Blend::Replace => return attachment,
        Blend::Add => (vk::BlendFactor::ONE, vk::BlendFactor::ONE),
        Blend::Under => (vk::BlendFactor::ONE_MINUS_DST_ALPHA, vk::BlendFactor::ONE),
    };
    attachment
        .blend_enable(true)
        .src_color_blend_factor(src)
        .dst_color_blend_factor(dst)
        .color_blend_op(vk::BlendOp::ADD)
        .src_alpha_blend_factor(src)
        .dst_alpha_blend_factor(dst)
        .alpha_blend_op(vk::BlendOp::ADD)
}

/// Fills triangles; back faces culled where asked (counter-clockwise is front).
fn raster_state(cull_back_faces: bool) -> vk::PipelineRasterizationStateCreateInfo<'static> {
    vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(if cull_back_faces { vk::CullModeFlags::BACK } else { vk::CullModeFlags::NONE })
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0)
}

/// No depth test (None), a test that writes (GREATER: reversed depth; LESS: the shadow map's), or one that only
/// passes the pre-pass's depth (EQUAL).
fn depth_state(test: Option<DepthTest>) -> vk::PipelineDepthStencilStateCreateInfo<'static> {
    let compare = match test {
        Some(DepthTest::Equal) => vk::CompareOp::EQUAL,
        Some(DepthTest::Write) => vk::CompareOp::GREATER,
        _ => vk::CompareOp::LESS,
    };
    vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(test.is_some_and(|t| t != DepthTest::Off))
        .depth_write_enable(matches!(test, Some(DepthTest::Write | DepthTest::WriteLess)))
        .depth_compare_op(compare)
}
