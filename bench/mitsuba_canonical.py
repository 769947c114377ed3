#!/usr/bin/env python3
"""Mitsuba 3 on the canonical scene (bench/canonical/sphere.toml): the unit sphere seen from (0, 0, 4), fov_y 40,
1920x1080, 1 sample per pixel or SPP (box filter), the brick colour texture repeated 8x4 as a diffuse reflectance, the
`bumpmap` BSDF over the height map repeated 8x4 (scale 0.004), the scene's two directional lights, direct
lighting only (the `direct` integrator, one emitter sample). Prints the median and best frame time of FRAMES
frames after a warm-up frame (which compiles the kernels of the LLVM variants) and writes the last frame.

Conventions differ from wrinkle's: Mitsuba's sphere puts (u, v) about its own z axis (turned onto y here, the
bricks' rows still start elsewhere), its diffuse BSDF is albedo / pi (the irradiances are scaled by pi to match) and it has no Blinn-Phong
highlight (the scene's specular 0.04 is left out). Compare times, not pictures.

Usage: mitsuba_canonical.py VARIANT CANONICAL_DIR OUT.png [FRAMES [SPP]]   (VARIANT: scalar_rgb or llvm_ad_rgb;
needs: pip install mitsuba; the LLVM variants need libLLVM, e.g. DRJIT_LIBLLVM_PATH=/usr/lib/llvm-19/lib/libLLVM.so)
"""
import math
import statistics
import sys
import time

import mitsuba as mi

variant, folder, out_png = sys.argv[1], sys.argv[2], sys.argv[3]
frames = int(sys.argv[4]) if len(sys.argv) > 4 else 9
spp = int(sys.argv[5]) if len(sys.argv) > 5 else 1
mi.set_variant(variant)
import drjit as dr  # noqa: E402  (after the variant is chosen)

repeat = mi.ScalarTransform4f().scale([8, 4, 1])


def bitmap(name, raw):
    return {"type": "bitmap", "filename": f"{folder}/{name}", "raw": raw, "to_uv": repeat}


def directional(direction, e):
    return {"type": "directional", "direction": direction, "irradiance": {"type": "rgb", "value": [math.pi * e] * 3}}


scene = mi.load_dict({
    "type": "scene",
    "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
    "sensor": {
        "type": "perspective", "fov": 40, "fov_axis": "y",
        "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
        "sampler": {"type": "independent", "sample_count": 1},
        "film": {"type": "hdrfilm", "width": 1920, "height": 1080, "rfilter": {"type": "box"}},
    },
    "sphere": {
        # Mitsuba's sphere has its poles on z; turned so that they lie on y, as wrinkle's.
        "type": "sphere", "radius": 1.0, "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90),
        "bsdf": {"type": "bumpmap", "arbitrary": bitmap("bricks_height.png", True), "scale": 0.004,
                 "bsdf": {"type": "diffuse", "reflectance": bitmap("bricks_color.png", False)}},
    },
    "key": directional([0.6, -0.55, -0.58], 2.6),
    "fill": directional([-0.8, 0.15, -0.35], 0.8),
})

times = []
image = None
for k in range(frames + 1):
    start = time.perf_counter()
    image = mi.render(scene, spp=spp)
    dr.eval(image)
    dr.sync_thread()
    if k > 0:
        times.append((time.perf_counter() - start) * 1e3)
mi.util.write_bitmap(out_png, image)
print(f"mitsuba variant={variant} spp={spp} median_ms={statistics.median(times):.2f} min_ms={min(times):.2f} frames={frames}")
