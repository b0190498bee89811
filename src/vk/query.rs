//! A timestamp-query ring for GPU timings (after h3r2tic/gpu-profiler): `frames` slots of `scopes` pairs of
//! timestamps. A frame writes into its slot; its results are read once the frame's work has completed, which
//! with `frames` ≥ frames in flight never stalls. A scope's name is its pass name and debug label.

use ash::vk;

use super::Context;
use crate::error::{Error, Result, VkResultExt};

/// One finished scope.
#[derive(Clone, Debug, PartialEq)]
pub struct ScopeTiming {
    pub name: String,
    pub ms: f64,
}

pub struct TimestampRing {
    pub raw: vk::QueryPool,
    frames: u32,
    scopes_per_frame: u32,
    period_ns: f64,
    valid_mask: u64,
    /// Scope names recorded into each slot since its last reset.
    names: Vec<Vec<String>>,
    current: u32,
}

impl TimestampRing {
    fn first_query(&self, slot: u32) -> u32 {
        slot * self.scopes_per_frame * 2
    }

    /// Starts frame `frame` (any counter; its slot is `frame % frames`): resets the slot's queries.
    pub fn begin_frame(&mut self, ctx: &Context, cmd: vk::CommandBuffer, frame: u64) {
        self.current = (frame % u64::from(self.frames)) as u32;
        self.names[self.current as usize].clear();
        let first = self.first_query(self.current);
        // SAFETY: cmd is recording; the range lies inside the pool.
        unsafe { ctx.device().cmd_reset_query_pool(cmd, self.raw, first, self.scopes_per_frame * 2) };
    }

    /// Opens a named scope (and a debug label of the same name). Returns its index for [`Self::end_scope`].
    pub fn begin_scope(&mut self, ctx: &Context, cmd: vk::CommandBuffer, name: &str) -> Result<u32> {
        let names = &mut self.names[self.current as usize];
        let index = names.len() as u32;
        if index >= self.scopes_per_frame {
            return Err(Error::Invalid(format!("more than {} timed scopes in one frame", self.scopes_per_frame)));
        }
        names.push(name.to_string());
        ctx.begin_label(cmd, name);
        let q = self.first_query(self.current) + index * 2;
        // SAFETY: cmd is recording; the query was reset in begin_frame.
        unsafe { ctx.device().cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::TOP_OF_PIPE, self.raw, q) };
        Ok(index)
    }

    pub fn end_scope(&mut self, ctx: &Context, cmd: vk::CommandBuffer, index: u32) {
        let q = self.first_query(self.current) + index * 2 + 1;
        // SAFETY: cmd is recording; paired with begin_scope.
        unsafe { ctx.device().cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::BOTTOM_OF_PIPE, self.raw, q) };
        ctx.end_label(cmd);
    }

    /// The timings of frame `frame`, whose work must have completed.
    pub fn read(&self, ctx: &Context, frame: u64) -> Result<Vec<ScopeTiming>> {
        let slot = (frame % u64::from(self.frames)) as u32;
        let names = &self.names[slot as usize];
        if names.is_empty() {
            return Ok(Vec::new());
        }
        let mut stamps = vec![0u64; names.len() * 2];
        // SAFETY: the queries were written by completed work; WAIT makes an unfinished one an error-free stall.
        unsafe {
            ctx.device().get_query_pool_results(
                self.raw,
                self.first_query(slot),
                &mut stamps,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        Ok(names
            .iter()
            .enumerate()
            .map(|(i, name)| {
                let ticks = (stamps[2 * i + 1] & self.valid_mask).wrapping_sub(stamps[2 * i] & self.valid_mask)
                    & self.valid_mask;
                ScopeTiming { name: name.clone(), ms: ticks as f64 * self.period_ns * 1e-6 }
            })
            .collect())
    }

    /// # Safety
    /// No pending work may write the pool.
    pub unsafe fn destroy(self, ctx: &Context) {
        ctx.device().destroy_query_pool(self.raw, None);
    }
}

/// What one profiled submission measured: GPU time (timestamps) and fragment-shader invocations (pipeline
/// statistics), each where the device has them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassProfile {
    pub gpu_ms: Option<f64>,
    pub fragment_invocations: Option<u64>,
}

/// The draws of a profiled submission whose fragment-shader invocations are counted: the recorder calls
/// [`Statistics::begin`] and [`Statistics::end`] around them once (both outside rendering scopes, or both inside
/// the same one). A no-op where the device has no pipeline statistics.
pub struct Statistics<'a> {
    ctx: &'a Context,
    pool: vk::QueryPool,
    /// 0: not begun, 1: begun, 2: ended.
    state: std::cell::Cell<u8>,
}

impl Statistics<'_> {
    pub fn begin(&self, cmd: vk::CommandBuffer) {
        if self.pool != vk::QueryPool::null() && self.state.replace(1) == 0 {
            // SAFETY: cmd is recording; the query was reset before the recording started.
            unsafe { self.ctx.device().cmd_begin_query(cmd, self.pool, 0, vk::QueryControlFlags::empty()) };
        }
    }

    pub fn end(&self, cmd: vk::CommandBuffer) {
        if self.pool != vk::QueryPool::null() && self.state.get() == 1 {
            self.state.set(2);
            // SAFETY: paired with begin, in the same rendering scope (or outside any).
            unsafe { self.ctx.device().cmd_end_query(cmd, self.pool, 0) };
        }
    }
}

impl Context {
    /// [`Context::one_shot_timed`] that also counts the fragment-shader invocations of the draws the recorder
    /// brackets with [`Statistics`], where the device has pipeline statistics.
    pub fn one_shot_profiled(
        &self,
        name: &str,
        record: impl FnOnce(vk::CommandBuffer, &Statistics<'_>),
    ) -> Result<PassProfile> {
        let unsupported = Statistics { ctx: self, pool: vk::QueryPool::null(), state: Default::default() };
        if !self.has_pipeline_statistics() {
            let gpu_ms = self.one_shot_timed(name, |cmd| record(cmd, &unsupported))?;
            return Ok(PassProfile { gpu_ms, fragment_invocations: None });
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .pipeline_statistics(vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS)
            .query_count(1);
        // SAFETY: a plain create on a live device that enabled pipelineStatisticsQuery.
        let pool = unsafe { self.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        // Destroyed at the scope's end: one_shot waits for the work that writes the query.
        let _destroyed_at_the_end = super::Guard::new(self, pool);
        self.set_name(pool, name);
        let statistics = Statistics { ctx: self, pool, state: Default::default() };
        let timed = self.one_shot_timed(name, |cmd| {
            // SAFETY: cmd is recording, outside any rendering scope.
            unsafe { self.device().cmd_reset_query_pool(cmd, pool, 0, 1) };
            record(cmd, &statistics);
        });
        let closed = statistics.state.get() == 2;
        let result = timed.and_then(|gpu_ms| {
            if !closed {
                // Reading a query that never ended would wait forever.
                return Err(crate::Error::Invalid(format!("{name}: the counted draws were not bracketed (a bug)")));
            }
            let mut count = [0u64; 1];
            // SAFETY: the work that wrote the query has completed (one_shot waits).
            unsafe {
                self.device().get_query_pool_results(
                    pool,
                    0,
                    &mut count,
                    vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
                )
            }
            .vk("vkGetQueryPoolResults")?;
            Ok(PassProfile { gpu_ms, fragment_invocations: Some(count[0]) })
        });
        result
    }

    /// [`Context::one_shot`] with the recorded work inside one timed scope named `name` (its debug label too);
    /// returns its GPU time in ms where the queue has timestamps.
    pub fn one_shot_timed(&self, name: &str, record: impl FnOnce(vk::CommandBuffer)) -> Result<Option<f64>> {
        let Some(ring) = self.create_timestamp_ring(1, 1, name)? else {
            self.one_shot(name, record)?;
            return Ok(None);
        };
        // Destroyed at the scope's end: one_shot waits for the work that writes the queries.
        let mut ring = super::Guard::new(self, ring);
        let mut scope_error = None;
        let submitted = self.one_shot(name, |cmd| {
            ring.begin_frame(self, cmd, 0);
            match ring.begin_scope(self, cmd, name) {
                Ok(scope) => {
                    record(cmd);
                    ring.end_scope(self, cmd, scope);
                }
                Err(e) => scope_error = Some(e),
            }
        });
        submitted.and_then(|()| match scope_error {
            Some(e) => Err(e),
            None => ring.read(self, 0).map(|t| t.first().map(|s| s.ms)),
        })
    }

    /// A ring of `frames` slots with room for `scopes_per_frame` timed scopes each; `None` where the queue has
    /// no timestamps.
    pub fn create_timestamp_ring(
        &self,
        frames: u32,
        scopes_per_frame: u32,
        name: &str,
    ) -> Result<Option<TimestampRing>> {
        let bits = self.device.timestamp_valid_bits;
        if bits == 0 || self.info.timestamp_period_ns <= 0.0 {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(frames * scopes_per_frame * 2);
        // SAFETY: a plain create on a live device.
        let raw = unsafe { self.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        self.set_name(raw, name);
        let valid_mask = if bits >= 64 { u64::MAX } else { (1u64 << bits) - 1 };
        Ok(Some(TimestampRing {
            raw,
            frames,
            scopes_per_frame,
            period_ns: f64::from(self.info.timestamp_period_ns),
            valid_mask,
            names: vec![Vec::new(); frames as usize],
            current: 0,
        }))
    }
}
