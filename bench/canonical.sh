#!/usr/bin/env bash
# Renders the canonical scene (bench/canonical/sphere.toml, 1920x1080) with and without bump mapping,
# alternating, on all cores and on one; then with 16 samples per pixel. Prints one line per run.
# Usage: bench/canonical.sh [ROUNDS]   (from the repository root)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
scene=bench/canonical/sphere.toml
cargo build --release -q -p wrinkle-cli
bin=target/release/wrinkle
for ((r = 0; r < rounds; r++)); do
  for threads in 2 1; do
    for bump in "" "--no-bump"; do
      $bin bench "$scene" --width 1920 --height 1080 --frames 9 --threads "$threads" $bump
    done
  done
done
for bump in "" "--no-bump"; do
  $bin bench "$scene" --width 1920 --height 1080 --frames 3 --spp 16 $bump
done
