//! The command line's lines on stdout and stderr, written so that a stream that cannot take them (a full disk,
//! `> /dev/full`) is an error of the run rather than a panic (Rust's `println!` panics): the line is lost, the
//! run goes on to finish what it writes to files, and [`failure`] makes it end with one `error:` line (where
//! stderr still works) and a non-zero status. A closed pipe still ends the process as SIGPIPE does (`cli::main`).

use std::fmt::Arguments;
use std::io::Write;
use std::sync::Mutex;

/// The first stream that could not be written, and why.
static FAILED: Mutex<Option<String>> = Mutex::new(None);

/// The line a failed write to `stream` ends the run with (also `brdf`'s, which writes its CSV itself).
pub fn failed(stream: &str, e: &std::io::Error) -> String {
    format!("could not write to {stream}: {e}")
}

/// Writes `args` then `end` to `w` and flushes it (so that its error is seen here), recording a failure.
fn put(mut w: impl Write, stream: &str, args: Arguments<'_>, end: &str) {
    if let Err(e) = w.write_fmt(args).and_then(|()| w.write_all(end.as_bytes())).and_then(|()| w.flush()) {
        let mut first = FAILED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        first.get_or_insert_with(|| failed(stream, &e));
    }
}

/// One line on stdout.
pub fn out(args: Arguments<'_>) {
    put(std::io::stdout().lock(), "standard output", args, "\n");
}

/// Text on stdout as it is (no newline added).
pub fn out_text(text: &str) {
    put(std::io::stdout().lock(), "standard output", format_args!("{text}"), "");
}

/// One line on stderr.
pub fn err(args: Arguments<'_>) {
    put(std::io::stderr().lock(), "standard error", args, "\n");
}

/// Text on stderr as it is (no newline added).
pub fn err_text(text: &str) {
    put(std::io::stderr().lock(), "standard error", format_args!("{text}"), "");
}

/// Why a stream could not be written, if one could not.
pub fn failure() -> Option<String> {
    FAILED.lock().unwrap_or_else(std::sync::PoisonError::into_inner).clone()
}
