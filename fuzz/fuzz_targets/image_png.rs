//! The `image_png` target: its body is `targets::image_png` (fuzz/targets.rs), shared with the stable harness.
#![no_main]

#[path = "../targets.rs"]
mod targets;

libfuzzer_sys::fuzz_target!(|data: &[u8]| targets::image_png(data));
