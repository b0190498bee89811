//! Progress on stderr for the long jobs — the exact reference image, baking a colour table, a map drawn in bands,
//! a frame sequence, a profile sweep — in one style, drawn by `indicatif`: what is running, a bar, the count, the
//! time taken and the time left. Where stderr is not a terminal no bar is drawn: logs and pipes get the lines that
//! are kept ([`Progress::line`]) and, once a job has run PLAIN_AFTER, a plain line of its count and times every
//! PLAIN_EVERY.

use std::borrow::Cow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// The one style: `what [#####·····] 3/8 · 12s, ~20 s left · detail`.
const TEMPLATE: &str = "{prefix} [{bar:30}] {pos}/{len} · {elapsed}, {left} · {wide_msg}";

/// The seconds a job has left at the rate of its steps so far (`elapsed` seconds for `done` of `total`); None
/// before its first step. (indicatif's own estimate weighs the latest steps: on a table whose first rows are the
/// slow ones it said 38 minutes for a 4-minute wait.)
fn time_left(elapsed: f64, done: u64, total: u64) -> Option<f64> {
    (done > 0).then(|| elapsed * total.saturating_sub(done) as f64 / done as f64)
}

/// `~N s left`, `~N min left`, or `time left unknown`.
fn left_text(left: Option<f64>) -> String {
    match left {
        Some(s) if s < 120.0 => format!("~{s:.0} s left"),
        Some(s) => format!("~{:.0} min left", s / 60.0),
        None => "time left unknown".to_string(),
    }
}

/// Every bar of the process, stacked (a job inside another — a table baked inside a profile sweep — gets its
/// own line under its parent's).
fn bars() -> &'static MultiProgress {
    static BARS: OnceLock<MultiProgress> = OnceLock::new();
    BARS.get_or_init(|| MultiProgress::with_draw_target(ProgressDrawTarget::stderr()))
}

/// A bar of `total` steps in the one style, named `what`.
fn styled(what: impl Into<Cow<'static, str>>, total: usize) -> ProgressBar {
    let style = ProgressStyle::with_template(TEMPLATE)
        .expect("a valid template")
        .with_key("left", |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
            let left = time_left(state.elapsed().as_secs_f64(), state.pos(), state.len().unwrap_or(0));
            let _ = w.write_str(&left_text(left));
        })
        .progress_chars("#>·");
    ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::hidden()).with_style(style).with_prefix(what)
}

/// Off a terminal, how long a job runs before its first plain line, and how often the next ones come.
const PLAIN_AFTER: Duration = Duration::from_secs(5);
const PLAIN_EVERY: Duration = Duration::from_secs(5);

/// Whether a job that has run `elapsed` and last printed a plain line at `last` (None: never) prints one `now`.
fn plain_line_due(elapsed: Duration, last: Option<Instant>, now: Instant) -> bool {
    elapsed >= PLAIN_AFTER && last.is_none_or(|last| now.duration_since(last) >= PLAIN_EVERY)
}

/// A job's progress line on stderr.
pub struct Progress {
    bar: ProgressBar,
    /// The bar is drawn from its first update on (a job that ends without one — a table found in the cache —
    /// shows nothing).
    started: AtomicBool,
    /// Off a terminal, for a job not hidden: when it last printed a plain line (None: not yet). Its start is the
    /// bar's.
    plain: Option<Mutex<Option<Instant>>>,
}

impl Progress {
    /// A job of `total` steps named `what` (e.g. "exact reference 256×256"), drawn on stderr if it is a terminal,
    /// else told in plain lines (at a step, once PLAIN_AFTER has passed, at most one each PLAIN_EVERY).
    pub fn new(what: impl Into<Cow<'static, str>>, total: usize) -> Self {
        let bar = bars().add(styled(what, total));
        let plain = bar.is_hidden().then(|| Mutex::new(None));
        Self { bar, started: AtomicBool::new(false), plain }
    }

    /// A job that shows nothing (too short to be worth a line), with the same interface.
    pub fn hidden() -> Self {
        Self { bar: styled("", 0), started: AtomicBool::new(false), plain: None }
    }

    /// [`Self::new`] if `show`, else [`Self::hidden`].
    pub fn new_if(show: bool, what: impl Into<Cow<'static, str>>, total: usize) -> Self {
        if show {
            Self::new(what, total)
        } else {
            Self::hidden()
        }
    }

    fn start(&self) {
        if !self.started.swap(true, Ordering::Relaxed) && !self.bar.is_hidden() {
            // Redrawn at least once a second, so the elapsed time moves while a long step runs.
            self.bar.enable_steady_tick(Duration::from_secs(1));
        }
    }

    /// One more step done (safe from any thread).
    pub fn step(&self) {
        self.start();
        self.bar.inc(1);
        self.plain_line();
    }

    /// `done` of `total` steps (a job that learns its size as it goes).
    pub fn set(&self, done: usize, total: usize) {
        self.start();
        self.bar.set_length(total as u64);
        self.bar.set_position(done as u64);
        self.plain_line();
    }

    /// Off a terminal, the job's count and times as a plain line, when one is due (`plain_line_due`).
    fn plain_line(&self) {
        let Some(plain) = &self.plain else { return };
        let (now, elapsed) = (Instant::now(), self.bar.elapsed());
        let Ok(mut last) = plain.lock() else { return };
        if !plain_line_due(elapsed, *last, now) {
            return;
        }
        *last = Some(now);
        let (done, total) = (self.bar.position(), self.bar.length().unwrap_or(0));
        let elapsed = elapsed.as_secs_f64();
        let left = left_text(time_left(elapsed, done, total));
        let detail = self.bar.message();
        let detail = if detail.is_empty() { String::new() } else { format!(" · {detail}") };
        log::info!(target: crate::io::LOG_PLAIN, "{}: {done}/{total} · {elapsed:.0} s, {left}{detail}", self.bar.prefix());
    }

    /// What the current step is doing (shown after the bar).
    pub fn detail(&self, text: impl Into<Cow<'static, str>>) {
        self.bar.set_message(text);
    }

    /// A line to keep, printed above the bar (or logged, `io::LOG_PLAIN`, when no bar is drawn).
    pub fn line(&self, text: &str) {
        if self.bar.is_hidden() || bars().println(text).is_err() {
            log::info!(target: crate::io::LOG_PLAIN, "{text}");
        }
    }

    /// Whether the bar is drawn (stderr is a terminal and the job was not hidden).
    pub fn is_drawn(&self) -> bool {
        !self.bar.is_hidden()
    }

    /// The job is over: the bar is removed.
    pub fn finish(self) {
        self.bar.finish_and_clear();
    }
}

impl Drop for Progress {
    /// A job given up on (an error returned early) leaves no bar behind.
    fn drop(&mut self) {
        if !self.bar.is_finished() {
            self.bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plain_line_comes_after_five_seconds_and_then_every_five() {
        let t0 = Instant::now();
        let (run, at) = (Duration::from_secs_f64, |s: f64| t0 + Duration::from_secs_f64(s));
        assert!(!plain_line_due(run(4.9), None, at(4.9)), "none in the first five seconds");
        assert!(plain_line_due(run(5.0), None, at(5.0)), "the first at five seconds");
        assert!(!plain_line_due(run(9.9), Some(at(5.0)), at(9.9)), "none sooner than five seconds after the last");
        assert!(plain_line_due(run(10.0), Some(at(5.0)), at(10.0)), "the next five seconds after the last");
    }

    #[test]
    fn the_time_left_follows_the_rate_so_far() {
        assert_eq!(time_left(10.0, 0, 8), None);
        assert_eq!(time_left(10.0, 2, 8), Some(30.0));
        assert_eq!(time_left(10.0, 8, 8), Some(0.0));
        assert_eq!(left_text(Some(30.0)), "~30 s left");
        assert_eq!(left_text(Some(600.0)), "~10 min left");
        assert_eq!(left_text(None), "time left unknown");
    }
}
