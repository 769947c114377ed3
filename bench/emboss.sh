#!/usr/bin/env bash
# Whole-command timings of `wrinkle emboss` and `wrinkle normalmap` against ImageMagick's -shade and the
# NumPy + OpenCV scripts of bench/emboss_numpy.py, alternating, on a 4096x4096 8-bit grey PNG; then
# emboss on 16384x16384 with its peak memory. Prints one line per run ("tool seconds peak-KB") and a
# summary (median and min per tool).
# Needs: ImageMagick 6 (convert-im6.q16; apt-get install imagemagick), python3 with numpy and
# opencv-python-headless (pip install numpy opencv-python-headless), GNU time.
# Usage: bench/emboss.sh [ROUNDS] [WORKDIR]   (from the repository root; inputs are made once in WORKDIR)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-5}
work=${2:-out/bench-emboss}
mkdir -p "$work"
cargo build --release -q -p wrinkle-cli
bin=$PWD/target/release/wrinkle
im=$(command -v convert-im6.q16 || command -v magick)
py="python3 $PWD/bench/emboss_numpy.py"
in4k=$work/in4k.png
in16k=$work/in16k.png
if [[ ! -f $in4k ]]; then
  # Fractal plasma, blurred a little: a height map with detail at every scale (paeth-filtered, zlib 6).
  $im -seed 7 -size 4096x4096 plasma:fractal -blur 0x2 -colorspace Gray -depth 8 -define png:color-type=0 "$in4k"
fi
if [[ ! -f $in16k ]]; then
  python3 -c "import cv2, numpy as np, sys; a = cv2.imread(sys.argv[1], 0); cv2.imwrite(sys.argv[2], np.tile(a, (4, 4)))" "$in4k" "$in16k"
fi
log=$work/runs.txt
: >"$log"
run() { # name, command...
  local name=$1
  shift
  /usr/bin/time -f "$name %e %M" -a -o "$log" "$@" >/dev/null 2>&1
  tail -1 "$log"
}
for ((r = 0; r < rounds; r++)); do
  run wrinkle-emboss $bin emboss "$in4k" -o "$work/w_emboss.png"
  run wrinkle-emboss-default $bin emboss "$in4k" -o "$work/w_emboss_default.png" --compression default
  run wrinkle-emboss-1thread $bin emboss "$in4k" -o "$work/w_emboss_1.png" --threads 1
  run imagemagick-shade $im "$in4k" -shade 135x45 "$work/im_shade.png"
  run imagemagick-shade-fastpng $im "$in4k" -shade 135x45 -define png:compression-level=1 "$work/im_shade_fast.png"
  run numpy-opencv-emboss $py emboss "$in4k" "$work/np_emboss.png"
  run wrinkle-normalmap $bin normalmap "$in4k" -o "$work/w_normal.png"
  run numpy-opencv-normalmap $py normalmap "$in4k" "$work/np_normal.png"
done
for ((r = 0; r < rounds; r++)); do
  run wrinkle-emboss-16k $bin emboss "$in16k" -o "$work/w_emboss16k.png"
done
$bin emboss "$in4k" -o "$work/w_emboss.png" --stats
echo "summary (seconds: median, min; peak KB: median)"
sort -k1,1 -s "$log" | awk '
  function flush() { if (n) { m = (n % 2) ? t[(n+1)/2] : (t[n/2] + t[n/2+1]) / 2; mm = (n % 2) ? k[(n+1)/2] : k[n/2];
    printf "%-28s %7.3f %7.3f %9d\n", name, m, t[1], mm } }
  $1 != name { flush(); name = $1; n = 0 }
  { n++; t[n] = $2; k[n] = $3; for (i = n; i > 1 && t[i] < t[i-1]; i--) { x = t[i]; t[i] = t[i-1]; t[i-1] = x }
    for (i = n; i > 1 && k[i] < k[i-1]; i--) { x = k[i]; k[i] = k[i-1]; k[i-1] = x } }
  END { flush() }'
ls -l "$work"/*.png | awk '{ print $5, $9 }'
