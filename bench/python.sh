#!/usr/bin/env bash
# The Python package's speed (BENCHMARKS.md, "Python package"): installs the package and pyfastnoiselite into
# a venv of its own (out/bench-python-venv) and runs bench/python_bench.py beside the CLI's bench-texture.
# Usage: bench/python.sh [ROUNDS]   (from the repository root)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
venv=out/bench-python-venv
cargo build --release -q -p wrinkle-cli
[[ -x $venv/bin/python ]] || python3 -m venv "$venv"
"$venv/bin/pip" install -q --disable-pip-version-check ./crates/wrinkle-py pyfastnoiselite
grep -m1 "model name" /proc/cpuinfo
"$venv/bin/python" bench/python_bench.py "$PWD/target/release/wrinkle" "$rounds"
