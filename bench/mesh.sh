#!/usr/bin/env bash
# A 1M-triangle textured, normal-mapped mesh (the canonical scene's bricks on a UV sphere of 1000 x 500
# quads, OBJ with its .mtl) at 1920x1080, 1 spp, trilinear: the render of one frame in-process (median of 9
# after a warm-up) and the whole command, which loads the model (OBJ parse, MikkTSpace tangents); then the
# load times of the OBJ and of the same sphere as GLB, beside tobj and gltf::import alone.
# Usage: bench/mesh.sh [ROUNDS]   (from the repository root)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cargo build --release -q -p wrinkle-cli
cargo build --release -q -p wrinkle --example model_parsers_alone
bin=target/release/wrinkle
python3 bench/mesh_sphere.py "$dir"
cp bench/canonical/bricks_color.png "$dir/"
$bin normalmap bench/canonical/bricks_height.png -o "$dir/bricks_normal.png" --strength 2 --wrap
cp bench/mesh/scene.toml "$dir/mesh.toml"
for ((r = 0; r < rounds; r++)); do
  start=$(date +%s.%N)
  $bin bench "$dir/mesh.toml" --width 1920 --height 1080 --frames 9
  echo "whole command: $(echo "$(date +%s.%N) - $start" | bc) s"
done
sed 's/sphere.obj/sphere.glb/' "$dir/mesh.toml" > "$dir/mesh_glb.toml"
for ((r = 0; r < rounds; r++)); do
  for scene in mesh mesh_glb; do
    $bin render "$dir/$scene.toml" -o "$dir/load.png" --width 64 --height 64 --stats 2>&1 | grep loaded | sed "s/^scene/$scene/"
  done
  target/release/examples/model_parsers_alone "$dir/sphere.obj" "$dir/sphere.glb" 2>/dev/null
done
