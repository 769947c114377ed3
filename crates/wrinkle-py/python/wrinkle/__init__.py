"""wrinkle: texture mapping and Blinn bump mapping, exactly and fast, over NumPy arrays.

Images are NumPy arrays, row 0 at the top: float32 in linear light unless a function says otherwise;
uint8 and uint16 inputs are read over their full scale. Long calls release the GIL and use every core.

    import wrinkle
    frame = wrinkle.Scene.default().render(640, 360)
    rgb8 = wrinkle.to_srgb8(frame["color"])
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable, Iterable, Optional, Sequence, Tuple, Union

import numpy as np

from . import _cpu

_wrinkle = _cpu.load()  # before anything else loads the extension module, on purpose

from . import bumpgen, noise  # noqa: E402
from .tables import (  # noqa: E402
    Bicubic, Billboard, Box, Bump, Camera, Cylinder, Environment, Light, Material, Mesh, Patch, Sphere, Table,
    Torus, Volume, plain,
)
from ._arrays import floats, grey  # noqa: E402
from ._wrinkle import CommandError, SceneError  # noqa: E402

__version__: str = _wrinkle.__version__
#: The instruction set the loaded extension module was built for: "x86-64-v3", or "x86-64" for the portable
#: one (the same results, for CPUs without AVX2).
build_level: str = _wrinkle.BUILD_LEVEL

__all__ = [
    "Bicubic", "Billboard", "Box", "Bump", "Camera", "Cylinder", "Environment", "Light", "Material", "Mesh",
    "Patch", "Sphere", "Table", "Torus", "Volume",
    "CommandError",
    "Scene",
    "SceneError",
    "Texture",
    "bumpgen",
    "build_level",
    "emboss",
    "height_from_normals",
    "noise",
    "normal_map",
    "read_exr",
    "read_image",
    "run_command",
    "write_frame",
    "write_image",
    "to_srgb8",
]

PathLike = Union[str, "os.PathLike[str]"]
Progress = Union[bool, Callable[[int, int], object], None]


def _progress_callback(progress: Progress):
    """A (done, total) callback: the caller's, a tqdm bar for True, none for None/False."""
    if progress is None or progress is False:
        return None, None
    if progress is True:
        from tqdm.auto import tqdm

        bar = tqdm(total=1, unit="band", leave=False)

        def tell(done: int, total: int) -> None:
            bar.total = total
            bar.n = done
            bar.refresh()

        return tell, bar
    if not callable(progress):
        raise TypeError(f"progress: expected True, False, None or a callable (done, total), got {type(progress).__name__}")
    return progress, None


class Scene:
    """A scene: camera, lights, objects and materials, as a scene file describes them
    (docs/scene-format.md). Build one with `Scene.from_toml`, `Scene.load`, `Scene.from_dict` or
    `Scene.default`, then `render` it."""

    __slots__ = ("_scene",)

    def __init__(self, native: "_wrinkle.Scene") -> None:
        if not isinstance(native, _wrinkle.Scene):
            raise TypeError("use Scene.from_toml, Scene.load, Scene.from_dict or Scene.default")
        self._scene = native

    @staticmethod
    def from_toml(text_or_path: Union[str, PathLike], base: Optional[PathLike] = None) -> "Scene":
        """A scene from TOML text, or from the file a path names (a `pathlib.Path`, or a string that
        names an existing file ending in .toml). Relative file names in text resolve against `base`
        (default: the current directory); in a file, against the file's folder."""
        if isinstance(text_or_path, os.PathLike) or (
            isinstance(text_or_path, str) and text_or_path.endswith(".toml") and "\n" not in text_or_path
        ):
            return Scene.load(text_or_path)
        if not isinstance(text_or_path, str):
            raise TypeError(f"text_or_path: expected str or a path, got {type(text_or_path).__name__}")
        return Scene(_wrinkle.Scene.parse(text_or_path, Path(base if base is not None else ".")))

    @staticmethod
    def load(path: PathLike) -> "Scene":
        """Reads a scene file."""
        return Scene(_wrinkle.Scene.load(Path(path)))

    @staticmethod
    def from_dict(tables: dict, base: Optional[PathLike] = None) -> "Scene":
        """A scene from a dictionary with the scene file's tables and fields, for example
        `{"camera": {...}, "light": [{...}], "object": [{"shape": "sphere", ...}]}`."""
        if not isinstance(tables, dict):
            raise TypeError(f"tables: expected a dict, got {type(tables).__name__}")
        return Scene(_wrinkle.Scene.from_dict(tables, Path(base if base is not None else ".")))

    @staticmethod
    def build(
        camera: Union[Table, dict],
        lights: Iterable[Union[Table, dict]] = (),
        objects: Iterable[Union[Table, dict]] = (),
        volumes: Iterable[Union[Table, dict]] = (),
        environment: Union[Table, dict, None] = None,
        base: Optional[PathLike] = None,
    ) -> "Scene":
        """A scene from Python objects: `Camera`, `Light`s, objects (`Sphere`, `Patch`, `Mesh`, ...) with
        their `Material` and `Bump`, `Volume`s and an `Environment` (or dictionaries in their place)."""
        tables = {"camera": plain(camera), "light": plain(list(lights)), "object": plain(list(objects))}
        if volumes:
            tables["volume"] = plain(list(volumes))
        if environment is not None:
            tables["environment"] = plain(environment)
        return Scene.from_dict(tables, base)

    @staticmethod
    def default() -> "Scene":
        """The embedded default scene (the cover of the 1978 proceedings), as `wrinkle render` draws it."""
        return Scene(_wrinkle.Scene.default())

    @property
    def objects(self) -> int:
        """How many objects the scene holds."""
        return self._scene.objects

    @property
    def animation_end(self) -> Optional[float]:
        """The time in seconds of the last key of the scene's `[[animation]]` tracks (None without any)."""
        return self._scene.animation_end

    def at(self, time: float) -> "Scene":
        """The scene at `time` seconds of its animation (as `wrinkle render --frames` renders frame
        f at time f / fps); ValueError for a scene without `[[animation]]` tracks."""
        return Scene(self._scene.at(float(time)))

    def render(
        self,
        width: int = 1280,
        height: int = 720,
        spp: int = 1,
        aov: Iterable[str] = (),
        *,
        bump: bool = True,
        bump_filter: Optional[str] = None,
        transparent: bool = False,
        transparency: str = "sorted",
        turntable: float = 0.0,
        progress: Progress = None,
        crop: Optional[Tuple[int, int, int, int]] = None,
        sampler: str = "stratified",
        pixel_filter: str = "box",
        seed: int = 0,
        texel_location: str = "centre",
        shading_rate: str = "sample",
    ) -> dict:
        """Renders a frame as `wrinkle render` does, returning arrays by name:

        - "color": (H, W, 3) float32, linear RGB (`to_srgb8` encodes it as the PNG output is);
        - with `aov` naming them: "normal" (H, W, 3), "uv" (H, W, 2), "depth" (H, W) distance from the eye,
          "id" (H, W) object index, "primitive" (H, W, 2) uint32 (object, triangle), "alpha" (H, W) coverage.
          Pixels where no object is seen hold NaN (primitive: 2**32 - 1; alpha: 0).

        `crop` = (x0, y0, x1, y1) renders only those pixels of the width x height frame (row 0 at the top),
        exactly as the whole frame renders them; the arrays are the crop's size.

        `spp` is 1 to 4096 samples per pixel, placed by `sampler`: "stratified" (jittered strata, the same in
        every pixel) or "sobol" (Owen-scrambled per pixel). `pixel_filter` makes the pixel from them: "box",
        "tent", "gaussian", "mitchell" or "lanczos", or "NAME:RADIUS"; `seed` seeds the Sobol scrambles
        (renders with other seeds are independent estimates of the same image). `texel_location` is where a
        pixel reads its textures: "centre", or "centroid" or "diagonals" of its projected corners (with their
        quadrilateral's footprint). `shading_rate` is "sample" (every sample shaded) or "pixel" (each
        triangle once per pixel, coverage still per sample). `progress=True` shows a tqdm bar; a
        callable gets (done, total). Ctrl-C stops the render promptly (KeyboardInterrupt)."""
        if isinstance(aov, str):
            aov = (aov,)
        callback, bar = _progress_callback(progress)
        try:
            return self._scene.render(
                int(width), int(height), int(spp), [str(a) for a in aov], bool(bump), bump_filter,
                bool(transparent), str(transparency), float(turntable), callback,
                None if crop is None else tuple(int(c) for c in crop), str(sampler), str(pixel_filter), int(seed),
                str(texel_location), str(shading_rate),
            )
        finally:
            if bar is not None:
                bar.close()

    def __repr__(self) -> str:
        return f"<wrinkle.Scene with {self.objects} objects>"


class Texture:
    """A colour texture ready for every filter of the course: nearest, bilinear, bicubic, bspline,
    gaussian, lanczos (magnification), mip-nearest, trilinear, ripmap, sat, aniso, ewa and reference.

    `pixels`: (H, W), (H, W, 3) or (H, W, 4); uint8 (stored in 8 bits, sRGB-decoded when `srgb`), uint16
    or float (linear unless `srgb` for uint16). Row 0 is the top of the image; t runs up it.
    `wrap`: "repeat", "clamp", "mirror" or "border", or a pair (s, t).
    `lod_bias`: levels added to the level of detail (every footprint scaled by 2**lod_bias), -4 to 4;
    -0.5 suits lookups that stand for one of several samples of a pixel."""

    __slots__ = ("_texture",)

    def __init__(
        self,
        pixels,
        wrap: Union[str, Tuple[str, str]] = "repeat",
        srgb: bool = True,
        filter: str = "trilinear",
        mip_filter: str = "box",
        max_aniso: float = 16.0,
        border: Sequence[float] = (0.0, 0.0, 0.0, 0.0),
        lod_bias: float = 0.0,
    ) -> None:
        a = np.asarray(pixels)
        if a.ndim == 2:
            a = a[..., None]
        if a.ndim != 3 or a.shape[2] not in (1, 3, 4):
            raise ValueError(f"pixels: expected (H, W), (H, W, 3) or (H, W, 4), got shape {np.shape(pixels)}")
        if a.shape[2] == 1:
            a = np.repeat(a, 3, axis=2)
        rgba8 = rgba = None
        if a.dtype == np.uint8:
            if a.shape[2] == 3:
                a = np.concatenate([a, np.full(a.shape[:2] + (1,), 255, np.uint8)], axis=2)
            rgba8 = np.ascontiguousarray(a)
        else:
            f = floats(a, "pixels")
            if srgb and a.dtype == np.uint16:
                f[..., :3] = _srgb_to_linear(f[..., :3])
            if f.shape[2] == 3:
                f = np.concatenate([f, np.ones(f.shape[:2] + (1,), np.float32)], axis=2)
            rgba = np.ascontiguousarray(f)
        wraps = (wrap, wrap) if isinstance(wrap, str) else tuple(wrap)
        if len(wraps) != 2:
            raise ValueError(f"wrap: expected a mode or a pair of modes, got {wrap!r}")
        border = tuple(float(b) for b in border)
        if len(border) != 4:
            raise ValueError(f"border: expected four numbers (RGBA), got {len(border)}")
        self._texture = _wrinkle.Texture(
            rgba8, rgba, bool(srgb), (str(wraps[0]), str(wraps[1])), str(mip_filter), str(filter),
            float(max_aniso), border, float(lod_bias),
        )

    @property
    def size(self) -> Tuple[int, int]:
        """(width, height) in texels."""
        return self._texture.size

    def sample(
        self,
        uv,
        footprint=None,
        filter: Optional[str] = None,
        max_aniso: Optional[float] = None,
    ) -> np.ndarray:
        """The filtered texture at N points: `uv` (N, 2) in periods (one copy of the texture per unit),
        `footprint` (N, 4) the pixel's derivatives (ds/dx, dt/dx, ds/dy, dt/dy) in the same units (None: a
        point, the full-resolution texture). Returns (N, 4) float32 linear RGBA. `filter` and `max_aniso`
        override the texture's own for this call."""
        uv_a = floats(uv, "uv", ints=False, finite=False)
        single = uv_a.ndim == 1
        if single:
            uv_a = uv_a[None, :]
        fp = None
        if footprint is not None:
            fp = floats(footprint, "footprint", ints=False, finite=False)
            if fp.ndim == 1:
                fp = fp[None, :]
        out = self._texture.sample(uv_a, fp, filter, None if max_aniso is None else float(max_aniso))
        return out[0] if single else out

    def lookup(self, s: float, t: float, footprint: Optional[Tuple[float, float, float, float]] = None) -> Tuple[float, float, float, float]:
        """One lookup at (s, t) with the footprint (ds/dx, dt/dx, ds/dy, dt/dy) (None: a point), as an RGBA
        tuple: the per-point form of `sample`, for loops over single points (it makes no arrays)."""
        return self._texture.lookup(s, t, footprint)

    def mipmap(self) -> list:
        """The MIP pyramid in linear light, full resolution first, each level (H, W, 4) float32."""
        return self._texture.mipmap()

    def __repr__(self) -> str:
        w, h = self.size
        return f"<wrinkle.Texture {w}x{h}>"


def _srgb_to_linear(c: np.ndarray) -> np.ndarray:
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4).astype(np.float32)


def emboss(height, azimuth: float = 135.0, elevation: float = 45.0, width: float = 3.0, texture=None) -> np.ndarray:
    """Schlag's fast emboss (Graphics Gems IV) of a height image, as `wrinkle emboss` computes it.

    `height`: (H, W) grey (colour becomes luma), white high. The light comes from `azimuth` degrees
    counter-clockwise from the right, `elevation` degrees above the picture; `width` is the bevel width
    (N_z = 6 * 255 / width). Returns the shade (H, W) float32 in [0, 1]; with a `texture` (H, W, 3), the
    texture times the shade: uint8 (rounded as the CLI rounds) for a uint8 texture, else float32."""
    h = grey(height, "height")
    shade = _wrinkle.emboss(h, float(azimuth), float(elevation), float(width))
    if texture is None:
        return shade
    t = np.asarray(texture)
    if t.ndim != 3 or t.shape[:2] != h.shape or t.shape[2] not in (3, 4):
        raise ValueError(f"texture: expected shape {h.shape + (3,)}, got {t.shape}")
    if t.dtype == np.uint8:
        return _wrinkle.modulate(shade, np.ascontiguousarray(t[..., :3]))
    return floats(t[..., :3], "texture") * shade[..., None]


def normal_map(
    height,
    strength: float = 3.0,
    convention: str = "opengl",
    kernel: str = "sobel",
    wrap: bool = False,
    offset: bool = False,
) -> np.ndarray:
    """The tangent-space normals of z = strength * height (x, y in pixels), as `wrinkle normalmap`.

    Returns unit normals (H, W, 3) float32 with components in [-1, 1] (store (n + 1) / 2 for an image);
    with `offset`, the slopes (H, W, 2) instead (the offset vectors, unclamped). `convention`: "opengl"
    (+Y up the picture) or "directx"; `kernel`: "central", "sobel" or "scharr"; `wrap`: tileable."""
    return _wrinkle.normal_map(grey(height, "height"), float(strength), str(convention), str(kernel), bool(wrap), bool(offset))


def height_from_normals(
    normals,
    strength: float = 3.0,
    convention: str = "opengl",
    wrap: bool = False,
    normalize: bool = False,
) -> np.ndarray:
    """Heights (H, W) in [0, 1] whose normal map is nearest to `normals` (Frankot-Chellappa), as
    `wrinkle heightmap`. `normals`: float (H, W, 3) unit vectors in [-1, 1] (what `normal_map` returns),
    or a uint8/uint16 normal-map image, decoded as (c * 2 - 1). The lowest point is 0; `normalize`
    stretches the highest to 1 (else heights above 1 mean `strength` was too small)."""
    a = np.asarray(normals)
    n = floats(a, "normals")
    if a.dtype in (np.uint8, np.uint16):
        n = n * np.float32(2.0) - np.float32(1.0)
    if n.ndim != 3 or n.shape[2] != 3:
        raise ValueError(f"normals: expected shape (H, W, 3), got {n.shape}")
    heights, _span = _wrinkle.height_from_normals(np.ascontiguousarray(n), float(strength), str(convention), bool(wrap), bool(normalize))
    return heights


def read_image(path: PathLike, srgb: bool = False) -> np.ndarray:
    """An image file (PNG 8/16-bit, JPEG, BMP, TGA, TIFF, EXR, HDR) as (H, W, 4) float32 RGBA: integer
    samples over their full scale, decoded from sRGB to linear when `srgb`."""
    return _wrinkle.read_image(Path(path), bool(srgb))


def write_image(path: PathLike, image, bits: Optional[int] = None, srgb: Optional[bool] = None) -> None:
    """Writes an image (H, W) or (H, W, C) with 1 to 4 channels (grey, grey + alpha, RGB, RGBA), whole or
    not at all (a temporary file renamed into place), by the path's extension:

    - .png: uint8 and uint16 arrays are written as stored (8 and 16 bits); float arrays are taken as linear,
      clamped to [0, 1] and written with `bits` (8 by default, or 16), sRGB-encoded when `srgb` (by default
      for RGB and RGBA, not for grey data such as heights; alpha is never encoded). 8-bit sRGB is exactly
      what `wrinkle render` writes.
    - .exr: float32, linear, lossless (NaN kept); channels Y, Y A, R G B or R G B A."""
    p = Path(path)
    ext = p.suffix.lower()
    a = np.asarray(image)
    if a.ndim == 2:
        a = a[..., None]
    if a.ndim != 3 or not 1 <= a.shape[2] <= 4:
        raise ValueError(f"image: expected shape (H, W) or (H, W, C) with 1 to 4 channels, got {np.shape(image)}")
    channels = a.shape[2]
    if ext == ".exr":
        f = floats(a, "image", finite=False)
        names = {1: ["Y"], 2: ["Y", "A"], 3: ["R", "G", "B"], 4: ["R", "G", "B", "A"]}[channels]
        _wrinkle.write_exr(p, [(n, np.ascontiguousarray(f[..., i])) for i, n in enumerate(names)])
        return
    if ext != ".png":
        raise ValueError(f"path: expected a .png or .exr file name, got {p.name!r}")
    if bits not in (None, 8, 16):
        raise ValueError(f"bits: expected 8 or 16, got {bits!r}")
    if a.dtype == np.uint8 and bits in (None, 8):
        _wrinkle.write_png8(p, np.ascontiguousarray(a))
        return
    if a.dtype == np.uint16 and bits in (None, 16):
        _wrinkle.write_png16(p, np.ascontiguousarray(a))
        return
    f = np.clip(floats(a, "image"), 0.0, 1.0)
    colour = 3 if channels >= 3 else 0
    encode = colour > 0 if srgb is None else bool(srgb) and colour > 0
    if (bits or 8) == 8:
        out = np.rint(f * 255).astype(np.uint8)
        if encode:
            out[..., :colour] = _wrinkle.encode_srgb8(np.ascontiguousarray(f[..., :colour]))
        _wrinkle.write_png8(p, np.ascontiguousarray(out))
    else:
        if encode:
            c = f[..., :colour]
            f[..., :colour] = np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)
        _wrinkle.write_png16(p, np.ascontiguousarray(np.rint(f * 65535).astype(np.uint16)))


def read_exr(path: PathLike) -> dict:
    """Every channel of an OpenEXR file by name (the renderer's AOVs among them), each (H, W) float32."""
    return _wrinkle.read_exr(Path(path))


def to_srgb8(linear) -> np.ndarray:
    """Linear values as 8-bit sRGB codes, exactly as the renderer encodes its PNG frames (any shape)."""
    return _wrinkle.encode_srgb8(floats(linear, "linear", ints=False))


def write_frame(path: PathLike, frame: dict) -> None:
    """Writes a frame, the dict `Scene.render` returns, as `wrinkle render -o PATH` writes it, byte for
    byte: PNG (8-bit sRGB; RGBA with straight alpha where the frame has "alpha") or EXR (linear,
    premultiplied) by the extension, and each AOV it holds as PATH.<name>.exr; all placed together or none."""
    arrays = {}
    for key, dtype in (("color", np.float32), ("alpha", np.float32), ("normal", np.float32), ("uv", np.float32),
                       ("depth", np.float32), ("id", np.float32), ("primitive", np.uint32)):
        if key in frame:
            arrays[key] = np.ascontiguousarray(frame[key], dtype=dtype)
    if "color" not in arrays:
        raise ValueError("frame: expected the dict Scene.render returns, with \"color\"")
    _wrinkle.write_frame(Path(path), **arrays)


def run_command(*args) -> None:
    """Runs the `wrinkle` command line in this process: `run_command("normalmap", "h.png", "-o", "n.png",
    "--strength", 4)` does what `wrinkle normalmap h.png -o n.png --strength 4` does, with the same options,
    outputs and messages. A failure raises CommandError(message, exit_code)."""
    _wrinkle.run_command([os.fspath(a) if isinstance(a, os.PathLike) else str(a) for a in args])
