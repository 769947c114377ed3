"""Scenes and rendering: the same frame as the CLI, AOVs, errors, progress, interrupts, the GIL."""

import _thread
import threading
import time

import numpy as np
import pytest

import wrinkle

SPHERE = """
[camera]
eye = [0.0, 0.0, 4.0]
look_at = [0.0, 0.0, 0.0]
fov_y = 40.0
background = [0.0, 0.0, 0.0]

[[light]]
type = "directional"
direction = [0.0, 0.0, -1.0]

[[object]]
shape = "sphere"
radius = 1.0
[object.material]
color = [0.8, 0.8, 0.8]
specular = 0.0
"""


def test_default_scene_matches_the_cli_bit_for_bit(cli, tmp_path):
    out = tmp_path / "cover.png"
    cli("render", "-o", out, "--width", 192, "--height", 108, "--spp", 4, "--aov", "depth,normal")
    frame = wrinkle.Scene.default().render(192, 108, spp=4, aov=("depth", "normal"))
    png = np.rint(wrinkle.read_image(out)[..., :3] * 255).astype(np.uint8)
    assert np.array_equal(wrinkle.to_srgb8(frame["color"]), png)
    depth = wrinkle.read_exr(tmp_path / "cover.depth.exr")["Z"]
    assert np.array_equal(np.isnan(depth), np.isnan(frame["depth"]))
    assert np.array_equal(depth[~np.isnan(depth)], frame["depth"][~np.isnan(depth)])
    normal = wrinkle.read_exr(tmp_path / "cover.normal.exr")
    seen = ~np.isnan(frame["normal"][..., 0])
    assert np.array_equal(normal["X"][seen], frame["normal"][..., 0][seen])


def test_sampler_and_pixel_filter_match_the_cli(cli, tmp_path):
    out = tmp_path / "filtered.exr"
    cli("render", "-o", out, "--width", 96, "--height", 64, "--spp", 6, "--sampler", "sobol", "--pixel-filter", "gaussian")
    scene = wrinkle.Scene.default()
    frame = scene.render(96, 64, spp=6, sampler="sobol", pixel_filter="gaussian")
    assert np.array_equal(wrinkle.read_exr(out)["R"], frame["color"][..., 0])
    # Not what the box over the same samples gives: the filter was used, not ignored.
    boxed = scene.render(96, 64, spp=6, sampler="sobol")
    assert np.abs(boxed["color"] - frame["color"]).max() > 0.05


def test_texel_location_and_lean_match_the_cli(cli, tmp_path, repo):
    floor = repo / "scenes" / "checker_floor.toml"
    out = tmp_path / "floor.exr"
    cli("render", floor, "-o", out, "--width", 96, "--height", 64, "--texel-location", "centroid",
        "--bump-filter", "lean", "--aov", "uv")
    scene = wrinkle.Scene.load(floor)
    frame = scene.render(96, 64, aov="uv", texel_location="centroid", bump_filter="lean")
    assert np.array_equal(wrinkle.read_exr(out)["R"], frame["color"][..., 0])
    uv = wrinkle.read_exr(tmp_path / "floor.uv.exr")
    seen = ~np.isnan(frame["uv"][..., 0])
    assert np.array_equal(uv["U"][seen], frame["uv"][..., 0][seen])
    # The centroid of the projected corners is not the centre's (u,v): the option was used, not ignored.
    centre = scene.render(96, 64, aov="uv")["uv"]
    assert np.nanmax(np.abs(centre - frame["uv"])) > 1e-3
    with pytest.raises(ValueError, match="texel_location"):
        scene.render(32, 32, texel_location="middle")


def test_shading_once_per_pixel_matches_the_cli(cli, tmp_path, repo):
    canonical = repo / "bench" / "canonical" / "sphere.toml"
    out = tmp_path / "sphere.exr"
    cli("render", canonical, "-o", out, "--width", 96, "--height", 64, "--spp", 16, "--shading-rate", "pixel")
    scene = wrinkle.Scene.load(canonical)
    frame = scene.render(96, 64, spp=16, shading_rate="pixel")
    assert np.array_equal(wrinkle.read_exr(out)["R"], frame["color"][..., 0])
    # Shading every sample averages the bricks inside each pixel: the option was used, not ignored.
    every = scene.render(96, 64, spp=16)
    assert np.abs(every["color"] - frame["color"]).max() > 0.01
    with pytest.raises(ValueError, match="shading_rate"):
        scene.render(32, 32, shading_rate="quad")


def test_an_animated_scene_at_a_time_is_the_clis_frame(cli, tmp_path, repo):
    scene = wrinkle.Scene.load(repo / "scenes" / "animation.toml")
    assert scene.animation_end == 4.0
    cli("render", repo / "scenes" / "animation.toml", "-o", tmp_path / "a.exr", "--frames", "36..36", "--fps", 24,
        "--width", 64, "--height", 48)
    frame = scene.at(1.5).render(64, 48)
    assert np.array_equal(wrinkle.read_exr(tmp_path / "a_0036.exr")["R"], frame["color"][..., 0])
    assert not np.array_equal(scene.render(64, 48)["color"], frame["color"])
    with pytest.raises(ValueError, match="animation"):
        wrinkle.Scene.default().at(1.0)
    assert wrinkle.Scene.default().animation_end is None


def test_shapes_dtypes_and_aovs_of_an_analytic_sphere():
    scene = wrinkle.Scene.from_toml(SPHERE)
    f = scene.render(64, 48, aov=("normal", "uv", "depth", "id", "primitive", "alpha"))
    assert f["color"].shape == (48, 64, 3) and f["color"].dtype == np.float32
    assert f["normal"].shape == (48, 64, 3) and f["uv"].shape == (48, 64, 2)
    assert f["depth"].shape == (48, 64) and f["id"].shape == (48, 64) and f["alpha"].shape == (48, 64)
    assert f["primitive"].shape == (48, 64, 2) and f["primitive"].dtype == np.uint32
    # The sphere's nearest point is 3 units from the eye, seen at the centre; corners see nothing.
    centre = f["depth"][23:25, 31:33]
    assert np.all(np.abs(centre - 3.0) < 0.01), centre
    assert np.isnan(f["depth"][0, 0]) and f["alpha"][0, 0] == 0.0
    assert f["primitive"][0, 0, 0] == 2**32 - 1
    # Lambert under a light along the view: the centre's shade is the albedo, N faces the eye.
    assert np.allclose(f["color"][24, 32], 0.8, atol=0.02)
    assert np.allclose(f["normal"][24, 32], [0, 0, 1], atol=0.05)
    assert np.all(f["id"][24, 32] == 0)


def test_from_dict_equals_the_same_scene_as_text():
    tables = {
        "camera": {"eye": [0.0, 0.0, 4.0], "look_at": [0.0, 0.0, 0.0], "fov_y": 40.0, "background": [0.0, 0.0, 0.0]},
        "light": [{"type": "directional", "direction": [0.0, 0.0, -1.0]}],
        "object": [
            {"shape": "sphere", "radius": 1.0, "material": {"color": [0.8, 0.8, 0.8], "specular": 0.0}}
        ],
    }
    a = wrinkle.Scene.from_dict(tables).render(40, 30)["color"]
    b = wrinkle.Scene.from_toml(SPHERE).render(40, 30)["color"]
    assert np.array_equal(a, b)


def test_a_scene_file_by_path(repo):
    scene = wrinkle.Scene.from_toml(repo / "scenes" / "grid_patch.toml")
    assert scene.objects >= 1
    assert scene.render(32, 24)["color"].shape == (24, 32, 3)


def test_errors_become_python_exceptions(tmp_path):
    with pytest.raises(wrinkle.SceneError, match="radius"):
        wrinkle.Scene.from_toml(SPHERE.replace("radius = 1.0", "radius = -1.0"))
    with pytest.raises(wrinkle.SceneError):
        wrinkle.Scene.from_dict({"camera": {"eye": "here"}})
    with pytest.raises(TypeError, match="object"):
        wrinkle.Scene.from_dict({"camera": {"eye": object()}})
    with pytest.raises(FileNotFoundError):
        wrinkle.Scene.load(tmp_path / "missing.toml")
    loop = {}
    loop["camera"] = loop
    with pytest.raises(ValueError, match="nested"):
        wrinkle.Scene.from_dict(loop)
    scene = wrinkle.Scene.from_toml(SPHERE)
    with pytest.raises(ValueError, match="spp"):
        scene.render(16, 16, spp=0)
    with pytest.raises(ValueError, match="pixel_filter"):
        scene.render(16, 16, pixel_filter="sinc")
    with pytest.raises(ValueError, match="sampler"):
        scene.render(16, 16, sampler="halton")
    with pytest.raises(ValueError, match="width"):
        scene.render(0, 16)
    with pytest.raises(ValueError, match="width"):
        scene.render(10**7, 16)
    with pytest.raises(ValueError, match="aovs"):
        scene.render(16, 16, aov=("colour",))
    with pytest.raises(ValueError, match="transparency"):
        scene.render(16, 16, transparency="random")
    assert issubclass(wrinkle.SceneError, ValueError)


def test_progress_reaches_the_total():
    seen = []
    wrinkle.Scene.default().render(256, 256, progress=lambda done, total: seen.append((done, total)))
    assert seen, "the callback was never called"
    assert all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    assert seen[-1][0] == seen[-1][1]
    wrinkle.Scene.default().render(64, 64, progress=True)


def test_an_exception_in_the_callback_stops_the_render():
    def fail(done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        wrinkle.Scene.default().render(1024, 1024, spp=16, progress=fail)


def test_ctrl_c_interrupts_a_long_render_promptly():
    scene = wrinkle.Scene.default()
    start = time.perf_counter()
    scene.render(512, 512, spp=16)
    small = time.perf_counter() - start
    # The same render at 16x the pixels takes about 16x as long; Ctrl-C arrives a moment after it starts.
    threading.Timer(0.2, _thread.interrupt_main).start()
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        scene.render(2048, 2048, spp=16)
    assert time.perf_counter() - start < 0.2 + max(1.0, 4 * small)


def test_the_gil_is_released_while_rendering():
    scene = wrinkle.Scene.default()
    span = {}

    def work():
        start = time.perf_counter()
        scene.render(2048, 2048, spp=4)
        span["render"] = (start, time.perf_counter())

    worker = threading.Thread(target=work)
    worker.start()
    ticks = []
    while worker.is_alive():
        ticks.append(time.perf_counter())
    worker.join()
    start, end = span["render"]
    during = [t for t in ticks if start <= t <= end]
    gaps = np.diff([start, *during, end])
    # Held for the whole call, the GIL would stop this thread for the whole render; released, this
    # thread runs all along (gaps of a switch interval or a progress look at most).
    assert end - start > 0.05
    assert gaps.max() < 0.5 * (end - start), (gaps.max(), end - start)


@pytest.mark.parametrize(
    "name", ["default", "shadows.toml", "panes.toml", "fractal_egg.toml", "environment_chrome.toml", "reflect_views.toml"]
)
def test_crops_are_the_whole_frames_pixels(name, repo):
    scene = wrinkle.Scene.default() if name == "default" else wrinkle.Scene.load(repo / "scenes" / name)
    aov = ("depth", "alpha", "normal")
    whole = scene.render(160, 100, spp=4, aov=aov)
    for x0, y0, x1, y1 in [(0, 0, 160, 100), (13, 7, 77, 93), (64, 0, 128, 64), (100, 50, 160, 100), (5, 90, 6, 91)]:
        part = scene.render(160, 100, spp=4, aov=aov, crop=(x0, y0, x1, y1))
        for key in ("color", *aov):
            assert part[key].shape[:2] == (y1 - y0, x1 - x0)
            assert np.array_equal(part[key], whole[key][y0:y1, x0:x1], equal_nan=True), (name, key, (x0, y0, x1, y1))


def test_a_frame_too_large_to_hold_renders_in_parts():
    scene = wrinkle.Scene.default()
    with pytest.raises(ValueError, match="in parts"):
        scene.render(40000, 40000)
    part = scene.render(40000, 40000, crop=(20000, 20000, 20064, 20032))
    assert part["color"].shape == (32, 64, 3)
    with pytest.raises(ValueError, match="crop"):
        scene.render(100, 100, crop=(0, 0, 101, 50))
