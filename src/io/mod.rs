//! What every layer shares with the file system and the terminal: bounded reads of the user's files (`input`),
//! checked, atomic writes of images and files ([`output`]), the on-disk cache of tables and references (`cache`),
//! progress bars on stderr (`progress`) and the statistics the reports print ([`stats`]).

pub(crate) mod cache;
pub(crate) mod input;
pub mod output;
pub(crate) mod progress;
pub mod stats;
