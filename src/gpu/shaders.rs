//! The shaders on the Vulkan side: the SPIR-V of every `glsl/<name>.<stage>.glsl`, compiled by `build.rs` and
//! embedded at build time (`NAME_STAGE` holds the bytes of `glsl/name.stage.glsl`; dashes and dots become
//! underscores), and the vertex layout they read, from [`interface`](crate::gpu::interface).

// Crate-private: the self-test's shader and constants are read by the backend's tests only.
#![cfg_attr(not(test), allow(dead_code))]

use ash::vk;

use crate::gpu::interface::{GlslType, Vertex, VERTEX_INPUTS};
use crate::gpu::vk::{Shader, ShaderBinding, VertexAttribute};

include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// The vertex attributes every vertex shader reads: `VERTEX_INPUTS` of [`Vertex`] at locations 0, 1, …, with
/// its fields' offsets and formats.
pub const VERTEX_ATTRIBUTES: [VertexAttribute; VERTEX_INPUTS.len()] = vertex_attributes();

const fn vertex_attributes() -> [VertexAttribute; VERTEX_INPUTS.len()] {
    let mut out = [VertexAttribute { location: 0, format: vk::Format::UNDEFINED, offset: 0 }; VERTEX_INPUTS.len()];
    let mut location = 0;
    while location < VERTEX_INPUTS.len() {
        let mut f = 0;
        // (A name Vertex lacks ends the loop past its fields: a compile-time index error.)
        while !same(Vertex::FIELDS[f].name, VERTEX_INPUTS[location]) {
            f += 1;
        }
        let field = &Vertex::FIELDS[f];
        let format = match field.ty {
            GlslType::Float => vk::Format::R32_SFLOAT,
            GlslType::Vec2 => vk::Format::R32G32_SFLOAT,
            GlslType::Vec3 => vk::Format::R32G32B32_SFLOAT,
            GlslType::Vec4 => vk::Format::R32G32B32A32_SFLOAT,
            _ => panic!("a vertex input must be a float or a float vector"),
        };
        out[location] = VertexAttribute { location: location as u32, format, offset: field.offset as u32 };
        location += 1;
    }
    out
}

const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::interface::*;

    /// The bindings read from the SPIR-V are the ones the GLSL declares, of each kind of descriptor.
    #[test]
    fn reflection_finds_each_kind_of_binding() {
        let of = |binding, kind| ShaderBinding { binding, kind };
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        assert_eq!(SELFTEST_COMP.bindings, [of(BINDING_SELFTEST_IN, storage), of(BINDING_SELFTEST_OUT, storage)]);
        let has = |shader: &Shader, b: ShaderBinding| shader.bindings.contains(&b);
        assert!(has(&MAP_COMP, of(BINDING_PARAMS, vk::DescriptorType::UNIFORM_BUFFER)));
        assert!(has(&MAP_COMP, of(BINDING_TABLE, vk::DescriptorType::COMBINED_IMAGE_SAMPLER)));
        assert!(has(&MAP_COMP, of(BINDING_SPECTRUM, storage)));
        assert!(has(&MAP_COMP, of(BINDING_MAP_IMAGE, vk::DescriptorType::STORAGE_IMAGE)));
        // The counting variants add the counters; the plain ones do not declare them.
        assert!(has(&MAP_COUNT_FRAG, of(BINDING_FETCH_COUNTS, storage)));
        assert!(!MAP_FRAG.bindings.iter().any(|b| b.binding == BINDING_FETCH_COUNTS));
        // A vertex shader that reads the environment's moments declares them; the plain one does not.
        assert!(has(&SURFACE_SKY_VERT, of(BINDING_MOMENTS, vk::DescriptorType::COMBINED_IMAGE_SAMPLER)));
        assert_eq!(SURFACE_VERT.bindings, [of(BINDING_FRAME, vk::DescriptorType::UNIFORM_BUFFER)]);
    }

    /// The vertex attributes follow the interface's fields: locations in `VERTEX_INPUTS`' order, offsets of
    /// `Vertex`'s fields.
    #[test]
    fn vertex_attributes_follow_the_vertex_struct() {
        assert_eq!(VERTEX_ATTRIBUTES.map(|a| a.location), [0, 1, 2, 3, 4]);
        assert_eq!(VERTEX_ATTRIBUTES[4].offset as usize, std::mem::offset_of!(Vertex, uv));
        assert_eq!(VERTEX_ATTRIBUTES[3].offset as usize, std::mem::offset_of!(Vertex, pigment));
        assert_eq!(VERTEX_ATTRIBUTES[2].format, vk::Format::R32G32B32A32_SFLOAT);
    }
}
