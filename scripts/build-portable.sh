#!/usr/bin/env bash
# Builds wrinkle for any x86-64 CPU (baseline x86-64: SSE2, no AVX) beside the default x86-64-v3 build:
#   target/release/wrinkle-portable                       the CLI; target/release/wrinkle hands over to it
#                                                         on a CPU without AVX2
#   crates/wrinkle-py/python/wrinkle/_wrinkle_portable.abi3.so
#                                                         the Python module: `pip install ./crates/wrinkle-py`
#                                                         (or maturin build) after this packs it in the wheel
# Both give the same bits as the x86-64-v3 build (crates/wrinkle/src/lanes/math.rs), slower.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "$(uname -m)" != x86_64 ]; then
  echo "build-portable: only x86-64 has two builds; here 'cargo build --release' is already portable" >&2
  exit 1
fi
# RUSTFLAGS replaces .cargo/config.toml's target-cpu=x86-64-v3; its own target folder keeps both builds.
RUSTFLAGS="-C target-cpu=x86-64" cargo build --release -p wrinkle-cli -p wrinkle-py --target-dir target/portable
mkdir -p target/release
install -m 755 target/portable/release/wrinkle target/release/wrinkle-portable
install -m 644 target/portable/release/lib_wrinkle.so crates/wrinkle-py/python/wrinkle/_wrinkle_portable.abi3.so
echo "built target/release/wrinkle-portable and crates/wrinkle-py/python/wrinkle/_wrinkle_portable.abi3.so (a build output: do not commit it)"
