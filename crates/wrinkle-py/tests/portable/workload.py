"""One small call of each kind of work (render with AOVs, emboss, normal map, heights from normals, noise,
procedural bake, texture filters, bump generators), saved to OUT.npz with the build that ran it; run by
test_portable.py once per build, on this CPU and on an emulated one without AVX2."""

import sys

import numpy as np

import wrinkle


def results():
    rng = np.random.default_rng(7)
    out = {}
    frame = wrinkle.Scene.default().render(64, 48, spp=4, aov=("normal", "uv", "depth"))
    out.update({f"render_{k}": v for k, v in frame.items()})
    height = rng.random((40, 56), dtype=np.float32)
    out["emboss"] = wrinkle.emboss(height, azimuth=30.0, elevation=40.0)
    normals = wrinkle.normal_map(height, strength=2.0)
    out["normal_map"] = normals
    out["heights"] = wrinkle.height_from_normals(normals)
    points = (rng.random((4000, 3)) * 10.0).astype(np.float32)
    out["perlin"] = wrinkle.noise.perlin(points)
    out["fbm"] = wrinkle.noise.fbm(points)
    out["marble"] = wrinkle.noise.marble(points)
    texture = wrinkle.Texture(rng.random((32, 48, 4), dtype=np.float32), srgb=False)
    uv = rng.random((800, 2), dtype=np.float32)
    footprint = np.tile(np.float32([0.05, 0.01, -0.004, 0.02]), (800, 1))
    for f in ("nearest", "bilinear", "trilinear", "aniso", "ewa"):
        out[f"texture_{f}"] = texture.sample(uv, footprint, filter=f)
    out["grid"] = wrinkle.bumpgen.grid(64, 64)
    return out


if __name__ == "__main__":
    np.savez(sys.argv[1], build=np.array(wrinkle.build_level), **results())
