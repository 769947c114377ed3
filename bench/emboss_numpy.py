#!/usr/bin/env python3
"""The peer of `wrinkle emboss` and `wrinkle normalmap`: Schlag's formula (or a Sobel normal map) with NumPy and
OpenCV, as an artist's script would do it. Prints the arithmetic time on stderr.

usage: emboss_numpy.py emboss|normalmap IN.png OUT.png [azimuth elevation width | strength]"""
import sys, time
import numpy as np
import cv2

mode, src, dst = sys.argv[1:4]
img = cv2.imread(src, cv2.IMREAD_GRAYSCALE | cv2.IMREAD_ANYDEPTH).astype(np.float32)
t = time.perf_counter()
if mode == "emboss":
    az, el, w = (float(a) for a in sys.argv[4:7]) if len(sys.argv) > 4 else (135.0, 45.0, 3.0)
    az, el = np.radians(az), np.radians(el)
    lx, ly, lz = np.cos(az) * np.cos(el), np.sin(az) * np.cos(el), np.sin(el)
    ku = np.array([[-1, 0, 1]] * 3, np.float32)
    kv = np.array([[1, 1, 1], [0, 0, 0], [-1, -1, -1]], np.float32)
    iu = cv2.filter2D(img, -1, ku, borderType=cv2.BORDER_REPLICATE)
    iv = cv2.filter2D(img, -1, kv, borderType=cv2.BORDER_REPLICATE)
    nz = 6.0 * 255.0 / w
    shade = np.maximum(nz * lz - iu * lx - iv * ly, 0) / np.sqrt(iu * iu + iv * iv + nz * nz)
    shade[(iu == 0) & (iv == 0)] = lz
    out = (shade * 255 + 0.5).astype(np.uint8)
else:
    s = float(sys.argv[4]) if len(sys.argv) > 4 else 3.0
    h = img / 255.0
    gx = cv2.Sobel(h, cv2.CV_32F, 1, 0, ksize=3, borderType=cv2.BORDER_REPLICATE) / 8.0
    gy = -cv2.Sobel(h, cv2.CV_32F, 0, 1, ksize=3, borderType=cv2.BORDER_REPLICATE) / 8.0
    n = np.dstack([-s * gx, -s * gy, np.ones_like(h)])
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    out = ((n + 1) * 127.5 + 0.5).astype(np.uint8)[:, :, ::-1]  # OpenCV writes BGR
print(f"arithmetic {1e3 * (time.perf_counter() - t):.0f} ms", file=sys.stderr)
cv2.imwrite(dst, out)
