//! The `obj` target: its body is `targets::obj` (fuzz/targets.rs), shared with the stable harness.
#![no_main]

#[path = "../targets.rs"]
mod targets;

libfuzzer_sys::fuzz_target!(|data: &[u8]| targets::obj(data));
