//! Fuzz target: arbitrary bytes as a user's file, read by `diffract::fuzz::gsf`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| diffract::fuzz::gsf(data));
