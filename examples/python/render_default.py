"""Render wrinkle's default scene (the cover of the 1978 proceedings) and show it with matplotlib, with
its depth AOV beside it. Without a display (MPLBACKEND=Agg) the figure is written to default_scene.png."""

import matplotlib.pyplot as plt
import numpy as np

import wrinkle

frame = wrinkle.Scene.default().render(640, 360, spp=4, aov=("depth",), progress=True)
colour = wrinkle.to_srgb8(frame["color"])  # exactly the PNG that `wrinkle render` writes
depth = np.where(np.isnan(frame["depth"]), np.nanmax(frame["depth"]), frame["depth"])

fig, (left, right) = plt.subplots(1, 2, figsize=(12, 3.6))
left.imshow(colour)
left.set_title("colour")
right.imshow(depth, cmap="viridis_r")
right.set_title("depth (distance from the eye)")
for ax in (left, right):
    ax.axis("off")
fig.tight_layout()
if plt.get_backend().lower() == "agg":
    fig.savefig("default_scene.png", dpi=80)
    print("wrote default_scene.png")
else:
    plt.show()
