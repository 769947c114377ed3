"""Blinn's bump-function tables (1978, figs. 5-8) as height arrays (H, W) float32 in [0, 1], white high,
as `wrinkle bumpgen` makes them. Options left out keep the generator's defaults."""

from __future__ import annotations

from typing import Optional

import numpy as np

from . import _wrinkle

__all__ = ["grid", "text", "rivets", "bricks"]


def _options(**given) -> dict:
    return {k: v for k, v in given.items() if v is not None}


def grid(size: int = 512, cells: Optional[int] = None, line_width: Optional[float] = None, soft: Optional[float] = None) -> np.ndarray:
    """Fig. 5: a gridwork of high lines on a low floor, `size` x `size`, `cells` along each side, each
    line `line_width` of a cell wide with edge ramps `soft` of a cell."""
    return _wrinkle.bumpgen("grid", int(size), _options(cells=cells, line_width=line_width, soft=soft))


def text(size: int = 128, text: Optional[str] = None, soft: Optional[float] = None) -> np.ndarray:
    """Fig. 6: embossed 8x8 bitmap letters in one row, `size` high and `size` wide per letter, blurred by
    `soft` of a glyph pixel (ASCII; other characters become '?')."""
    return _wrinkle.bumpgen("text", int(size), _options(text=text, soft=soft))


def rivets(size: int = 512, count: Optional[int] = None, radius: Optional[float] = None) -> np.ndarray:
    """Fig. 7: the Z-buffer of a sphere replicated into `count` x `count` rivets of `radius` (a fraction of
    a rivet's cell); `count` must divide `size`."""
    return _wrinkle.bumpgen("rivets", int(size), _options(count=count, radius=radius))


def bricks(
    size: int = 512,
    rows: Optional[int] = None,
    bricks_per_row: Optional[int] = None,
    mortar: Optional[float] = None,
    bevel: Optional[float] = None,
) -> np.ndarray:
    """Fig. 8: a running-bond brick unit cell, `rows` courses (even) of `bricks_per_row` bricks, mortar
    joints and bevels as fractions of a course's height."""
    return _wrinkle.bumpgen(
        "bricks", int(size), _options(rows=rows, bricks_per_row=bricks_per_row, mortar=mortar, bevel=bevel)
    )
