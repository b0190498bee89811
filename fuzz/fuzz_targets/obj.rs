//! Fuzz target: arbitrary bytes as a user's file, read by `diffract::fuzz::obj`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| diffract::fuzz::obj(data));
