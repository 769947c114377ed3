//! The `image_bmp` target: its body is `targets::image_bmp` (fuzz/targets.rs), shared with the stable harness.
#![no_main]

#[path = "../targets.rs"]
mod targets;

libfuzzer_sys::fuzz_target!(|data: &[u8]| targets::image_bmp(data));
