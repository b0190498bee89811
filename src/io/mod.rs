//! What every layer shares with the file system and the terminal: bounded reads of the user's files (`input`),
//! checked, atomic writes of images and files ([`output`]), the on-disk cache of tables and references (`cache`),
//! progress bars on stderr (`progress`), the statistics the reports print ([`stats`]) and the command line's
//! lines on stdout and stderr, which end the run with an error on a full or closed stream ([`stream`]).
//!
//! The library prints nothing itself: what a user should read (a table it could not cache, a cached entry it
//! computes again, a material's caveat, a validation message) goes to the `log` crate, warnings as
//! `log::warn!` and notes as `log::info!`, for the application to show (the command line prints them as
//! `warning: …` and `note: …` lines; the targets below as they are).

pub(crate) mod cache;
pub(crate) mod input;
pub mod output;
pub(crate) mod progress;
pub mod stats;
pub mod stream;

/// The log target of the Vulkan validation layer's messages (each a whole line of its own).
pub const LOG_VALIDATION: &str = "diffract::validation";
/// The log target of lines shown as they are: a long job's report when no progress bar is drawn.
pub const LOG_PLAIN: &str = "diffract::plain";
