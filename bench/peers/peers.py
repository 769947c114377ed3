#!/usr/bin/env python3
"""The table of bench/peers/run: every workload on wrinkle and on each peer, alternating tool by tool, round
by round, after one warm-up run each; then one line per workload and tool with the median and best of the
rounds, wrinkle's advantage (peer time / wrinkle time, or wrinkle rate / peer rate) and the CPU model.

Run through bench/peers/run, which installs the peers and builds wrinkle, FastNoise2 and the OpenImageIO
benchmark first. A workload whose tool fails is left out with one line saying why; the others still run.
usage: peers.py --work DIR [--quick] [--rounds N] [--only canonical,environment,shadows,texture,noise,emboss,normalmap,mesh]
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Dr.Jit's LLVM backend (Mitsuba's llvm variants) needs a libLLVM newer than the one Mesa brings.
for _llvm in ["/usr/lib/x86_64-linux-gnu/libLLVM-19.so", "/usr/lib/llvm-19/lib/libLLVM.so"]:
    if os.path.exists(_llvm):
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", _llvm)
        break
WRINKLE = os.path.join(ROOT, "target", "release", "wrinkle")
FASTNOISE2 = os.path.join(ROOT, "target", "peers", "release", "fastnoise2-bench")
OIIO_LOOKUP = os.path.join(ROOT, "target", "peers", "oiio_lookup")


def cpu_model():
    info = {}
    with open("/proc/cpuinfo") as f:
        for line in f:
            key, _, value = line.partition(":")
            info.setdefault(key.strip(), value.strip())
    flags = info.get("flags", "").split()
    wide = "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else "SSE"
    return (f"{info.get('model name', '?')} (family {info.get('cpu family', '?')} model {info.get('model', '?')}, "
            f"{wide}), {os.cpu_count()} cores")


def keyvalues(text):
    """The key=value pairs of a line like bench-noise's."""
    return {k: v for k, v in re.findall(r"(\w+)=([^\s]+)", text)}


class Tool:
    """One tool's command on one workload; `measure` runs it once and returns {metric: value}. `picture`, when
    given, is the frame it writes, compared after the rounds with wrinkle's (or with `against`, a frame it stands
    in for, or with its metric's reference frame); `notes` holds what that found, per metric."""

    def __init__(self, name, argv, read, picture=None, against=None):
        self.name, self.argv, self.read, self.picture, self.against = name, argv, read, picture, against
        self.samples = {}
        self.notes = {}

    def measure(self):
        start = time.perf_counter()
        run = subprocess.run(self.argv, capture_output=True, text=True, cwd=ROOT)
        wall = time.perf_counter() - start
        if run.returncode != 0:
            raise RuntimeError(f"{self.name}: {' '.join(self.argv)} failed: {run.stderr.strip()[-300:]}")
        return self.read(run.stdout + run.stderr, wall)


def wall_ms(metric):
    return lambda out, wall: {metric: 1e3 * wall}


def fields(mapping):
    """Reads metrics from key=value output: mapping is {metric: key}."""
    def read(out, wall):
        kv = keyvalues(out)
        return {metric: float(kv[key]) for metric, key in mapping.items()}
    return read


# Metric name -> (unit, higher is better).
UNITS = {}
# Metric name -> (frame, what it is): the frame every tool's picture is compared with on that metric, where it
# is not wrinkle's own (an equal-quality metric: each tool's picture against the converged frame).
REFERENCES = {}


def metric(name, unit, higher_better, reference=None):
    UNITS[name] = (unit, higher_better)
    if reference:
        REFERENCES[name] = reference
    return name


def noise_workload(args):
    points, inner = (1_000_000, 3) if args.quick else (4_000_000, 7)
    perlin = metric("3D Perlin noise, random points, 1 thread", "M points/s", True)
    fbm = metric("3D 6-octave fBm, 1 thread", "M points/s", True)
    image = metric("1024x1024 2D 6-octave fBm image, 1 thread", "ms", False)
    tools = [Tool("wrinkle", [WRINKLE, "bench-noise", "--threads", "1", "--rounds", str(inner), "--points", str(points)],
                  fields({perlin: "perlin3_mpts", fbm: "fbm6_mpts", image: "texture1024_fbm_ms"})),
             Tool("wrinkle, Perlin's table (reference values)",
                  [WRINKLE, "bench-noise", "--threads", "1", "--rounds", str(inner), "--points", str(points)],
                  fields({perlin: "perlin3_reference_mpts", fbm: "fbm6_reference_mpts",
                          image: "texture1024_fbm_reference_ms"}))]
    if os.access(FASTNOISE2, os.X_OK):
        tools.append(Tool("FastNoise2 (fastnoise2 0.4 crate, its C++ library)", [FASTNOISE2, str(points), str(inner), "1"],
                          fields({perlin: "perlin3_mpts", fbm: "fbm6_mpts", image: "texture1024_fbm_ms"})))
    else:
        print("left out: FastNoise2 (not built; see out/peers/fastnoise2.log)", file=sys.stderr)
    return tools


def line_fields(mapping):
    """Reads metrics from the line that holds every `selector` word: mapping is {metric: (selector, key)}."""
    def read(out, wall):
        found = {}
        for metric, (selector, key) in mapping.items():
            line = next(l for l in out.splitlines() if all(w in l.split() for w in selector.split()))
            found[metric] = float(keyvalues(line)[key])
        return found
    return read


def texture_workload(args, work):
    size, lookups, inner = ("2048", "200000", "1") if args.quick else ("4096", "1000000", "3")
    tri, tri_batch = (metric(f"trilinear lookups, iso footprints, random, {size}^2 RGBA8, 1 thread, {k}", "M/s", True)
                      for k in ("one a call", "a batch of 16 a call"))
    ani, ani_batch = (metric(f"anisotropic 8:1 lookups, random, {size}^2 RGBA8, 1 thread, {k}", "M/s", True)
                      for k in ("one a call", "a batch of 16 a call"))
    build = metric(f"MIP pyramid build {size}^2 RGBA8, 1 thread", "ms", False)
    iso, aniso = "filter=trilinear footprint=iso order=random", "filter=aniso footprint=aniso8 order=random"
    tools = [Tool("wrinkle", [WRINKLE, "bench-texture", "--filters", "trilinear,aniso", "--size", size, "--lookups",
                              lookups, "--rounds", inner, "--threads", "1"],
                  line_fields({tri: (iso, "mlookups_per_s_1thread"), tri_batch: (iso, "batch_1thread"),
                               ani: (aniso, "mlookups_per_s_1thread"), ani_batch: (aniso, "batch_1thread"),
                               build: ("pyramid", "build_ms")}))]
    if os.access(OIIO_LOOKUP, os.X_OK):
        tools.append(Tool("OpenImageIO TextureSystem (C++, bench/peers/oiio)",
                          [OIIO_LOOKUP, work, size, lookups, inner],
                          line_fields({tri: (iso, "mlookups_per_s_1thread"), tri_batch: (iso, "batch16_1thread"),
                                       ani: (aniso, "mlookups_per_s_1thread"), ani_batch: (aniso, "batch16_1thread"),
                                       build: ("make_texture", "build_ms")})))
    else:
        print("left out: OpenImageIO (not built; see out/peers/oiio.log)", file=sys.stderr)
    return tools


def height_image(args, work):
    """A grey 8-bit height map with detail at every scale: ImageMagick's seeded plasma, blurred a little."""
    size = 2048 if args.quick else 4096
    path = os.path.join(work, f"height{size}.png")
    if not os.path.exists(path):
        im = shutil.which("convert-im6.q16") or shutil.which("magick") or shutil.which("convert")
        if im is None:
            raise RuntimeError("ImageMagick is needed to make the height map")
        subprocess.run([im, "-seed", "7", "-size", f"{size}x{size}", "plasma:fractal", "-blur", "0x2", "-colorspace",
                        "Gray", "-depth", "8", "-define", "png:color-type=0", path], check=True)
    return path


def python_has(*modules):
    return subprocess.run([sys.executable, "-c", "import " + ", ".join(modules)], capture_output=True).returncode == 0


def height_map_workload(command, label, args, work):
    """`wrinkle COMMAND` (emboss or normalmap) on the height map, whole command, beside the peers that do it:
    NumPy + OpenCV for both, ImageMagick's -shade and GEGL's emboss for emboss."""
    src = height_image(args, work)
    size = "2048^2" if args.quick else "4096^2"
    m = metric(f"{label} {size} grey PNG, whole command", "ms", False)
    out = lambda name: os.path.join(work, name)
    tools = [Tool("wrinkle", [WRINKLE, command, src, "-o", out(f"w_{command}.png")], wall_ms(m))]
    im = shutil.which("convert-im6.q16") or shutil.which("magick")
    if command == "emboss" and im:
        tools.append(Tool("ImageMagick -shade 135x45, PNG level 1",
                          [im, src, "-shade", "135x45", "-define", "png:compression-level=1", out("im_shade.png")],
                          wall_ms(m)))
    elif command == "emboss":
        print("left out: ImageMagick (not installed)", file=sys.stderr)
    if command == "emboss" and shutil.which("gegl"):
        # GEGL's own emboss (GIMP's filter): depth 3 is the nearest to the others' bevel; it pads its output by
        # three pixels and writes 16-bit grey with alpha.
        tools.append(Tool("GEGL gegl:emboss (the gegl command)", ["gegl", src, "-o", out("gegl_emboss.png"), "--",
                                                                  "gegl:emboss", "azimuth=135", "elevation=45",
                                                                  "depth=3"], wall_ms(m)))
    elif command == "emboss":
        print("left out: GEGL (not installed)", file=sys.stderr)
    if python_has("numpy", "cv2"):
        tools.append(Tool("NumPy + OpenCV (bench/emboss_numpy.py)",
                          [sys.executable, "bench/emboss_numpy.py", command, src, out(f"np_{command}.png")],
                          wall_ms(m)))
    else:
        print("left out: NumPy + OpenCV (not installed)", file=sys.stderr)
    return tools


def psnr(a_png, b_png):
    """PSNR (8-bit) of two frames over the pixels either covers (both backgrounds are black)."""
    import numpy as np
    from PIL import Image
    a = np.asarray(Image.open(a_png).convert("RGB"), np.float64)
    b = np.asarray(Image.open(b_png).convert("RGB"), np.float64)
    covered = (a.sum(2) > 0) | (b.sum(2) > 0)
    mse = ((a - b) ** 2)[covered].mean()
    return 10 * np.log10(255 ** 2 / max(mse, 1e-12))


def wrinkle_frame(m, scene, frames, picture, spp=1, shading_rate="sample", against=None, extra=()):
    """wrinkle's frame of `scene` at 1920x1080 and `spp` samples (and `extra` options): timed in-process by
    `wrinkle bench`, and rendered once now to `picture`, which the peers' frames are compared with (and which
    is compared with `against`, the frame of another shading rate it stands in for, where given)."""
    size = ["--width", "1920", "--height", "1080", "--spp", str(spp), "--shading-rate", shading_rate] + list(extra)
    subprocess.run([WRINKLE, "render", scene, "-o", picture] + size, check=True, capture_output=True)
    name = "wrinkle (2 threads)" if shading_rate == "sample" else f"wrinkle (2 threads), shaded once per {shading_rate}"
    if extra:
        name += f", {spp} spp {' '.join(extra)}"
    return Tool(name, [WRINKLE, "bench", scene, "--frames", frames] + size, fields({m: "median_ms"}), picture=picture,
                against=against)


def canonical_workload(args, work):
    """The canonical scene at 1 spp and at 16 (wrinkle's 16 samples, llvmpipe's 4x4 supersampling, Mitsuba's
    16 samples per pixel)."""
    frames = "3" if args.quick else "9"
    scene = os.path.join(ROOT, "bench/canonical/sphere.toml")
    tools = []
    for spp, ss, mitsuba in [(1, 1, ["llvm_ad_rgb", "scalar_rgb"]), (16, 4, ["llvm_ad_rgb"])]:
        m = metric(f"canonical bump-mapped sphere 1920x1080 {spp} spp, frame", "ms", False)
        tools.append(wrinkle_frame(m, scene, frames, os.path.join(work, f"wrinkle_canonical_{spp}.png"), spp))
        # Several samples: also wrinkle's multisampling (each triangle shaded once per pixel), whose own
        # metric repeats the peers' figures beside it.
        ms = {m: "median_ms"}
        if spp > 1:
            mp = metric(f"canonical bump-mapped sphere 1920x1080 {spp} spp, wrinkle shading once per pixel, frame",
                        "ms", False)
            tools.append(wrinkle_frame(mp, scene, frames, os.path.join(work, f"wrinkle_canonical_{spp}_pixel.png"),
                                       spp, "pixel", against=tools[-1].picture))
            ms[mp] = "median_ms"
            # Equal quality: 4 samples with the level of detail half a level finer (docs/filtering.md) come
            # as close to the converged frame as the peers' 16; each picture is measured against that frame.
            converged = os.path.join(work, "wrinkle_canonical_converged.png")
            subprocess.run([WRINKLE, "render", scene, "-o", converged, "--width", "1920", "--height", "1080",
                            "--spp", "64" if args.quick else "256"], check=True, capture_output=True)
            mq = metric(f"canonical bump-mapped sphere 1920x1080 at {spp} spp's quality (wrinkle 4 spp, lod bias -0.5), "
                        "frame", "ms", False, reference=(converged, f"the converged frame ({'64' if args.quick else '256'} spp)"))
            tools.append(wrinkle_frame(mq, scene, frames, os.path.join(work, "wrinkle_canonical_4_lod.png"), 4,
                                       extra=["--lod-bias", "-0.5"]))
            ms[mq] = "median_ms"
        if python_has("moderngl", "numpy", "PIL"):
            theirs = os.path.join(work, f"llvmpipe_canonical_{spp}.png")
            name = "Mesa llvmpipe (GLSL Blinn bump, 512x256 sphere mesh" + (f", {ss}x{ss} supersampled)" if ss > 1 else ")")
            tools.append(Tool(name, [sys.executable, "bench/llvmpipe_canonical.py", "bench/canonical", theirs, frames,
                                     str(ss)], fields(ms), picture=theirs))
        else:
            print("left out: llvmpipe (moderngl not installed)", file=sys.stderr)
        if python_has("mitsuba"):
            for variant in mitsuba:
                tools.append(Tool(f"Mitsuba 3 {variant} (bumpmap BSDF, direct lighting)",
                                  [sys.executable, "bench/mitsuba_canonical.py", variant, "bench/canonical",
                                   os.path.join(work, f"mitsuba_{variant}_{spp}.png"), frames, str(spp)],
                                  fields({m: "median_ms"})))
        else:
            print("left out: Mitsuba 3 (not installed)", file=sys.stderr)
    return tools


def scene_workload(label, scene, peer_script, args, work):
    """One benchmark scene of bench/ at 1920x1080, 1 spp: wrinkle's frame beside its llvmpipe peer's, and their
    pictures compared."""
    frames = "3" if args.quick else "9"
    m = metric(f"{label} 1920x1080 1 spp, frame", "ms", False)
    scene = os.path.join(ROOT, scene)
    name = os.path.splitext(os.path.basename(peer_script))[0]
    tools = [wrinkle_frame(m, scene, frames, os.path.join(work, f"wrinkle_{name}.png"))]
    if python_has("moderngl", "numpy", "PIL", "cv2"):
        theirs = os.path.join(work, f"{name}.png")
        # The peers read their inputs relative to bench/.
        tools.append(Tool("Mesa llvmpipe", ["sh", "-c", 'cd bench && exec "$0" "$@"', sys.executable,
                                            os.path.basename(peer_script), theirs, frames],
                          fields({m: "median_ms"}), picture=theirs))
    else:
        print("left out: llvmpipe (moderngl or OpenCV not installed)", file=sys.stderr)
    return tools


def mesh_workload(args, work):
    folder = os.path.join(work, "mesh")
    os.makedirs(folder, exist_ok=True)
    if not os.path.exists(os.path.join(folder, "sphere.obj")):
        subprocess.run([sys.executable, "bench/mesh_sphere.py", folder], check=True, cwd=ROOT)
        shutil.copy(os.path.join(ROOT, "bench/canonical/bricks_color.png"), folder)
        subprocess.run([WRINKLE, "normalmap", "bench/canonical/bricks_height.png", "-o",
                        os.path.join(folder, "bricks_normal.png"), "--strength", "2", "--wrap"], check=True, cwd=ROOT,
                       capture_output=True)
    shutil.copy(os.path.join(ROOT, "bench/mesh/scene.toml"), os.path.join(folder, "mesh.toml"))
    frames = "3" if args.quick else "9"
    m = metric("1M-triangle normal-mapped mesh 1920x1080 1 spp, frame", "ms", False)
    scene = os.path.join(folder, "mesh.toml")
    tools = [wrinkle_frame(m, scene, frames, os.path.join(work, "wrinkle_mesh.png"))]
    if python_has("moderngl", "numpy", "PIL"):
        theirs = os.path.join(work, "llvmpipe_mesh.png")
        tools.append(Tool("Mesa llvmpipe (GLSL normal mapping)",
                          [sys.executable, "bench/llvmpipe_mesh.py", folder, frames, theirs], fields({m: "median_ms"}),
                          picture=theirs))
    else:
        print("left out: llvmpipe (moderngl not installed)", file=sys.stderr)
    return tools


WORKLOADS = {
    "canonical": canonical_workload,
    "environment": lambda a, w: scene_workload("chrome sphere mirroring an HDR environment, as background too",
                                               "bench/environment/scene.toml", "bench/llvmpipe_environment.py", a, w),
    "shadows": lambda a, w: scene_workload("two spheres on a floor, a sun's 1024^2 shadow map", "bench/shadows/scene.toml",
                                           "bench/llvmpipe_shadows.py", a, w),
    "texture": texture_workload,
    "noise": lambda a, w: noise_workload(a),
    "emboss": lambda a, w: height_map_workload("emboss", "emboss", a, w),
    "normalmap": lambda a, w: height_map_workload("normalmap", "normal map", a, w),
    "mesh": mesh_workload,
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--work", required=True)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--rounds", type=int)
    parser.add_argument("--only", default=",".join(WORKLOADS))
    args = parser.parse_args()
    rounds = args.rounds or (2 if args.quick else 5)
    chosen = [w.strip() for w in args.only.split(",") if w.strip()]
    unknown = [w for w in chosen if w not in WORKLOADS]
    if unknown:
        sys.exit(f"peers.py: unknown workload {', '.join(unknown)} (expected some of {', '.join(WORKLOADS)})")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=ROOT).stdout.strip()
    print(f"CPU: {cpu_model()}; wrinkle {commit}; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; "
          f"{rounds} rounds, alternating, after a warm-up", flush=True)
    rows = []
    for name in chosen:
        try:
            tools = WORKLOADS[name](args, args.work)
            for tool in tools:
                tool.measure()  # warm-up: caches, page cache, lazy loading
            for r in range(rounds):
                for tool in tools:
                    for m, v in tool.measure().items():
                        tool.samples.setdefault(m, []).append(v)
                print(f"{name}: round {r + 1}/{rounds} done", file=sys.stderr, flush=True)
        except (RuntimeError, subprocess.CalledProcessError, KeyError, StopIteration, ValueError) as e:
            # One line, and the other workloads still run.
            print(f"bench/peers: {name} left out: {str(e).splitlines()[0] if str(e) else type(e).__name__}",
                  file=sys.stderr)
            continue
        for tool in tools:
            for m in tool.samples:
                # The metric's reference frame; else the frame a second wrinkle run (another shading rate)
                # stands in for; else the wrinkle run of the same metric (listed first for each metric).
                ours = next(t for t in tools if t.name.startswith("wrinkle") and m in t.samples)
                reference, what = REFERENCES.get(m) or (
                    (tool.against, "wrinkle's frame shading every sample") if tool.against else
                    (ours.picture if tool is not ours else None, "wrinkle's frame"))
                if reference and tool.picture and python_has("numpy", "PIL"):
                    tool.notes[m] = f"PSNR {psnr(reference, tool.picture):.1f} dB against {what}"
        rows.extend(tools)
    print("| workload | tool | median | best | unit | wrinkle's advantage | picture |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for m, (unit, higher) in UNITS.items():
        ours = None
        for tool in rows:
            if m not in tool.samples:
                continue
            s = tool.samples[m]
            median, best = statistics.median(s), (max(s) if higher else min(s))
            if ours is None:
                ours = median  # the first tool of every workload is wrinkle
            ratio = (ours / median) if higher else (median / ours)
            print(f"| {m} | {tool.name} | {median:.1f} | {best:.1f} | {unit} | {ratio:.2f}x | {tool.notes.get(m, '')} |")


if __name__ == "__main__":
    main()
