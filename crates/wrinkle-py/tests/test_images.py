"""Emboss, normal maps, heights from normals and bump tables: against the CLI and analytic results."""

import numpy as np
import pytest

import wrinkle


def grey16(path):
    return wrinkle.read_image(path)[..., 0]


def test_bump_tables_match_the_cli(cli, tmp_path):
    for kind, args, table in [
        ("grid", ["--size", 64, "--cells", 4, "--line-width", 0.3], wrinkle.bumpgen.grid(64, cells=4, line_width=0.3)),
        ("text", ["--size", 16, "--text", "Hi"], wrinkle.bumpgen.text(16, text="Hi")),
        ("rivets", ["--size", 64, "--count", 4], wrinkle.bumpgen.rivets(64, count=4)),
        ("bricks", ["--size", 64, "--rows", 4], wrinkle.bumpgen.bricks(64, rows=4)),
    ]:
        out = tmp_path / f"{kind}.png"
        cli("bumpgen", kind, "-o", out, *args)
        assert table.dtype == np.float32 and table.ndim == 2
        assert np.array_equal(np.rint(table * 65535), np.rint(grey16(out) * 65535)), kind
    assert wrinkle.bumpgen.text(16, text="Hi").shape == (16, 32)


def test_emboss_matches_the_cli(cli, tmp_path):
    src = tmp_path / "h.png"
    cli("bumpgen", "rivets", "-o", src, "--size", 96, "--count", 3)
    out = tmp_path / "e.png"
    cli("emboss", src, "-o", out, "--azimuth", 30, "--elevation", 40, "--width", 4, "--depth", 16)
    shade = wrinkle.emboss(wrinkle.read_image(src), azimuth=30, elevation=40, width=4)
    assert shade.shape == (96, 96) and shade.dtype == np.float32
    assert np.abs(np.rint(shade * 65535) - np.rint(grey16(out) * 65535)).max() <= 1


def test_emboss_with_a_texture_matches_the_cli(cli, tmp_path):
    src, tex, out = tmp_path / "h.png", tmp_path / "t.png", tmp_path / "e.png"
    cli("bumpgen", "grid", "-o", src, "--size", 64)
    cli("texture", "marble", "-o", tex, "--size", "64x64")
    cli("emboss", src, "-o", out, "--texture", tex)
    colour = np.rint(wrinkle.read_image(tex)[..., :3] * 255).astype(np.uint8)
    mine = wrinkle.emboss(wrinkle.read_image(src), texture=colour)
    assert mine.dtype == np.uint8 and mine.shape == (64, 64, 3)
    theirs = np.rint(wrinkle.read_image(out)[..., :3] * 255).astype(np.int32)
    assert np.abs(mine.astype(np.int32) - theirs).max() <= 1


def test_emboss_of_a_plane_is_lamberts_law():
    # A flat image has N = (0, 0, 1): the shade is sin(elevation) everywhere.
    assert np.allclose(wrinkle.emboss(np.full((8, 8), 0.5, np.float32), elevation=30), 0.5, atol=1e-6)
    # A ramp of one code per pixel rising to the right: Schlag's i_u = 6, N = [-6, 0, 6 * 255 / w].
    ramp = np.tile(np.arange(16, dtype=np.float32) / 255.0, (16, 1))
    n = np.array([-6.0, 0.0, 6 * 255 / 3])
    # Lit from the left (azimuth 180, elevation 0): L = [-1, 0, 0].
    shade = wrinkle.emboss(ramp, azimuth=180, elevation=0, width=3)
    assert np.allclose(shade[1:-1, 1:-1], 6.0 / np.linalg.norm(n), atol=1e-6)
    # Lit from the right it faces away: black.
    assert np.all(wrinkle.emboss(ramp, azimuth=0, elevation=0)[1:-1, 1:-1] == 0)


def test_normal_map_matches_the_cli(cli, tmp_path):
    src, out = tmp_path / "h.png", tmp_path / "n.png"
    cli("bumpgen", "bricks", "-o", src, "--size", 64)
    cli("normalmap", src, "-o", out, "--strength", 5, "--kernel", "scharr", "--depth", 16, "--wrap")
    n = wrinkle.normal_map(wrinkle.read_image(src), strength=5, kernel="scharr", wrap=True)
    assert n.shape == (64, 64, 3) and n.dtype == np.float32
    encoded = np.rint((n + 1) * 32767.5)
    assert np.abs(encoded - np.rint(wrinkle.read_image(out)[..., :3] * 65535)).max() <= 1


def test_normal_map_of_a_ramp_is_analytic():
    slope = 0.01
    h = np.tile(np.arange(32, dtype=np.float32) * slope, (32, 1))
    for kernel in ("central", "sobel", "scharr"):
        n = wrinkle.normal_map(h, strength=10, kernel=kernel)
        expect = np.array([-0.1, 0.0, 1.0]) / np.sqrt(1.01)
        assert np.allclose(n[4:-4, 4:-4], expect, atol=1e-5), kernel
    # Rising down the picture: the OpenGL normal leans up the picture (+y), DirectX's stores -y.
    down = h.T.copy()
    gl = wrinkle.normal_map(down, strength=10)
    assert np.allclose(gl[4:-4, 4:-4], np.array([0.0, 0.1, 1.0]) / np.sqrt(1.01), atol=1e-5)
    dx = wrinkle.normal_map(down, strength=10, convention="directx")
    assert np.allclose(dx[4:-4, 4:-4], np.array([0.0, -0.1, 1.0]) / np.sqrt(1.01), atol=1e-5)
    off = wrinkle.normal_map(h, strength=10, offset=True)
    assert off.shape == (32, 32, 2) and np.allclose(off[4:-4, 4:-4], [0.1, 0.0], atol=1e-5)


def test_heights_come_back_from_their_normals():
    y, x = np.mgrid[0:64, 0:64].astype(np.float32)
    h = (0.25 * (np.sin(2 * np.pi * x / 64) + np.cos(2 * np.pi * 2 * y / 64)) + 0.5).astype(np.float32)
    n = wrinkle.normal_map(h, strength=20, kernel="central", wrap=True)
    back = wrinkle.height_from_normals(n, strength=20, wrap=True)
    assert back.shape == h.shape
    # Up to a constant: both lowest at 0. Central differences of a sampled sine lose a little amplitude.
    assert np.abs(back - (h - h.min())).max() < 0.02
    encoded = np.rint((n + 1) * 127.5).astype(np.uint8)
    assert np.abs(wrinkle.height_from_normals(encoded, strength=20, wrap=True) - back).max() < 0.05


def test_heightmap_matches_the_cli(cli, tmp_path):
    src, normals, out = tmp_path / "h.png", tmp_path / "n.png", tmp_path / "back.png"
    cli("bumpgen", "rivets", "-o", src, "--size", 64)
    cli("normalmap", src, "-o", normals, "--depth", 16)
    cli("heightmap", normals, "-o", out, "--normalize")
    n16 = np.rint(wrinkle.read_image(normals)[..., :3] * 65535).astype(np.uint16)
    mine = wrinkle.height_from_normals(n16, normalize=True)
    assert np.abs(np.rint(mine * 65535) - np.rint(grey16(out) * 65535)).max() <= 1


def test_layouts_do_not_change_results():
    rng = np.random.default_rng(1)
    h = rng.random((40, 50)).astype(np.float32)
    fortran = np.asfortranarray(h)
    strided = np.zeros((80, 100), np.float32)
    strided[::2, ::2] = h
    view = strided[::2, ::2]
    for f in (wrinkle.emboss, wrinkle.normal_map):
        base = f(h)
        assert np.array_equal(f(fortran), base)
        assert np.array_equal(f(view), base)
        assert np.array_equal(f(h.astype(np.float64)), base)
    # 8-bit input is read over its full scale.
    codes = (h * 255).astype(np.uint8)
    assert np.array_equal(wrinkle.emboss(codes), wrinkle.emboss(codes.astype(np.float32) / 255))


def test_bad_inputs_raise_clear_exceptions():
    with pytest.raises(TypeError, match="dtype int64"):
        wrinkle.emboss(np.zeros((4, 4), np.int64))
    with pytest.raises(ValueError, match="NaN"):
        wrinkle.emboss(np.full((4, 4), np.nan, np.float32))
    with pytest.raises(ValueError, match="shape"):
        wrinkle.emboss(np.zeros((4, 4, 4, 4), np.float32))
    with pytest.raises(ValueError, match="empty"):
        wrinkle.normal_map(np.zeros((0, 4), np.float32))
    with pytest.raises(ValueError, match="strength"):
        wrinkle.normal_map(np.zeros((4, 4), np.float32), strength=-1)
    with pytest.raises(ValueError, match="kernel"):
        wrinkle.normal_map(np.zeros((4, 4), np.float32), kernel="prewitt")
    with pytest.raises(ValueError, match="convention"):
        wrinkle.height_from_normals(np.zeros((4, 4, 3), np.float32), convention="metal")
    with pytest.raises(ValueError):
        wrinkle.bumpgen.grid(10**9)
    with pytest.raises(ValueError, match="unknown option"):
        wrinkle._wrinkle.bumpgen("grid", 64, {"cels": 3})
    with pytest.raises(ValueError, match="elevation"):
        wrinkle.emboss(np.zeros((4, 4), np.float32), elevation=120)
    with pytest.raises(FileNotFoundError):
        wrinkle.read_image("/nonexistent/image.png")


def test_written_images_read_back(tmp_path):
    rng = np.random.default_rng(9)
    rgb8 = (rng.random((20, 30, 3)) * 255).astype(np.uint8)
    wrinkle.write_image(tmp_path / "a.png", rgb8)
    assert np.array_equal(np.rint(wrinkle.read_image(tmp_path / "a.png")[..., :3] * 255), rgb8)
    grey16 = (rng.random((20, 30)) * 65535).astype(np.uint16)
    wrinkle.write_image(tmp_path / "g.png", grey16)
    assert np.array_equal(np.rint(wrinkle.read_image(tmp_path / "g.png")[..., 0] * 65535), grey16)
    heights = rng.random((20, 30)).astype(np.float32)
    wrinkle.write_image(tmp_path / "h.png", heights, bits=16)
    assert np.abs(wrinkle.read_image(tmp_path / "h.png")[..., 0] - heights).max() <= 0.5 / 65535 + 1e-7
    rgba = rng.random((20, 30, 4)).astype(np.float32)
    rgba[0, 0, 0] = np.nan
    wrinkle.write_image(tmp_path / "f.exr", rgba)
    back = wrinkle.read_exr(tmp_path / "f.exr")
    assert np.array_equal(np.stack([back[c] for c in "RGBA"], axis=-1), rgba, equal_nan=True)


def test_linear_colour_is_written_as_the_renderer_writes_it(cli, tmp_path):
    cli("render", "-o", tmp_path / "cli.png", "--width", 64, "--height", 36)
    frame = wrinkle.Scene.default().render(64, 36)
    wrinkle.write_image(tmp_path / "py.png", frame["color"])
    assert np.array_equal(wrinkle.read_image(tmp_path / "py.png"), wrinkle.read_image(tmp_path / "cli.png"))


def test_bad_images_are_not_written(tmp_path):
    with pytest.raises(ValueError, match="png or .exr"):
        wrinkle.write_image(tmp_path / "a.jpg", np.zeros((4, 4), np.uint8))
    with pytest.raises(ValueError, match="channels"):
        wrinkle.write_image(tmp_path / "a.png", np.zeros((4, 4, 5), np.uint8))
    with pytest.raises(ValueError, match="bits"):
        wrinkle.write_image(tmp_path / "a.png", np.zeros((4, 4), np.float32), bits=12)
    with pytest.raises(OSError):
        wrinkle.write_image(tmp_path / "missing" / "a.png", np.zeros((4, 4), np.uint8))
    assert not (tmp_path / "a.png").exists()
