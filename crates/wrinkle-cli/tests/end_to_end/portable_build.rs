//! The portable build (baseline x86-64) of both front ends, as scripts/build-portable.sh builds it: its own
//! target folder, RUSTFLAGS replacing .cargo/config.toml's x86-64-v3. Shared by this crate's tests and the
//! Python package's (crates/wrinkle-py/tests/python.rs includes this file): one command, one feature
//! resolution, so whichever test runs second finds everything built.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Builds the CLI and the Python module for baseline x86-64 under `target`/portable and returns the folder
/// that holds them (`wrinkle`, `lib_wrinkle.so`).
pub fn build_portable(target: &Path) -> PathBuf {
    let portable = target.join("portable");
    let status = Command::new(std::env::var_os("CARGO").unwrap_or("cargo".into()))
        .args(["build", "--release", "-p", "wrinkle-cli", "-p", "wrinkle-py", "--target-dir"])
        .arg(&portable)
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env("RUSTFLAGS", "-C target-cpu=x86-64")
        .status()
        .expect("cargo");
    assert!(status.success(), "the portable build failed");
    portable.join("release")
}
