//! Pipelines specialized for a view: what a view needs compiled in (its shadows, its lamps) and the pipelines built
//! for each such need a renderer has met, so that a view that changes its needs (the sun going down) switches to
//! pipelines built once.

use crate::error::Result;
use crate::gpu::vk::{Context, Destroy};

/// What a view's pipelines are specialized for (`SPEC_SHADOWS`, `SPEC_LAMPS`, `SPEC_SUN`): whether it casts shadows,
/// how many lamps light it and whether the sun does. A frame without lamps runs shaders without their code (on
/// lavapipe a loop that ran no lamp still cost the default scene's frame 30 %); with lamps, the shaders write each
/// lamp out at a constant index (on lavapipe a loop over them, its count read from the uniforms, cost a lamp-lit
/// frame 1.5×); without the sun, its code is left out (it cost a lamp-lit frame 1.4×).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ViewSpec {
    pub shadows: bool,
    /// How many lamps (at most `MAX_LAMPS`).
    pub lamps: u32,
    pub sun: bool,
}

/// Pipelines built for the [`ViewSpec`] of the view a renderer last drew, and those for the other specs views have
/// needed since (a view that loses its shadow, the sun going down, draws with other pipelines).
pub(crate) struct ViewVariants<T> {
    current: T,
    spec: ViewSpec,
    others: Vec<(ViewSpec, T)>,
}

impl<T: Destroy> ViewVariants<T> {
    pub fn new(spec: ViewSpec, build: impl FnOnce(ViewSpec) -> Result<T>) -> Result<Self> {
        Ok(Self { current: build(spec)?, spec, others: Vec::new() })
    }

    /// Makes the pipelines for `spec` current, building them the first time.
    pub fn select(&mut self, spec: ViewSpec, build: impl FnOnce(ViewSpec) -> Result<T>) -> Result<()> {
        if spec == self.spec {
            return Ok(());
        }
        let next = match self.others.iter().position(|(s, _)| *s == spec) {
            Some(i) => self.others.swap_remove(i).1,
            None => build(spec)?,
        };
        let previous = std::mem::replace(&mut self.current, next);
        self.others.push((self.spec, previous));
        self.spec = spec;
        Ok(())
    }

    /// The pipelines of the view last selected.
    pub fn current(&self) -> &T {
        &self.current
    }

    /// # Safety
    /// No pending work may use them.
    pub unsafe fn destroy(self, ctx: &Context) {
        self.current.destroy(ctx);
        for (_, t) in self.others {
            t.destroy(ctx);
        }
    }
}
