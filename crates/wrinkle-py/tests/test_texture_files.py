"""MIP-mapped texture files against OpenImageIO (the PyPI wheel, with its oiiotool and maketx): what
`wrinkle mipmap --format exr|tiff` writes opens there with every level, and a texture maketx makes renders in
wrinkle as the same source loaded flat."""

import sys
import subprocess
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

import wrinkle


def oiio_tool(name: str) -> str:
    """The wheel's command-line tool beside the venv's Python."""
    tool = Path(sys.executable).parent / name
    assert tool.exists(), f"{tool}: the OpenImageIO wheel installs {name}"
    return str(tool)


def mip_levels(path: Path) -> list:
    """Every MIP level of subimage 0 as OpenImageIO reads it: float arrays (H, W, C)."""
    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    levels = []
    while inp.seek_subimage(0, len(levels)):
        levels.append(inp.read_image("float"))
    inp.close()
    return levels


def srgb8(linear: np.ndarray) -> np.ndarray:
    """Linear values to 8-bit sRGB codes (colour channels only)."""
    c = np.clip(linear, 0.0, 1.0)
    encoded = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)
    return np.round(encoded * 255).astype(int)


def test_wrinkles_mip_mapped_files_open_in_openimageio_with_every_level(cli, tmp_path, repo):
    source = repo / "scenes" / "tiles_color.png"
    cli("mipmap", source, "-o", tmp_path / "levels.png", "--levels")
    cli("mipmap", source, "-o", tmp_path / "tiles.exr", "--format", "exr")
    cli("mipmap", source, "-o", tmp_path / "tiles.tif", "--format", "tiff")
    width, height = wrinkle.read_image(source).shape[1::-1]
    count = int(np.log2(max(width, height))) + 1
    pngs = [wrinkle.read_image(tmp_path / f"levels_{k}.png") for k in range(count)]
    # Within a code: the PNG encoder and the TIFF writer round the same floats their own ways.
    for name, tolerance in [("tiles.exr", 1), ("tiles.tif", 1)]:
        levels = mip_levels(tmp_path / name)
        assert len(levels) == count, f"{name}: {len(levels)} levels"
        for k, (level, png) in enumerate(zip(levels, pngs)):
            assert level.shape[:2] == png.shape[:2], f"{name} level {k}"
            rgb = srgb8(level[..., :3]) if name.endswith(".exr") else np.round(level[..., :3] * 255).astype(int)
            want = np.round(png[..., :3] * 255).astype(int)
            assert np.abs(rgb - want).max() <= tolerance, f"{name} level {k}"


def test_a_maketx_texture_renders_as_its_flat_source(cli, tmp_path, repo):
    # Linear float texels and maketx's box filter: the levels maketx builds are the ones wrinkle would.
    flat = tmp_path / "flat.exr"
    subprocess.run([oiio_tool("oiiotool"), str(repo / "scenes" / "tiles_color.png"), "--colorconvert", "sRGB",
                    "linear", "-d", "float", "-o", str(flat)], check=True)
    tx = tmp_path / "tiles.tx"
    subprocess.run([oiio_tool("maketx"), str(flat), "-d", "float", "--filter", "box", "-o", str(tx)], check=True)
    assert len(mip_levels(tx)) == 9
    floor = (
        '[camera]\neye = [0.0, 0.6, 3.0]\nlook_at = [0.0, 0.0, 0.0]\nfov_y = 40.0\n\n'
        '[[light]]\ntype = "ambient"\nintensity = 1.0\n\n[[object]]\nshape = "patch"\n'
        'corners = [[-1.0, -0.5, 1.0], [1.0, -0.5, 1.0], [1.0, -0.5, -9.0], [-1.0, -0.5, -9.0]]\n'
        'material = {{ texture = {{ path = "{}", repeat = [2, 10] }} }}\n'
    )
    frames = {}
    for texture in (flat, tx):
        scene = tmp_path / f"{texture.stem}.toml"
        scene.write_text(floor.format(texture.as_posix()))
        cli("render", scene, "-o", tmp_path / f"{texture.stem}.png", "--width", 160, "--height", 120)
        frames[texture.stem] = wrinkle.read_image(tmp_path / f"{texture.stem}.png")
    assert np.abs(frames["flat"] - frames["tiles"]).max() * 255 <= 1.001
