"""The farm's speed (BENCHMARKS.md, "Farm on Ray"): an animation rendered by the CLI on every core against the
farm with 1 and 2 local workers, and the farm's cost per task (tiny frames, whose rendering is negligible).
Each Ray instance is started once per worker count and not timed; rounds alternate. Run by bench/farm.sh."""

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import ray

from wrinkle import farm

cli, rounds = sys.argv[1], int(sys.argv[2])
scene = Path(__file__).resolve().parent.parent / "scenes" / "animation.toml"
FRAMES, SIZE = "0..7", dict(width=960, height=540, spp=16)
TINY, TINY_FRAMES = dict(width=32, height=24, spp=1), "0..99"


def timed(f):
    t = time.perf_counter()
    f()
    return time.perf_counter() - t


def cli_job(frames, size, out):
    args = [cli, "render", str(scene), "-o", str(out / "c.png"), "--frames", frames]
    for k, v in size.items():
        args += [f"--{k}", str(v)]
    subprocess.run(args, check=True)


results = {}
for workers in (1, 2):
    farm.connect("local", num_cpus=workers)
    # Warm: the workers start and import the package once.
    with tempfile.TemporaryDirectory() as d:
        farm.render(Path(d) / "w.png", scene, frames="0..3", progress=False, **TINY)
    for r in range(rounds):
        with tempfile.TemporaryDirectory() as d:
            results.setdefault(("cli", "animation"), []).append(timed(lambda: cli_job(FRAMES, SIZE, Path(d))))
        with tempfile.TemporaryDirectory() as d:
            job = lambda: farm.render(Path(d) / "f.png", scene, frames=FRAMES, progress=False, **SIZE)
            results.setdefault((f"farm {workers}", "animation"), []).append(timed(job))
        with tempfile.TemporaryDirectory() as d:
            results.setdefault(("cli", "tiny"), []).append(timed(lambda: cli_job(TINY_FRAMES, TINY, Path(d))))
        with tempfile.TemporaryDirectory() as d:
            job = lambda: farm.render(Path(d) / "t.png", scene, frames=TINY_FRAMES, progress=False, **TINY)
            results.setdefault((f"farm {workers}", "tiny"), []).append(timed(job))
    ray.shutdown()

for (who, what), times in sorted(results.items()):
    n = 8 if what == "animation" else 100
    med = statistics.median(times)
    print(f"{what:9} {who:7} median {med:7.3f} s  best {min(times):7.3f} s  per frame {1e3 * med / n:8.2f} ms")
