#!/usr/bin/env python3
"""Writes sky.hdr: a synthetic outdoor environment (latlong, 512x256, Radiance RGBE) for the environment
examples. A blue sky over a chequered ground, a small bright sun and a few coloured walls on the horizon;
made here, so it is free of any licence. Run from this folder: python3 make_sky.py"""
import math
import struct

W, H = 512, 256
SUN = (0.45, 0.55, -0.70)
n = math.sqrt(sum(c * c for c in SUN))
SUN = tuple(c / n for c in SUN)
# Walls on the horizon: (azimuth from, to in degrees about +Y from -Z towards +X, top elevation, colour).
WALLS = [(-70, -40, 12, (0.7, 0.12, 0.08)), (20, 35, 20, (0.1, 0.5, 0.55)), (100, 150, 8, (0.8, 0.65, 0.1)),
         (-160, -120, 15, (0.35, 0.35, 0.4))]


def radiance(x, y, z):
    azimuth = math.degrees(math.atan2(x, -z))
    elevation = math.degrees(math.asin(max(-1.0, min(1.0, y))))
    for a0, a1, top, c in WALLS:
        if a0 <= azimuth <= a1 and 0.0 <= elevation <= top:
            shade = 0.6 + 0.4 * (elevation / top)
            return tuple(v * shade for v in c)
    if y >= 0.0:
        t = y ** 0.5
        sky = tuple(h * (1 - t) + z_ * t for h, z_ in zip((1.1, 1.15, 1.2), (0.2, 0.4, 0.95)))
        cos_sun = x * SUN[0] + y * SUN[1] + z * SUN[2]
        if cos_sun > math.cos(math.radians(2.5)):
            return (60.0, 55.0, 45.0)
        glow = 2.0 * max(0.0, cos_sun) ** 64
        return tuple(s + glow for s in sky)
    # The ground plane one unit below: chequers of one unit, hazier towards the horizon.
    k = -1.0 / y
    gx, gz = x * k, z * k
    even = (math.floor(gx) + math.floor(gz)) % 2 == 0
    ground = (0.32, 0.22, 0.12) if even else (0.18, 0.3, 0.1)
    haze = min(1.0, k / 30.0)
    return tuple(g * (1 - haze) + 0.9 * haze for g in ground)


def rgbe(r, g, b):
    v = max(r, g, b)
    if v < 1e-32:
        return bytes(4)
    m, e = math.frexp(v)
    scale = m * 256.0 / v
    return bytes([int(r * scale), int(g * scale), int(b * scale), e + 128])


rows = []
for j in range(H):
    polar = (j + 0.5) / H * math.pi
    row = bytearray()
    for i in range(W):
        phi = ((i + 0.5) / W - 0.5) * 2 * math.pi
        x, y, z = math.sin(polar) * math.sin(phi), math.cos(polar), -math.sin(polar) * math.cos(phi)
        row += rgbe(*radiance(x, y, z))
    rows.append(bytes(row))
with open("sky.hdr", "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
    f.write(b"-Y %d +X %d\n" % (H, W))
    for r in rows:
        f.write(r)
