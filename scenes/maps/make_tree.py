#!/usr/bin/env python3
"""Writes tree.png: a stylised tree (three stacked green cones' outlines over a brown trunk) as an 8-bit
RGBA PNG, transparent around it, for the billboard example (scenes/billboards.toml). Made here, free of any
licence. Run from this folder: python3 make_tree.py"""
import struct
import zlib

W, H = 128, 256


def texel(x, y):
    # y = 0 at the top of the picture; work with u, v in [0, 1], v up.
    u, v = (x + 0.5) / W, 1.0 - (y + 0.5) / H
    if abs(u - 0.5) < 0.06 and v < 0.25:
        shade = 0.8 + 0.2 * ((x // 3) % 2)
        return (int(110 * shade), int(70 * shade), int(35 * shade), 255)
    for base, top, half_width in ((0.18, 0.62, 0.46), (0.4, 0.82, 0.36), (0.6, 0.98, 0.26)):
        if base <= v <= top:
            reach = half_width * (top - v) / (top - base)
            if abs(u - 0.5) <= reach:
                light = 0.75 + 0.25 * (0.5 - u) / max(reach, 1e-6)
                return (int(40 * light), int(125 * light), int(45 * light), 255)
    return (0, 0, 0, 0)


raw = bytearray()
for y in range(H):
    raw.append(0)
    for x in range(W):
        raw += bytes(texel(x, y))


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


with open("tree.png", "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n")
    f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 6, 0, 0, 0)))
    f.write(chunk(b"IDAT", zlib.compress(bytes(raw), 9)))
    f.write(chunk(b"IEND", b""))
