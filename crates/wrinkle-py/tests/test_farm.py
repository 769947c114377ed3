"""The farm on a local Ray instance (two workers on loopback): its outputs are the `wrinkle` command's, byte
for byte, whole frames, tiles and image files alike, and a worker killed mid-job costs nothing: every frame
is still written, once."""

import os
import signal
import sys
import threading
import time
from pathlib import Path

import pytest

import wrinkle

ray = pytest.importorskip("ray")
from wrinkle import farm  # noqa: E402


@pytest.fixture(scope="module", autouse=True)
def local_ray():
    farm.connect("local", num_cpus=2)
    yield
    ray.shutdown()


def files(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_an_animation_is_the_clis_frames(cli, tmp_path, repo):
    scene = repo / "scenes" / "animation.toml"
    size = dict(width=96, height=64, spp=4, sampler="sobol", pixel_filter="gaussian")
    (tmp_path / "farm").mkdir()
    (tmp_path / "cli").mkdir()
    written = farm.render(tmp_path / "farm" / "a.png", scene, frames="5..8", fps=12, progress=False, **size)
    assert [p.name for p in written] == ["a_0005.png", "a_0006.png", "a_0007.png", "a_0008.png"]
    cli("render", scene, "-o", tmp_path / "cli" / "a.png", "--frames", "5..8", "--fps", 12, "--width", 96,
        "--height", 64, "--spp", 4, "--sampler", "sobol", "--pixel-filter", "gaussian")
    ours, theirs = files(tmp_path / "farm"), files(tmp_path / "cli")
    assert list(ours) == list(theirs)
    assert ours == theirs, "the farm's frames differ from the CLI's"
    assert len(set(ours.values())) == 4, "the frames do not move"


def test_a_frame_in_tiles_is_the_clis_whole_frame(cli, tmp_path):
    (tmp_path / "farm").mkdir()
    (tmp_path / "cli").mkdir()
    farm.render(tmp_path / "farm" / "t.exr", None, tiles=64, width=150, height=100, spp=4, aov=("depth", "primitive"),
                progress=False)
    cli("render", "-o", tmp_path / "cli" / "t.exr", "--width", 150, "--height", 100, "--spp", 4, "--aov", "depth,primitive")
    ours, theirs = files(tmp_path / "farm"), files(tmp_path / "cli")
    assert list(ours) == ["t.depth.exr", "t.exr", "t.primitive.exr"] == list(theirs)
    assert ours == theirs
    # A transparent PNG assembled from 4 tiles (2 x 2, the last ones narrower).
    farm.render(tmp_path / "farm" / "c.png", None, tiles=64, width=100, height=90, transparent=True, progress=False)
    cli("render", "-o", tmp_path / "cli" / "c.png", "--width", 100, "--height", 90, "--background", "transparent")
    assert (tmp_path / "farm" / "c.png").read_bytes() == (tmp_path / "cli" / "c.png").read_bytes()


def _kill_one_render_task(killed: list, stop: threading.Event) -> None:
    """Kills (SIGKILL) the first worker process seen running a render task: Ray names such a process
    `ray::render_part` while the task runs."""
    while not stop.is_set() and not killed:
        for pid in os.listdir("/proc"):
            if not pid.isdigit():
                continue
            try:
                cmdline = Path(f"/proc/{pid}/cmdline").read_bytes()
            except OSError:
                continue
            if cmdline.startswith(b"ray::render_part"):
                os.kill(int(pid), signal.SIGKILL)
                killed.append(int(pid))
                return
        time.sleep(0.01)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="finds the worker through /proc")
def test_a_worker_killed_mid_job_loses_no_frame(cli, tmp_path, repo):
    scene = repo / "scenes" / "animation.toml"
    (tmp_path / "farm").mkdir()
    (tmp_path / "cli").mkdir()
    # Frames of a few hundred milliseconds each, so the killer finds one running.
    size = ["--width", 480, "--height", 320, "--spp", 32]
    killed: list = []
    stop = threading.Event()
    killer = threading.Thread(target=_kill_one_render_task, args=(killed, stop))
    killer.start()
    try:
        written = farm.render(tmp_path / "farm" / "k.png", scene, frames="0..5", width=480, height=320, spp=32,
                              progress=False)
    finally:
        stop.set()
        killer.join()
    assert killed, "no render task was seen running to kill"
    assert [p.name for p in written] == [f"k_{f:04d}.png" for f in range(6)]
    cli("render", scene, "-o", tmp_path / "cli" / "k.png", "--frames", "0..5", *size)
    ours, theirs = files(tmp_path / "farm"), files(tmp_path / "cli")
    assert list(ours) == list(theirs), "frames missing, doubled or left half-written"
    assert ours == theirs


def test_images_are_the_commands_outputs(cli, tmp_path):
    heights, normals = tmp_path / "heights", tmp_path / "normals"
    heights.mkdir()
    for k, kind in enumerate(["bricks", "rivets", "grid"]):
        cli("bumpgen", kind, "-o", heights / f"{kind}.png", "--size", 64 * (k + 1))
    (heights / "notes.txt").write_text("not an image")
    written = farm.images("normalmap", heights, normals, ["--strength", 4, "--depth", 16], progress=False)
    assert [p.name for p in written] == ["bricks.png", "grid.png", "rivets.png"]
    for p in written:
        cli("normalmap", heights / p.name, "-o", tmp_path / p.name, "--strength", 4, "--depth", 16)
        assert p.read_bytes() == (tmp_path / p.name).read_bytes(), p.name
    assert sorted(os.listdir(normals)) == ["bricks.png", "grid.png", "rivets.png"], "temporaries left behind"
    with pytest.raises(farm.FarmError, match="--strength"):
        farm.images("normalmap", heights, normals, ["--strength", "x"], progress=False)


def test_bad_jobs_fail_with_one_line(tmp_path, repo):
    with pytest.raises(farm.FarmError, match="no \\[\\[animation\\]\\] tracks"):
        farm.render(tmp_path / "x.png", None, frames="3", progress=False)
    with pytest.raises(farm.FarmError, match="backwards"):
        farm.render(tmp_path / "x.png", None, frames="5..2", progress=False)
    with pytest.raises(farm.FarmError, match="must end in"):
        farm.render(tmp_path / "x.jpg", None, progress=False)
    with pytest.raises(farm.FarmError, match="not a folder"):
        farm.images("emboss", tmp_path / "missing", tmp_path / "out", progress=False)
    bad = tmp_path / "bad.toml"
    bad.write_text((repo / "scenes" / "animation.toml").read_text().replace(
        'target = "objects[0].material.texture.time"', 'target = "objects[0].radius"'))
    # A radius from 1 at 0 s to -1 at 4 s: fine at first, refused on a worker from 2 s, named with its time.
    bad.write_text(bad.read_text().replace(
        "{ time = 0.0, value = 0.0 }, { time = 4.0, value = 1.2 }", "{ time = 0.0, value = 1.0 }, { time = 4.0, value = -1.0 }"))
    with pytest.raises(farm.FarmError, match="radius.*at time"):
        farm.render(tmp_path / "y.png", bad, frames="0..95", width=32, height=24, progress=False)


def test_without_ray_the_farm_says_how_to_get_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)
    with pytest.raises(farm.FarmError, match=r"pip install"):
        farm._ray()


def test_the_command_line(cli, tmp_path, capsys):
    out = tmp_path / "m.png"
    args = ["--width", "64", "--height", "48", "--bump-filter", "mip"]
    assert farm.main(["render", "-o", str(out), "--tiles", "32", "--quiet", *args]) == 0
    cli("render", "-o", tmp_path / "c.png", *args)
    assert out.read_bytes() == (tmp_path / "c.png").read_bytes()
    assert farm.main(["render", "-o", str(out), "--frames", "2", "--quiet"]) == 2
    assert "add --turntable" in capsys.readouterr().err
