//! The GPU: the Vulkan backend ([`vk`], the only code that creates or destroys Vulkan objects), the shaders'
//! SPIR-V compiled by `build.rs`, and [`interface`], the numbers and layouts the shaders and the Rust side share.

pub mod interface;
pub(crate) mod shaders;
pub mod vk;
