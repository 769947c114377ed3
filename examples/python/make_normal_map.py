"""Make a tileable normal map from one of Blinn's bump tables, store it as an 8-bit image, and integrate
it back to heights to see how much of the surface the map keeps."""

import numpy as np

import wrinkle

height = wrinkle.bumpgen.bricks(256, rows=8, bricks_per_row=3)  # (256, 256) heights in [0, 1]
normals = wrinkle.normal_map(height, strength=6.0, wrap=True)  # unit normals, OpenGL convention
image = np.rint((normals + 1.0) * 127.5).astype(np.uint8)  # the usual RGB encoding
wrinkle.write_image("bricks_normal.png", image)

back = wrinkle.height_from_normals(image, strength=6.0, wrap=True)
error = np.abs((back - back.mean()) - (height - height.mean()))
print(f"bricks_normal.png written; heights from it differ from the table by {error.mean():.4f} on average")
