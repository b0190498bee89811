//! One way to hold Vulkan objects under construction: [`Destroy`] on every object that owns GPU state (and on
//! `Option`, `Vec` and pairs of them), and a [`Guard`] that destroys what it holds when it is dropped — on an
//! early return with `?` — unless [`Guard::keep`] hands it on. Leaves keep having no `Drop` of their own: a
//! finished object is destroyed explicitly, by its owner, when the GPU is done with it.
//!
//! The raw handles that `vk/` itself creates on the way to a leaf (an image before its memory is bound, the
//! layouts before a pipeline, a fence before a frame's sync) and memory allocations implement [`Destroy`] too, so
//! the leaves' own constructors are written with guards like everything above them. Two places clean up by
//! hand, on purpose: opening the [`Context`] itself (there is no context to guard with yet) and
//! [`Context::one_shot`] (a failed submission must be waited for before its fence and command buffer go).

use std::ops::{Deref, DerefMut};

use ash::vk;
use gpu_allocator::vulkan::Allocation;

use crate::gpu::vk::Context;

/// An object that owns GPU state and is destroyed explicitly.
pub trait Destroy {
    /// # Safety
    /// No pending GPU work may use the object.
    unsafe fn destroy(self, ctx: &Context);
}

impl<T: Destroy> Destroy for Option<T> {
    unsafe fn destroy(self, ctx: &Context) {
        if let Some(x) = self {
            x.destroy(ctx);
        }
    }
}

impl<T: Destroy> Destroy for Vec<T> {
    unsafe fn destroy(self, ctx: &Context) {
        for x in self {
            x.destroy(ctx);
        }
    }
}

impl<A: Destroy, B: Destroy> Destroy for (A, B) {
    unsafe fn destroy(self, ctx: &Context) {
        self.1.destroy(ctx);
        self.0.destroy(ctx);
    }
}

/// Raw handles, destroyed by the device call of their kind.
macro_rules! impl_destroy_raw {
    ($($t:ty => $call:ident),* $(,)?) => {$(
        impl Destroy for $t {
            unsafe fn destroy(self, ctx: &Context) {
                ctx.device().$call(self, None);
            }
        }
    )*};
}

impl_destroy_raw!(
    vk::Buffer => destroy_buffer,
    vk::Image => destroy_image,
    vk::ImageView => destroy_image_view,
    vk::ShaderModule => destroy_shader_module,
    vk::DescriptorSetLayout => destroy_descriptor_set_layout,
    vk::PipelineLayout => destroy_pipeline_layout,
    vk::Fence => destroy_fence,
    vk::Semaphore => destroy_semaphore,
    vk::CommandPool => destroy_command_pool,
    vk::QueryPool => destroy_query_pool,
);

/// Memory goes back to the allocator (a failure to free is the allocator's bookkeeping, reported by the leak
/// check at teardown).
impl Destroy for Allocation {
    unsafe fn destroy(self, ctx: &Context) {
        let _ = ctx.allocator().free(self);
    }
}

/// Implements [`Destroy`] by the type's own `unsafe fn destroy(self, &Context)`.
#[macro_export]
#[doc(hidden)]
macro_rules! impl_destroy {
    ($($t:ty),* $(,)?) => {$(
        impl $crate::gpu::vk::Destroy for $t {
            unsafe fn destroy(self, ctx: &$crate::gpu::vk::Context) {
                <$t>::destroy(self, ctx)
            }
        }
    )*};
}

/// Holds `T` while it is being built, or for a scope that uses it: dropped (an error returned early, or the
/// scope's end), it destroys `T`; `keep` hands `T` on. It dereferences to `T`.
///
/// Only for objects that no pending work uses when the guard is dropped: everything the crate submits is waited
/// for ([`Context::one_shot`]) before the next step can fail or the scope can end.
pub struct Guard<'a, T: Destroy> {
    ctx: &'a Context,
    value: Option<T>,
}

impl<'a, T: Destroy> Guard<'a, T> {
    pub fn new(ctx: &'a Context, value: T) -> Self {
        Self { ctx, value: Some(value) }
    }

    /// The object, no longer guarded.
    pub fn keep(mut self) -> T {
        self.value.take().expect("a guard holds its value until kept")
    }
}

impl<T: Destroy> Deref for Guard<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.value.as_ref().expect("a guard holds its value until kept")
    }
}

impl<T: Destroy> DerefMut for Guard<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        self.value.as_mut().expect("a guard holds its value until kept")
    }
}

impl<T: Destroy> Drop for Guard<'_, T> {
    fn drop(&mut self) {
        if let Some(value) = self.value.take() {
            // SAFETY: a guarded object is not used by pending work (see the type's documentation).
            unsafe { value.destroy(self.ctx) };
        }
    }
}

/// A finished object owned by code outside the crate's frame loops (a library user's capture, a command's): it
/// dereferences to `T`, and dropped, it waits until the device is idle and destroys `T`, so no `unsafe` is
/// needed to let it go. (The wait costs a little at each drop: the crate's own objects are destroyed explicitly.)
pub struct Owned<'a, T: Destroy> {
    guard: Guard<'a, T>,
}

impl<'a, T: Destroy> Owned<'a, T> {
    pub fn new(ctx: &'a Context, value: T) -> Self {
        Self { guard: Guard::new(ctx, value) }
    }
}

impl<T: Destroy> Deref for Owned<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.guard
    }
}

impl<T: Destroy> DerefMut for Owned<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.guard
    }
}

impl<T: Destroy> Drop for Owned<'_, T> {
    fn drop(&mut self) {
        // Nothing submitted may still use it when the guard below destroys it. A device that cannot wait is lost:
        // destroying then is what Vulkan allows.
        let _ = self.guard.ctx.wait_idle();
    }
}
