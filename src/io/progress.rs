//! Progress on stderr for the long jobs — the exact reference image, baking a colour table, a map drawn in bands,
//! a frame sequence, a profile sweep — in one style, drawn by `indicatif`: what is running, a bar, the count, the
//! time taken and the time left. Nothing is drawn where stderr is not a terminal (logs and pipes get only the
//! lines that are kept, through [`Progress::line`]).

use std::borrow::Cow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::Duration;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

/// The one style: `what [#####·····] 3/8 · 12s, ~20s left · detail`.
const TEMPLATE: &str = "{prefix} [{bar:30}] {pos}/{len} · {elapsed}, ~{eta} left · {wide_msg}";

/// Every bar of the process, stacked (a job inside another — a table baked inside a profile sweep — gets its
/// own line under its parent's).
fn bars() -> &'static MultiProgress {
    static BARS: OnceLock<MultiProgress> = OnceLock::new();
    BARS.get_or_init(|| MultiProgress::with_draw_target(ProgressDrawTarget::stderr()))
}

/// A bar of `total` steps in the one style, named `what`.
fn styled(what: impl Into<Cow<'static, str>>, total: usize) -> ProgressBar {
    let style = ProgressStyle::with_template(TEMPLATE).expect("a valid template").progress_chars("#>·");
    ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::hidden()).with_style(style).with_prefix(what)
}

/// A job's progress line on stderr.
pub struct Progress {
    bar: ProgressBar,
    /// The bar is drawn from its first update on (a job that ends without one — a table found in the cache —
    /// shows nothing).
    started: AtomicBool,
}

impl Progress {
    /// A job of `total` steps named `what` (e.g. "exact reference 256×256"), drawn on stderr if it is a terminal.
    pub fn new(what: impl Into<Cow<'static, str>>, total: usize) -> Self {
        Self { bar: bars().add(styled(what, total)), started: AtomicBool::new(false) }
    }

    /// A job that shows nothing (too short to be worth a line), with the same interface.
    pub fn hidden() -> Self {
        Self { bar: styled("", 0), started: AtomicBool::new(false) }
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
    }

    /// `done` of `total` steps (a job that learns its size as it goes).
    pub fn set(&self, done: usize, total: usize) {
        self.start();
        self.bar.set_length(total as u64);
        self.bar.set_position(done as u64);
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
