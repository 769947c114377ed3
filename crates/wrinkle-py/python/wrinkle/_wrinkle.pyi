"""Type stubs of the extension module. Its functions take C-contiguous float32 arrays (uint8 where named)
and are called through the package's documented wrappers (wrinkle, wrinkle.noise, wrinkle.bumpgen),
which convert dtypes and layouts first."""

from os import PathLike
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str
BUILD_LEVEL: str

def cpu_runs_x86_64_v3() -> bool:
    """Whether this CPU runs x86-64-v3 code (CPUID: AVX2, FMA, BMI2 and the OS saving AVX state)."""

F32 = npt.NDArray[np.float32]
U8 = npt.NDArray[np.uint8]

class CommandError(RuntimeError):
    """A `wrinkle` command that failed: args are its one-line message and its exit code."""

def run_command(args: List[str]) -> None: ...
def write_frame(
    path: PathLike[str],
    color: F32,
    alpha: Optional[F32] = None,
    normal: Optional[F32] = None,
    uv: Optional[F32] = None,
    depth: Optional[F32] = None,
    id: Optional[F32] = None,
    primitive: Optional[npt.NDArray[np.uint32]] = None,
) -> None: ...

class SceneError(ValueError):
    """A scene that cannot be used: a missing, mistyped or out-of-range field, named by its path."""

class Scene:
    """A parsed, validated scene."""
    @staticmethod
    def parse(text: str, base: PathLike[str]) -> Scene: ...
    @staticmethod
    def load(path: PathLike[str]) -> Scene: ...
    @staticmethod
    def from_dict(tables: dict, base: PathLike[str]) -> Scene: ...
    @staticmethod
    def default() -> Scene: ...
    @property
    def objects(self) -> int: ...
    @property
    def animation_end(self) -> Optional[float]: ...
    def at(self, time: float) -> Scene: ...
    def render(
        self,
        width: int,
        height: int,
        spp: int,
        aovs: List[str],
        bump: bool,
        bump_filter: Optional[str],
        transparent: bool,
        transparency: str,
        turntable: float,
        progress: Optional[Callable[[int, int], object]],
        crop: Optional[Tuple[int, int, int, int]] = None,
        sampler: str = "stratified",
        pixel_filter: str = "box",
        seed: int = 0,
        texel_location: str = "centre",
        shading_rate: str = "sample",
    ) -> Dict[str, np.ndarray]: ...

class Texture:
    """A filtered texture over 8-bit (`rgba8`) or float (`rgba`) RGBA pixels."""
    def __init__(
        self,
        rgba8: Optional[U8],
        rgba: Optional[F32],
        srgb: bool,
        wrap: Tuple[str, str],
        mip_filter: str,
        filter: str,
        max_aniso: float,
        border: Sequence[float],
        lod_bias: float,
    ) -> None: ...
    @property
    def size(self) -> Tuple[int, int]: ...
    def sample(self, uv: F32, footprint: Optional[F32], filter: Optional[str], max_aniso: Optional[float]) -> F32: ...
    def mipmap(self) -> List[F32]: ...

def emboss(height: F32, azimuth: float, elevation: float, width: float) -> F32: ...
def modulate(shade: F32, texture: U8) -> U8: ...
def normal_map(height: F32, strength: float, convention: str, kernel: str, wrap: bool, offset: bool) -> F32: ...
def height_from_normals(normals: F32, strength: float, convention: str, wrap: bool, normalize: bool) -> Tuple[F32, float]: ...
def bumpgen(kind: str, size: int, params: Optional[dict] = None) -> F32: ...
def read_image(path: PathLike[str], srgb: bool) -> F32: ...
def read_exr(path: PathLike[str]) -> Dict[str, F32]: ...
def encode_srgb8(linear: F32) -> U8: ...
def write_png8(path: PathLike[str], samples: U8) -> None: ...
def write_png16(path: PathLike[str], samples: npt.NDArray[np.uint16]) -> None: ...
def write_exr(path: PathLike[str], channels: List[Tuple[str, F32]]) -> None: ...
def perlin(points: F32, seed: int, variant: str) -> F32: ...
def fractal(points: F32, sum: str, octaves: int, lacunarity: float, gain: float, seed: int, variant: str) -> F32: ...
def pattern(kind: str, points: F32, width: float, params: Optional[dict] = None) -> Tuple[F32, F32]: ...
def bake(kind: str, width: int, height: int, tileable: bool, params: Optional[dict] = None) -> Tuple[F32, F32]: ...
def pattern_kinds() -> List[Tuple[str, str]]: ...
