//! The `scene` target: its body is `targets::scene` (fuzz/targets.rs), shared with the stable harness.
#![no_main]

#[path = "../targets.rs"]
mod targets;

libfuzzer_sys::fuzz_target!(|data: &[u8]| targets::scene(data));
