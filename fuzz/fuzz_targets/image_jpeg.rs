//! The `image_jpeg` target: its body is `targets::image_jpeg` (fuzz/targets.rs), shared with the stable harness.
#![no_main]

#[path = "../targets.rs"]
mod targets;

libfuzzer_sys::fuzz_target!(|data: &[u8]| targets::image_jpeg(data));
