"""Perlin noise, its fractal sums and the procedural patterns of the course over arrays of points, and
patterns baked into images. Points are (N, 3) for solid textures or (N, 2); every call runs on all
cores with the GIL released.

Pattern parameters keep the scene file's names: scale, seed, variant ("hashed", the fast default;
"improved", Perlin's permutation table and published values; or "classic", 1985),
octaves, lacunarity, gain, strength, rings, time, mortar, line_width, colors (a list of linear RGB
triples from t = 0 to t = 1)."""

from __future__ import annotations

from typing import List, Optional, Tuple

import numpy as np

from . import _wrinkle
from ._arrays import points as _points

__all__ = [
    "perlin", "fbm", "turbulence", "pattern", "bake", "kinds",
    "marble", "wood", "fire", "clouds", "bricks", "checker", "grid",
]


def _name(option: Optional[str]) -> Optional[str]:
    """An option's name as the extension takes it: None leaves the core's default."""
    return None if option is None else str(option)


def perlin(points, seed: int = 0, variant: Optional[str] = None) -> np.ndarray:
    """Perlin's gradient noise (about [-1, 1]) at every point, (N,) float32. Seed 0 with "improved" is
    Perlin's published 2002 function; the default (None: "hashed") is the same noise on a hashed lattice,
    faster."""
    return _wrinkle.perlin(_points(points), int(seed), _name(variant))


def fbm(points, octaves: int = 6, lacunarity: float = 2.0, gain: float = 0.5, seed: int = 0, variant: Optional[str] = None) -> np.ndarray:
    """Fractional Brownian motion: the sum of noise(f p) / f over `octaves` (frequency ratio `lacunarity`,
    amplitude ratio `gain`), (N,) float32."""
    return _wrinkle.fractal(_points(points), "fbm", int(octaves), float(lacunarity), float(gain), int(seed), _name(variant))


def turbulence(points, octaves: int = 6, lacunarity: float = 2.0, gain: float = 0.5, seed: int = 0, variant: Optional[str] = None) -> np.ndarray:
    """Perlin's turbulence: the sum of |noise(f p)| / f over octaves, (N,) float32."""
    return _wrinkle.fractal(_points(points), "turbulence", int(octaves), float(lacunarity), float(gain), int(seed), _name(variant))


def pattern(kind: str, points, width: float = 0.0, **params) -> Tuple[np.ndarray, np.ndarray]:
    """A procedural pattern (see `kinds()`) at every point: (t, rgb) with t (N,) in [0, 1] and its colour
    (N, 3) linear. `width` is the footprint in the points' units: the pattern is filtered over it (0: a
    point sample)."""
    return _wrinkle.pattern(str(kind), _points(points), float(width), params)


def bake(kind: str, width: int = 512, height: int = 512, tileable: bool = False, **params) -> Tuple[np.ndarray, np.ndarray]:
    """A pattern baked into an image as `wrinkle texture` bakes it: (t, rgb), t (H, W) and rgb (H, W, 3)
    linear; the image covers [0, 1) in u (left to right) and v (bottom to top)."""
    return _wrinkle.bake(str(kind), int(width), int(height), bool(tileable), params)


def kinds() -> List[Tuple[str, str]]:
    """Every pattern kind with a line on what it is and which parameters it reads."""
    return list(_wrinkle.pattern_kinds())


def _colour_of(kind: str):
    def colour(points, width: float = 0.0, **params) -> np.ndarray:
        return pattern(kind, points, width, **params)[1]

    colour.__name__ = kind
    colour.__qualname__ = kind
    colour.__doc__ = (
        f"The {kind} pattern's colour (N, 3) linear RGB at every point: "
        f"{dict(_wrinkle.pattern_kinds())[kind]}. Parameters as in `pattern`."
    )
    return colour


marble = _colour_of("marble")
wood = _colour_of("wood")
fire = _colour_of("fire")
clouds = _colour_of("clouds")
bricks = _colour_of("bricks")
checker = _colour_of("checker")
grid = _colour_of("grid")
