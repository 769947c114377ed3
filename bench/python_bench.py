"""Speed of the Python package (BENCHMARKS.md, "Python package"): per-call overhead of one texture lookup,
batched lookups against the Rust benchmark's rate, noise against pyfastnoiselite in the same run, and two
Python threads rendering at once against one. Run by bench/python.sh; prints one line per figure."""

import os
import statistics
import subprocess
import sys
import threading
import time

import numpy as np

import wrinkle


def best_and_median(f, rounds):
    times = []
    for _ in range(rounds):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times), statistics.median(times)


def lookups(n, seed=1):
    """Random (s, t) and isotropic footprints of width log-uniform in [2^-12, 2^-6], as bench-texture."""
    rng = np.random.default_rng(seed)
    uv = rng.random((n, 2), dtype=np.float32)
    w = 2.0 ** (-12.0 + 6.0 * rng.random(n))
    a = rng.random(n) * 2 * np.pi
    c, s = np.cos(a), np.sin(a)
    fp = np.stack([w * c, w * s, -w * s, w * c], axis=1).astype(np.float32)
    return uv, fp


def main():
    cli = sys.argv[1]
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    rng = np.random.default_rng(7)
    size = 4096
    pixels = (rng.random((size, size, 4)) * 255).astype(np.uint8)
    tex = wrinkle.Texture(pixels)

    # Per-call overhead: one lookup, whole Python call included (the loop's own cost too): the scalar
    # `lookup`, and `sample` given one point (which makes arrays in and out).
    calls = 100_000
    best, med = best_and_median(lambda: [tex.lookup(0.5, 0.5) for _ in range(calls)], rounds)
    print(f"one_lookup_call_us median={med / calls * 1e6:.2f} best={best / calls * 1e6:.2f}")
    best, med = best_and_median(lambda: [tex.sample((0.5, 0.5)) for _ in range(calls)], rounds)
    print(f"one_point_sample_call_us median={med / calls * 1e6:.2f} best={best / calls * 1e6:.2f}")

    # Batched: 10^6 random trilinear lookups, all cores, against `wrinkle bench-texture` in the same run.
    uv, fp = lookups(1_000_000)
    best, med = best_and_median(lambda: tex.sample(uv, fp), rounds)
    print(f"batched_trilinear_mlookups_per_s median={1 / med:.2f} best={1 / best:.2f}")
    out = subprocess.run([cli, "bench-texture", "--filters", "trilinear", "--rounds", str(rounds)],
                         capture_output=True, text=True, check=True).stdout
    line = next(l for l in out.splitlines() if "footprint=iso order=random" in l)
    rust = {k: v for k, v in (f.split("=") for f in line.split())}
    threads = next(k for k in rust if k.startswith("mlookups_per_s_") and k.endswith("threads") and "1thread" not in k)
    print(f"rust_bench_texture_trilinear_iso_random {threads}={rust[threads]}")

    # Noise: 4M random points in [0, 10)^3, wrinkle (all cores) against pyfastnoiselite (one core, GIL held).
    points = (rng.random((4_000_000, 3)) * 10).astype(np.float32)
    best, med = best_and_median(lambda: wrinkle.noise.perlin(points), rounds)
    print(f"wrinkle_perlin3_mpts median={4 / med:.1f} best={4 / best:.1f}")
    try:
        from pyfastnoiselite.pyfastnoiselite import FastNoiseLite, NoiseType

        fnl = FastNoiseLite(0)
        fnl.noise_type = NoiseType.NoiseType_Perlin
        coords = np.ascontiguousarray(points.T)
        best, med = best_and_median(lambda: fnl.gen_from_coords(coords), rounds)
        print(f"pyfastnoiselite_perlin3_mpts median={4 / med:.1f} best={4 / best:.1f}")
    except ImportError:
        print("pyfastnoiselite not installed: skipped")

    # Two threads rendering at once against one render, default scene 1920x1080: with all cores each render
    # already fills the machine; with one worker thread a render (RAYON_NUM_THREADS=1, in a process of its
    # own) leaves a core to the other thread only if the GIL is released.
    for workers in ("all", "1"):
        env = dict(os.environ)
        if workers == "1":
            env["RAYON_NUM_THREADS"] = "1"
        out = subprocess.run([sys.executable, __file__, "--renders", str(rounds)], env=env, capture_output=True,
                             text=True, check=True).stdout.strip()
        print(f"render_1080p_ms workers={workers} {out}")


def renders(rounds):
    scene = wrinkle.Scene.default()
    scene.render(1920, 1080)

    def two():
        ts = [threading.Thread(target=scene.render, args=(1920, 1080)) for _ in range(2)]
        for t in ts:
            t.start()
        for t in ts:
            t.join()

    _, med1 = best_and_median(lambda: scene.render(1920, 1080), rounds)
    _, med2 = best_and_median(two, rounds)
    print(f"one={med1 * 1e3:.1f} two_threads_at_once={med2 * 1e3:.1f} ratio={med2 / med1:.2f}")


if __name__ == "__main__":
    if sys.argv[1] == "--renders":
        renders(int(sys.argv[2]))
    else:
        main()
