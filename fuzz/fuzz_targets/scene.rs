//! Fuzz target: arbitrary bytes as a user's file, read by `diffract::fuzz::scene`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| diffract::fuzz::scene(data));
