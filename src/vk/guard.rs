//! One way to hold Vulkan objects under construction: [`Destroy`] on every object that owns GPU state (and on
//! `Option`, `Vec` and pairs of them), and a [`Guard`] that destroys what it holds when it is dropped — on an
//! early return with `?` — unless [`Guard::keep`] hands it on. Leaves keep having no `Drop` of their own: a
//! finished object is destroyed explicitly, by its owner, when the GPU is done with it.

use std::ops::{Deref, DerefMut};

use super::Context;

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

/// Implements [`Destroy`] by the type's own `unsafe fn destroy(self, &Context)`.
#[macro_export]
#[doc(hidden)]
macro_rules! impl_destroy {
    ($($t:ty),* $(,)?) => {$(
        impl $crate::vk::Destroy for $t {
            unsafe fn destroy(self, ctx: &$crate::vk::Context) {
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
