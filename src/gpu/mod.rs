//! The GPU: the Vulkan backend ([`vk`], the only code that creates or destroys Vulkan objects), the shaders'
//! SPIR-V compiled by `build.rs`, and [`interface`], the numbers and layouts the shaders and the Rust side share.

/// The numbers and layouts the shaders and the Rust side share: the crate `diffract-gpu-interface`
/// (`crates/gpu-interface`), which `build.rs` writes the shaders' GLSL from.
pub use diffract_gpu_interface as interface;
pub(crate) mod shaders;
pub mod vk;
