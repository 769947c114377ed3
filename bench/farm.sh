#!/usr/bin/env bash
# The farm's scaling and per-task overhead (BENCHMARKS.md, "Farm on Ray"): installs the package with its
# farm extra (Ray) into a venv of its own (out/bench-farm-venv) and runs bench/farm_bench.py beside the CLI.
# Usage: bench/farm.sh [ROUNDS]   (from the repository root)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
venv=out/bench-farm-venv
cargo build --release -q -p wrinkle-cli
[[ -x $venv/bin/python ]] || python3 -m venv "$venv"
"$venv/bin/pip" install -q --disable-pip-version-check "./crates/wrinkle-py[farm]"
grep -m1 "model name" /proc/cpuinfo
"$venv/bin/python" bench/farm_bench.py "$PWD/target/release/wrinkle" "$rounds"
