"""A render farm on Ray: wrinkle's jobs split into Ray tasks (frames, tiles of frames, or image files) on a
local Ray instance or a cluster, retried where a worker dies, with their outputs written by this process
exactly as the `wrinkle` command writes them. docs/farm.md says how to start a cluster and what scales.

    python -m wrinkle.farm render scenes/animation.toml -o planet.png --frames 0..95 --spp 16
    python -m wrinkle.farm render -o cover.png --width 8192 --height 8192 --tiles 2048
    python -m wrinkle.farm images normalmap heights/ normals/ --strength 4

Ray is an optional extra: `pip install "./crates/wrinkle-py[farm]"` (or `pip install ray`).
"""

from __future__ import annotations

import argparse
import functools
import logging
import os
import sys
import time
from collections import deque
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

import wrinkle

#: How many tasks per worker CPU are kept in flight: enough to hide a task's start, few enough that results
#: (whole frames, image files) do not pile up in memory.
IN_FLIGHT_PER_CPU = 2
#: The extensions the image commands read.
IMAGE_EXTENSIONS = {".png", ".jpg", ".jpeg", ".bmp", ".tga", ".tif", ".tiff", ".exr"}


class FarmError(Exception):
    """A farm job that cannot run or failed: its message is one line."""


def _ray():
    try:
        import ray  # noqa: F401
    except ImportError:
        raise FarmError(
            "wrinkle.farm needs Ray: pip install \"./crates/wrinkle-py[farm]\" (or pip install ray)"
        ) from None
    return ray


def connect(address: Optional[str] = "local", num_cpus: Optional[int] = None, ship: Optional[Path] = None) -> None:
    """Joins Ray unless this process already has: `local` starts an instance here (`num_cpus` workers, all
    cores by default), `auto` joins the cluster `ray start` made on this machine, and HOST:PORT (or
    ray://HOST:PORT) the cluster there. Each task renders on one thread (one task per CPU). `ship` uploads
    that folder to every worker (Ray's working_dir): relative paths then resolve in it there."""
    ray = _ray()
    if ray.is_initialized():
        return
    # A failed job cancels its other tasks; their errors are not news.
    os.environ.setdefault("RAY_IGNORE_UNHANDLED_ERRORS", "1")
    # One task a CPU, each rendering on one thread: Ray places the tasks, and a node's cores are not
    # oversubscribed by every task's thread pool.
    runtime_env = {"env_vars": {"RAYON_NUM_THREADS": "1"}}
    if ship is not None:
        runtime_env["working_dir"] = str(ship)
    kwargs = dict(runtime_env=runtime_env, include_dashboard=False, log_to_driver=False, logging_level=logging.ERROR)
    if address in (None, "local"):
        ray.init(num_cpus=num_cpus, **kwargs)
    else:
        ray.init(address=address, **kwargs)


def parse_frames(text: str) -> Tuple[int, int, bool]:
    """`N` (frames 0 to N - 1) or `A..B` (A to B, both included), as `wrinkle render --frames` reads them:
    (first, last, whether outputs are numbered)."""
    try:
        if ".." in text:
            a, b = text.split("..", 1)
            first, last, numbered = int(a), int(b), True
        else:
            n = int(text)
            if n < 1:
                raise FarmError("--frames must be at least 1 frame")
            first, last, numbered = 0, n - 1, n > 1
    except ValueError:
        raise FarmError(f"--frames: expected N or A..B (whole numbers), got {text!r}") from None
    if first < 0 or first > last:
        raise FarmError(f"--frames: the range must not run backwards, got {text}")
    return first, last, numbered


def numbered(out: Path, frame: int) -> Path:
    """`out.png` -> `out_0007.png`, as `wrinkle render` numbers frames."""
    return out.with_name(f"{out.stem}_{frame:04d}{out.suffix}")


def tiles_of(width: int, height: int, size: Optional[int]) -> List[Optional[Tuple[int, int, int, int]]]:
    """The crops (x0, y0, x1, y1) of a frame in `size` x `size` tiles, row by row; [None]: the whole frame."""
    if size is None:
        return [None]
    if size < 16:
        raise FarmError(f"--tiles must be at least 16 pixels, got {size}")
    return [
        (x, y, min(x + size, width), min(y + size, height))
        for y in range(0, height, size)
        for x in range(0, width, size)
    ]


class _Bar:
    """Progress over all tasks: tqdm where it is installed, else a line every few seconds on stderr."""

    def __init__(self, total: int, unit: str, show: bool) -> None:
        self.total, self.done, self.unit, self.show = total, 0, unit, show
        self.start = self.last = time.monotonic()
        self.bar = None
        if show:
            try:
                from tqdm import tqdm

                self.bar = tqdm(total=total, unit=unit, file=sys.stderr)
            except ImportError:
                pass

    def step(self) -> None:
        self.done += 1
        if self.bar is not None:
            self.bar.update(1)
        elif self.show and (time.monotonic() - self.last > 5.0 or self.done == self.total):
            self.last = time.monotonic()
            elapsed = self.last - self.start
            left = elapsed / self.done * (self.total - self.done)
            print(f"farm: {self.done}/{self.total} {self.unit} ({elapsed:.0f} s, about {left:.0f} s left)", file=sys.stderr)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


# ------------------------------------------------------------------------------------------------
# What runs on the workers.

_scenes: Dict[Tuple[str, float], "wrinkle.Scene"] = {}


def _scene(path: Optional[str]) -> "wrinkle.Scene":
    """The scene file (the embedded scene for None), loaded once per worker process while it is unchanged."""
    if path is None:
        key = ("", 0.0)
    else:
        key = (os.path.abspath(path), os.path.getmtime(path))
    if key not in _scenes:
        _scenes.clear()
        _scenes[key] = wrinkle.Scene.default() if path is None else wrinkle.Scene.load(path)
    return _scenes[key]


def _as_farm_errors(task):
    """A task whose failures reach the driver as FarmError with the one-line message (the extension's own
    exception types do not travel between processes)."""

    @functools.wraps(task)
    def run(*args, **kwargs):
        try:
            return task(*args, **kwargs)
        except wrinkle.CommandError as e:
            raise FarmError(e.args[0]) from None
        except (ValueError, OSError, RuntimeError) as e:
            raise FarmError(str(e)) from None

    return run


@_as_farm_errors
def render_part(scene: Optional[str], time_s: Optional[float], options: dict, crop) -> dict:
    """One frame (at `time_s` of the scene's animation) or one crop of it, as `Scene.render` returns it."""
    s = _scene(scene)
    if time_s is not None:
        s = s.at(time_s)
    return s.render(crop=crop, **options)


@_as_farm_errors
def run_image_command(command: str, name: str, data: bytes, out_name: str, options: Sequence[str]) -> Dict[str, bytes]:
    """`wrinkle COMMAND NAME -o OUT_NAME OPTIONS...` on a private folder of this worker; returns every file it
    wrote, by name."""
    import tempfile

    with tempfile.TemporaryDirectory(prefix="wrinkle-farm-") as folder:
        src, out = Path(folder) / "in" / name, Path(folder) / "out" / out_name
        src.parent.mkdir()
        out.parent.mkdir()
        src.write_bytes(data)
        wrinkle.run_command(command, src, "-o", out, *options)
        return {p.name: p.read_bytes() for p in sorted(out.parent.iterdir()) if p.is_file()}


# ------------------------------------------------------------------------------------------------
# The jobs.


def _remote(ray, function, retries: int):
    # Retried where a worker dies (or its node); an error of the job itself (a bad scene) is not retried.
    return ray.remote(function).options(max_retries=retries, retry_exceptions=False)


def _run(ray, submit, jobs: list, on_result, bar: _Bar) -> None:
    """Submits `jobs` through `submit` with a bounded number in flight and hands each result to
    `on_result(job, result)` as it comes, in whatever order tasks finish; the first task that fails cancels
    the rest and raises FarmError with its message."""
    window = max(1, int(ray.cluster_resources().get("CPU", 1)) * IN_FLIGHT_PER_CPU)
    queue, running = deque(jobs), {}
    try:
        while queue or running:
            while queue and len(running) < window:
                job = queue.popleft()
                running[submit(job)] = job
            ready, _ = ray.wait(list(running), num_returns=1)
            for ref in ready:
                job = running.pop(ref)
                try:
                    result = ray.get(ref)
                except ray.exceptions.RayTaskError as e:
                    cause = getattr(e, "cause", None)
                    message = str(cause) if isinstance(cause, FarmError) else str(e).strip().splitlines()[-1]
                    raise FarmError(message) from None
                except ray.exceptions.RayError as e:
                    # Workers (or nodes) lost more often than the retries allow.
                    raise FarmError(f"{type(e).__name__} on {job!r}: {str(e).strip().splitlines()[0]}") from None
                on_result(job, result)
                bar.step()
    finally:
        # Not force=True: killing a worker while its task completes or is retried aborted Ray's own driver
        # (task_manager.cc, "Tried to complete task that was not pending"). Queued tasks are dropped; a
        # running one ends with its current frame or tile, and its result is not read.
        for ref in running:
            ray.cancel(ref)
        bar.close()


def render(
    output: Path,
    scene: Optional[Path] = None,
    frames: str = "1",
    fps: float = 24.0,
    tiles: Optional[int] = None,
    turntable: bool = False,
    retries: int = 3,
    progress: bool = True,
    worker_scene: Optional[str] = None,
    **options,
) -> List[Path]:
    """Renders frames of a scene (the embedded one where `scene` is None) on Ray, each frame whole or in
    `tiles` x `tiles` crops, and writes them as `wrinkle render -o OUTPUT --frames FRAMES` does: one file per
    frame (numbered for a range or several frames) with its AOVs. `options` are `Scene.render`'s (width,
    height, spp, sampler, pixel_filter, texel_location, shading_rate, aov, bump, bump_filter, transparent, transparency). Each frame is
    written once, when all its parts are in. The workers read the scene at its absolute path (shared
    storage), or at `worker_scene` (a path in the folder `connect(ship=...)` uploaded). Returns the files'
    paths in frame order."""
    ray = _ray()
    first, last, is_numbered = parse_frames(frames)
    if not (fps > 0 and np.isfinite(fps)):
        raise FarmError(f"--fps must be above 0, got {fps}")
    output = Path(output)
    if output.suffix.lower() not in (".png", ".exr"):
        raise FarmError(f"{output}: output must end in .png or .exr")
    options = dict(options)
    width, height = options.setdefault("width", 1280), options.setdefault("height", 720)
    # The scene is checked here first, so a bad one fails before any task starts.
    local = wrinkle.Scene.default() if scene is None else wrinkle.Scene.load(scene)
    animated = local.animation_end is not None
    if last > first and not animated and not turntable:
        raise FarmError("--frames: the scene has no [[animation]] tracks, so every frame would be the same (add --turntable)")
    count = last - first + 1
    crops = tiles_of(width, height, tiles)
    scene_arg = worker_scene or (None if scene is None else os.path.abspath(scene))
    task = _remote(ray, render_part, retries)

    def job_options(f: int) -> dict:
        return dict(options, turntable=360.0 * (f - first) / count if turntable else 0.0)

    jobs = [(f, crop) for f in range(first, last + 1) for crop in crops]
    parts: Dict[int, dict] = {}
    left = {f: len(crops) for f in range(first, last + 1)}
    written: Dict[int, Path] = {}

    def submit(job):
        f, crop = job
        return task.remote(scene_arg, f / fps if animated else None, job_options(f), crop)

    def on_result(job, arrays: dict):
        f, crop = job
        if crop is None:
            whole = arrays
        else:
            x0, y0, x1, y1 = crop
            whole = parts.setdefault(
                f, {k: np.empty((height, width) + a.shape[2:], a.dtype) for k, a in arrays.items()}
            )
            for k, a in arrays.items():
                whole[k][y0:y1, x0:x1] = a
        left[f] -= 1
        if left[f] == 0:
            path = numbered(output, f) if is_numbered else output
            wrinkle.write_frame(path, whole)
            written[f] = path
            parts.pop(f, None)

    _run(ray, submit, jobs, on_result, _Bar(len(jobs), "parts" if tiles else "frames", progress))
    return [written[f] for f in sorted(written)]


def images(
    command: str,
    in_dir: Path,
    out_dir: Path,
    options: Sequence[str] = (),
    retries: int = 3,
    progress: bool = True,
) -> List[Path]:
    """Runs `wrinkle COMMAND IN -o OUT OPTIONS...` on every image of `in_dir` (normalmap, emboss,
    heightmap, mipmap), one Ray task per file: the file goes to the worker, the outputs come back and are
    written into `out_dir` under the input's name as PNG, each once. Returns the written paths."""
    ray = _ray()
    if command not in ("normalmap", "emboss", "heightmap", "mipmap"):
        raise FarmError(f"images: expected normalmap, emboss, heightmap or mipmap, got {command!r}")
    in_dir, out_dir = Path(in_dir), Path(out_dir)
    if not in_dir.is_dir():
        raise FarmError(f"{in_dir}: not a folder")
    files = sorted(p for p in in_dir.iterdir() if p.is_file() and p.suffix.lower() in IMAGE_EXTENSIONS)
    if not files:
        raise FarmError(f"{in_dir}: no images ({', '.join(sorted(IMAGE_EXTENSIONS))})")
    out_dir.mkdir(parents=True, exist_ok=True)
    options = [str(o) for o in options]
    task = _remote(ray, run_image_command, retries)
    written: List[Path] = []

    def submit(path: Path):
        return task.remote(command, path.name, path.read_bytes(), path.stem + ".png", options)

    def on_result(path: Path, outputs: Dict[str, bytes]):
        for name, data in outputs.items():
            target = out_dir / name
            tmp = out_dir / f".{name}.{os.getpid()}.farm.tmp"
            tmp.write_bytes(data)
            os.replace(tmp, target)
            written.append(target)

    _run(ray, submit, files, on_result, _Bar(len(files), "files", progress))
    return sorted(written)


# ------------------------------------------------------------------------------------------------
# The command line.


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m wrinkle.farm", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="job", required=True)
    farm = argparse.ArgumentParser(add_help=False)
    farm.add_argument("--address", default="local", help="local (start Ray here, the default), auto (the cluster `ray start` made on this machine) or HOST:PORT")
    farm.add_argument("--cpus", type=int, help="worker processes of a local instance (default: all cores)")
    farm.add_argument("--retries", type=int, default=3, help="times a task is run again when its worker dies (default 3)")
    farm.add_argument("--quiet", action="store_true", help="no progress")

    r = sub.add_parser("render", parents=[farm], help="render frames (or tiles of frames) of a scene, as `wrinkle render`")
    r.add_argument("scene", nargs="?", type=Path, help="scene file (TOML); the embedded cover scene when omitted")
    r.add_argument("-o", "--output", type=Path, default=Path("wrinkle.png"), help=".png or .exr")
    r.add_argument("--frames", default="1", help="N (frames 0 to N - 1) or A..B (A to B, both included)")
    r.add_argument("--fps", type=float, default=24.0)
    r.add_argument("--tiles", type=int, metavar="N", help="render each frame in N x N tiles, one task each")
    r.add_argument("--ship", action="store_true", help="upload the scene's folder to the workers (no shared storage)")
    # The options of `wrinkle render` (its --help says more).
    r.add_argument("--width", type=int, default=1280)
    r.add_argument("--height", type=int, default=720)
    r.add_argument("--spp", type=int, default=1, help="samples per pixel, 1 to 4096")
    r.add_argument("--sampler", default="stratified", choices=["stratified", "sobol"])
    r.add_argument("--pixel-filter", default="box", help="box, tent, gaussian, mitchell or lanczos, or NAME:RADIUS")
    r.add_argument("--texel-location", default="centre", choices=["centre", "centroid", "diagonals"])
    r.add_argument("--shading-rate", default="sample", choices=["sample", "pixel"])
    r.add_argument("--turntable", action="store_true", help="one full turn of the objects over the frames")
    r.add_argument("--aov", default="", help="comma-separated: normal, uv, depth, id, primitive")
    r.add_argument("--background", default="scene", choices=["scene", "transparent"])
    r.add_argument("--no-bump", action="store_true", help="render without bump mapping")
    r.add_argument("--bump-filter", help="filter every bump function: none, mip, a texture filter, lean, toksvig, lean:FILTER or toksvig:FILTER")
    r.add_argument("--transparency", default="sorted", choices=["sorted", "exact"])

    i = sub.add_parser(
        "images", parents=[farm], help="run an image command on every image of a folder",
        description="Runs `wrinkle COMMAND IMAGE -o OUT_DIR/<name>.png OPTIONS` on every image of IN_DIR, one Ray "
        "task per file. Every option not listed here is the command's own (`wrinkle COMMAND --help`), for example "
        "--strength 4 --depth 16 for normalmap.",
    )
    i.add_argument("command", choices=["normalmap", "emboss", "heightmap", "mipmap"])
    i.add_argument("in_dir", type=Path)
    i.add_argument("out_dir", type=Path)
    return p


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = _parser()
    args, rest = parser.parse_known_args(argv)
    try:
        if args.job == "render":
            if rest:
                parser.error(f"unknown options: {' '.join(rest)}")
            ship = args.scene.resolve().parent if args.ship and args.scene is not None else None
            connect(args.address, args.cpus, ship)
            render(
                args.output.resolve(), args.scene, frames=args.frames, fps=args.fps, tiles=args.tiles,
                worker_scene=args.scene.name if ship is not None else None,
                turntable=args.turntable, retries=args.retries, progress=not args.quiet,
                width=args.width, height=args.height, spp=args.spp, sampler=args.sampler,
                pixel_filter=args.pixel_filter, texel_location=args.texel_location, shading_rate=args.shading_rate,
                aov=tuple(a for a in args.aov.split(",") if a),
                bump=not args.no_bump, bump_filter=args.bump_filter,
                transparent=args.background == "transparent", transparency=args.transparency,
            )
        else:
            # Every other option is the image command's own (`wrinkle normalmap --help` lists them).
            connect(args.address, args.cpus)
            images(args.command, args.in_dir, args.out_dir, rest, retries=args.retries, progress=not args.quiet)
    except (FarmError, wrinkle.CommandError, ValueError, OSError) as e:
        message = e.args[0] if isinstance(e, wrinkle.CommandError) else str(e)
        print(f"error: {message}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    # The tasks must be this package's functions (importable on every worker), not __main__'s copies.
    from wrinkle.farm import main as _main

    sys.exit(_main())
