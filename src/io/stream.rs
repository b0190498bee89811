//! The command line's lines on stdout and stderr, written so that a stream that cannot take them (a full disk,
//! `> /dev/full`) is an error of the run rather than a panic (Rust's `println!` panics): the line is lost, the
//! run goes on to finish what it writes to files, and [`failure`] makes it end with one `error:` line (where
//! stderr still works) and a non-zero status. A closed pipe still ends the process as SIGPIPE does (`cli::main`).

use std::fmt::Arguments;
use std::io::Write;
use std::sync::Mutex;

/// The first stream that could not be written, and why.
static FAILED: Mutex<Option<String>> = Mutex::new(None);

fn record(stream: &str, e: &std::io::Error) {
    let mut failed = FAILED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if failed.is_none() {
        *failed = Some(format!("could not write to {stream}: {e}"));
    }
}

/// One line on stdout (flushed, so that its error is seen here).
pub fn out(args: Arguments<'_>) {
    let mut stdout = std::io::stdout().lock();
    if let Err(e) = stdout.write_fmt(args).and_then(|()| stdout.write_all(b"\n")).and_then(|()| stdout.flush()) {
        record("standard output", &e);
    }
}

/// Text on stdout as it is (no newline added).
pub fn out_text(text: &str) {
    let mut stdout = std::io::stdout().lock();
    if let Err(e) = stdout.write_all(text.as_bytes()).and_then(|()| stdout.flush()) {
        record("standard output", &e);
    }
}

/// One line on stderr.
pub fn err(args: Arguments<'_>) {
    let mut stderr = std::io::stderr().lock();
    if let Err(e) = stderr.write_fmt(args).and_then(|()| stderr.write_all(b"\n")) {
        record("standard error", &e);
    }
}

/// Text on stderr as it is (no newline added).
pub fn err_text(text: &str) {
    if let Err(e) = std::io::stderr().lock().write_all(text.as_bytes()) {
        record("standard error", &e);
    }
}

/// Why a stream could not be written, if one could not.
pub fn failure() -> Option<String> {
    FAILED.lock().unwrap_or_else(std::sync::PoisonError::into_inner).clone()
}
