"""Compare texture filters on a checkerboard seen on a plane receding to the horizon: each pixel's
footprint comes from the projection's derivatives, every filter reads the same lookups, and each is
scored against the supersampled `reference` filter."""

import time

import matplotlib.pyplot as plt
import numpy as np

import wrinkle

W, H = 320, 160
checker = np.kron((np.indices((8, 8)).sum(axis=0) % 2).astype(np.float32), np.ones((32, 32), np.float32))
texture = wrinkle.Texture(np.repeat(checker[..., None], 3, axis=2))

# A ground plane under a pinhole camera: pixel (x, y) below the horizon sees (s, t) = (x' / y', 1 / y').
x, y = np.meshgrid((np.arange(W) + 0.5 - W / 2) / (H / 2), (np.arange(H) + 0.5) / H + 0.02)
s, t = 2 * x / y, 1.0 / y
# The derivatives per pixel step: ds/dx = 2 / (y H/2), ds/dy = -2 x / y^2 / H, dt/dy = -1 / y^2 / H.
dsdx, dtdx = 2 / (y * H / 2), np.zeros_like(y)
dsdy, dtdy = -2 * x / y**2 / H, -1 / y**2 / H
uv = np.stack([s, t], axis=-1).reshape(-1, 2).astype(np.float32)
footprint = np.stack([dsdx, dtdx, dsdy, dtdy], axis=-1).reshape(-1, 4).astype(np.float32)

truth = texture.sample(uv, footprint, filter="reference")[:, 0]
fig, axes = plt.subplots(2, 3, figsize=(12, 4.5))
for ax, name in zip(axes.flat, ["nearest", "bilinear", "trilinear", "ripmap", "aniso", "ewa"]):
    start = time.perf_counter()
    grey = texture.sample(uv, footprint, filter=name)[:, 0]
    ms = (time.perf_counter() - start) * 1e3
    psnr = 10 * np.log10(1.0 / np.mean((grey - truth) ** 2))
    print(f"{name:10s} {ms:7.1f} ms  {psnr:5.1f} dB against the reference")
    ax.imshow(wrinkle.to_srgb8(grey.reshape(H, W)), cmap="gray", vmin=0, vmax=255)
    ax.set_title(f"{name}: {psnr:.1f} dB")
    ax.axis("off")
fig.tight_layout()
fig.savefig("filters.png", dpi=80)
print("wrote filters.png")
