"""Argument checks shared by the package: arrays become C-contiguous float32 (or uint8) without a copy
where they already are, and anything else gets a clear exception naming the argument."""

from __future__ import annotations

import numpy as np

_SCALE = {np.dtype(np.uint8): 255.0, np.dtype(np.uint16): 65535.0}


def floats(value, name: str, *, ints: bool = True, finite: bool = True) -> np.ndarray:
    """`value` as a C-contiguous float32 array: floats as they are, uint8 and uint16 (when `ints`) over
    their full scale (255 and 65535 become 1.0). NaN and infinities are refused here when `finite` (else
    the extension refuses them as it reads the values)."""
    a = np.asarray(value)
    if a.dtype in _SCALE and ints:
        return np.ascontiguousarray(a, dtype=np.float32) / np.float32(_SCALE[a.dtype])
    if a.dtype.kind != "f":
        allowed = "a float, uint8 or uint16 array" if ints else "a float array"
        raise TypeError(f"{name}: expected {allowed}, got dtype {a.dtype}")
    a = np.ascontiguousarray(a, dtype=np.float32)
    if finite and a.size and not np.isfinite(a).all():
        raise ValueError(f"{name}: contains NaN or infinite values")
    return a


def grey(value, name: str) -> np.ndarray:
    """A grey image (H, W); (H, W, 3) and (H, W, 4) colour become luma (Rec. 709 weights, as the CLI)."""
    a = floats(value, name)
    if a.ndim == 3 and a.shape[2] in (3, 4):
        a = np.ascontiguousarray(a[..., 0] * 0.2126 + a[..., 1] * 0.7152 + a[..., 2] * 0.0722, dtype=np.float32)
    elif a.ndim == 3 and a.shape[2] == 1:
        a = np.ascontiguousarray(a[..., 0])
    if a.ndim != 2:
        raise ValueError(f"{name}: expected a grey image (H, W), got shape {a.shape}")
    return a


def points(value, name: str = "points") -> np.ndarray:
    """Points (N, 2) or (N, 3) as float32; a single point (2,) or (3,) becomes (1, D)."""
    a = floats(value, name, ints=False, finite=False)
    if a.ndim == 1 and a.shape[0] in (2, 3):
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] not in (2, 3):
        raise ValueError(f"{name}: expected shape (N, 2) or (N, 3), got {a.shape}")
    return a
