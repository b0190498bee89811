//! GPU timings from timestamp queries (after h3r2tic/gpu-profiler): a ring of `frames` slots, each a run of
//! timestamps written back to back through a frame — one where it starts, then one where each pass ends (a *lap*),
//! so that the passes' times sum to the frame's. A slot is read once its frame's work has completed, which with
//! `frames` ≥ frames in flight never stalls. A lap waits for all the work recorded before it (`ALL_COMMANDS`): on a
//! GPU that overlaps passes, it is the time the pass added to the frame.
//!
//! On a CPU device llvmpipe bins a timestamp into the *next* scene's tiles and reads the clock when they are
//! rasterised, so each mark is followed by a second, *settling* timestamp, never read, whose flush rasterises the
//! (empty) scene holding the mark right away (docs/performance.md, "Per-pass GPU times", has the figures).

use std::cell::{Cell, RefCell};

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::vk::Context;

/// The most passes a frame made by [`Context::one_shot_laps`] may time.
pub const MAX_LAPS: u32 = 16;

/// One pass of a frame and its GPU time.
#[derive(Clone, Debug, PartialEq)]
pub struct ScopeTiming {
    pub name: String,
    pub ms: f64,
}

/// A frame's GPU time, pass by pass, in the order they ran.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameTimes {
    pub passes: Vec<ScopeTiming>,
}

impl FrameTimes {
    /// The whole frame: from its start to its last lap.
    pub fn total_ms(&self) -> f64 {
        self.passes.iter().map(|p| p.ms).sum()
    }

    /// The time of the passes named `name` (a pass recorded twice counts twice), or None where none ran.
    pub fn pass_ms(&self, name: &str) -> Option<f64> {
        let mut of = self.passes.iter().filter(|p| p.name == name).peekable();
        of.peek()?;
        Some(of.map(|p| p.ms).sum())
    }

    /// "depth pre-pass 1.2 + shading 3.4 + resolve 0.5 ms": the passes in one line.
    pub fn describe(&self) -> String {
        let parts: Vec<String> = self.passes.iter().map(|p| format!("{} {:.2}", p.name, p.ms)).collect();
        format!("{} ms", parts.join(" + "))
    }
}

/// Timestamps in slots of `marks_per_frame`: a frame's start and each lap after it.
pub struct TimestampRing {
    pub raw: vk::QueryPool,
    frames: u32,
    marks_per_frame: u32,
    /// Queries per mark: 1, or 2 where each mark is followed by a settling timestamp (a CPU device).
    queries_per_mark: u32,
    period_ns: f64,
    valid_mask: u64,
    /// The laps recorded into each slot since its last reset; None once a frame recorded more than fit.
    names: RefCell<Vec<Option<Vec<String>>>>,
    current: Cell<u32>,
}

/// Where a recorder marks the end of each of its passes: a no-op where the queue has no timestamps (or the caller
/// does not time the frame).
#[derive(Clone, Copy, Default)]
pub struct Laps<'a>(Option<(&'a Context, &'a TimestampRing)>);

impl<'a> Laps<'a> {
    /// Laps that record nothing.
    pub const NONE: Laps<'static> = Laps(None);

    /// Ends the pass `name`: the work recorded into `cmd` since the frame's start or its previous lap.
    pub fn lap(self, cmd: vk::CommandBuffer, name: &str) {
        if let Some((ctx, ring)) = self.0 {
            ring.lap(ctx, cmd, name);
        }
    }
}

impl TimestampRing {
    fn query(&self, slot: u32, mark: u32) -> u32 {
        (slot * self.marks_per_frame + mark) * self.queries_per_mark
    }

    /// Writes mark `mark` of slot `slot` (and its settling timestamp on a CPU device).
    fn write_mark(&self, ctx: &Context, cmd: vk::CommandBuffer, slot: u32, mark: u32, stage: vk::PipelineStageFlags2) {
        let q = self.query(slot, mark);
        // SAFETY: cmd is recording; the queries were reset in begin_frame and are written once per frame.
        unsafe {
            ctx.device().cmd_write_timestamp2(cmd, stage, self.raw, q);
            if self.queries_per_mark == 2 {
                ctx.device().cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::ALL_COMMANDS, self.raw, q + 1);
            }
        }
    }

    /// Starts frame `frame` (any counter; its slot is `frame % frames`): resets the slot's queries and writes
    /// the frame's first timestamp. Returns where its passes mark their ends.
    pub fn begin_frame<'a>(&'a self, ctx: &'a Context, cmd: vk::CommandBuffer, frame: u64) -> Laps<'a> {
        let slot = (frame % u64::from(self.frames)) as u32;
        self.current.set(slot);
        self.names.borrow_mut()[slot as usize] = Some(Vec::new());
        let count = self.marks_per_frame * self.queries_per_mark;
        // SAFETY: cmd is recording, outside any rendering scope; the range lies inside the pool.
        unsafe { ctx.device().cmd_reset_query_pool(cmd, self.raw, self.query(slot, 0), count) };
        self.write_mark(ctx, cmd, slot, 0, vk::PipelineStageFlags2::TOP_OF_PIPE);
        Laps(Some((ctx, self)))
    }

    /// Where the passes of the frame begun last ([`Self::begin_frame`]) mark their ends.
    pub fn laps<'a>(&'a self, ctx: &'a Context) -> Laps<'a> {
        Laps(Some((ctx, self)))
    }

    fn lap(&self, ctx: &Context, cmd: vk::CommandBuffer, name: &str) {
        let slot = self.current.get();
        let mut names = self.names.borrow_mut();
        let Some(laps) = names[slot as usize].as_mut() else { return };
        let index = laps.len() as u32 + 1;
        if index >= self.marks_per_frame {
            names[slot as usize] = None;
            return;
        }
        laps.push(name.to_string());
        drop(names);
        self.write_mark(ctx, cmd, slot, index, vk::PipelineStageFlags2::ALL_COMMANDS);
    }

    /// The pass times of frame `frame`, whose work must have completed.
    pub fn read(&self, ctx: &Context, frame: u64) -> Result<FrameTimes> {
        let slot = (frame % u64::from(self.frames)) as u32;
        let names = self.names.borrow();
        let Some(names) = &names[slot as usize] else {
            return Err(Error::Invalid(format!(
                "a frame recorded more than {} timed passes (a bug)",
                self.marks_per_frame - 1
            )));
        };
        if names.is_empty() {
            return Ok(FrameTimes::default());
        }
        let mut read = vec![0u64; (names.len() + 1) * self.queries_per_mark as usize];
        // SAFETY: the queries were written by completed work; WAIT makes an unfinished one an error-free stall.
        unsafe {
            ctx.device().get_query_pool_results(
                self.raw,
                self.query(slot, 0),
                &mut read,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        let stamps: Vec<u64> = read.into_iter().step_by(self.queries_per_mark as usize).collect();
        let passes = names
            .iter()
            .zip(stamps.windows(2))
            .map(|(name, pair)| {
                let ticks = (pair[1] & self.valid_mask).wrapping_sub(pair[0] & self.valid_mask) & self.valid_mask;
                ScopeTiming { name: name.clone(), ms: ticks as f64 * self.period_ns * 1e-6 }
            })
            .collect();
        Ok(FrameTimes { passes })
    }

    /// # Safety
    /// No pending work may write the pool.
    pub unsafe fn destroy(self, ctx: &Context) {
        ctx.device().destroy_query_pool(self.raw, None);
    }
}

/// What one profiled submission measured: GPU time (timestamps) and fragment-shader invocations (pipeline
/// statistics), each where the device has them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PassProfile {
    /// The submission's passes, each ended by a `Laps::lap` of the recorder.
    pub times: Option<FrameTimes>,
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
    /// brackets with `Statistics`, where the device has pipeline statistics.
    pub fn one_shot_profiled(
        &self,
        name: &str,
        record: impl FnOnce(vk::CommandBuffer, &Statistics<'_>, Laps<'_>),
    ) -> Result<PassProfile> {
        let unsupported = Statistics { ctx: self, pool: vk::QueryPool::null(), state: Default::default() };
        if !self.has_pipeline_statistics() {
            let times = self.one_shot_laps(name, |cmd, laps| record(cmd, &unsupported, laps))?;
            return Ok(PassProfile { times, fragment_invocations: None });
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .pipeline_statistics(vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS)
            .query_count(1);
        // SAFETY: a plain create on a live device that enabled pipelineStatisticsQuery.
        let pool = unsafe { self.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        // Destroyed at the scope's end: one_shot waits for the work that writes the query.
        let _destroyed_at_the_end = crate::gpu::vk::Guard::new(self, pool);
        self.set_name(pool, name);
        let statistics = Statistics { ctx: self, pool, state: Default::default() };
        let timed = self.one_shot_laps(name, |cmd, laps| {
            // SAFETY: cmd is recording, outside any rendering scope.
            unsafe { self.device().cmd_reset_query_pool(cmd, pool, 0, 1) };
            record(cmd, &statistics, laps);
        });
        let closed = statistics.state.get() == 2;
        let result = timed.and_then(|times| {
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
            Ok(PassProfile { times, fragment_invocations: Some(count[0]) })
        });
        result
    }

    /// [`Context::one_shot`] timed as one pass named `name`; returns its GPU time in ms where the queue has
    /// timestamps.
    pub fn one_shot_timed(&self, name: &str, record: impl FnOnce(vk::CommandBuffer)) -> Result<Option<f64>> {
        let times = self.one_shot_laps(name, |cmd, laps| {
            record(cmd);
            laps.lap(cmd, name);
        })?;
        Ok(times.map(|t| t.total_ms()))
    }

    /// [`Context::one_shot`] whose recorder marks the end of each of its passes with `Laps::lap`; returns their
    /// GPU times where the queue has timestamps.
    pub fn one_shot_laps(
        &self,
        name: &str,
        record: impl FnOnce(vk::CommandBuffer, Laps<'_>),
    ) -> Result<Option<FrameTimes>> {
        let Some(ring) = self.create_timestamp_ring(1, MAX_LAPS, name)? else {
            self.one_shot(name, |cmd| record(cmd, Laps::NONE))?;
            return Ok(None);
        };
        // Destroyed at the scope's end: one_shot waits for the work that writes the queries.
        let ring = crate::gpu::vk::Guard::new(self, ring);
        self.one_shot(name, |cmd| record(cmd, ring.begin_frame(self, cmd, 0)))?;
        ring.read(self, 0).map(Some)
    }

    /// A ring of `frames` slots with room for `laps` timed passes each; `None` where the queue has no
    /// timestamps.
    pub fn create_timestamp_ring(&self, frames: u32, laps: u32, name: &str) -> Result<Option<TimestampRing>> {
        let bits = self.device.timestamp_valid_bits;
        if bits == 0 || self.info.timestamp_period_ns <= 0.0 {
            return Ok(None);
        }
        let queries_per_mark = if self.info.kind == vk::PhysicalDeviceType::CPU { 2 } else { 1 };
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(frames * (laps + 1) * queries_per_mark);
        // SAFETY: a plain create on a live device.
        let raw = unsafe { self.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        self.set_name(raw, name);
        let valid_mask = if bits >= 64 { u64::MAX } else { (1u64 << bits) - 1 };
        Ok(Some(TimestampRing {
            raw,
            frames,
            marks_per_frame: laps + 1,
            queries_per_mark,
            period_ns: f64::from(self.info.timestamp_period_ns),
            valid_mask,
            names: RefCell::new(vec![Some(Vec::new()); frames as usize]),
            current: Cell::new(0),
        }))
    }
}
