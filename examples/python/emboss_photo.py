"""Emboss a photograph (Schlag, Graphics Gems IV) lit from the upper left, and multiply the photo by the
shade. Give an image path, or it embosses the repository's tiles texture."""

import sys
from pathlib import Path

import numpy as np

import wrinkle

path = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "scenes" / "tiles_color.png"
photo = wrinkle.read_image(path)[..., :3]  # (H, W, 3) float32 in [0, 1], as stored
shade = wrinkle.emboss(photo, azimuth=135, elevation=30, width=4)  # colour becomes luma
relief = wrinkle.emboss(photo, azimuth=135, elevation=30, width=4, texture=(photo * 255).round().astype(np.uint8))

wrinkle.write_image("embossed.png", shade)  # grey data: stored as computed, no sRGB curve
wrinkle.write_image("embossed_colour.png", relief)  # uint8: stored as is
print(f"embossed {path.name} ({photo.shape[1]}x{photo.shape[0]}): embossed.png, embossed_colour.png")
