"""Textures: every filter against analytic values, the pyramid against box averages, batches against
single lookups."""

import numpy as np
import pytest

import wrinkle

FILTERS = ["nearest", "bilinear", "bicubic", "bspline", "gaussian", "lanczos", "mip-nearest", "trilinear",
           "ripmap", "sat", "aniso", "ewa", "reference"]


def test_a_constant_texture_reads_its_value_through_every_filter():
    tex = wrinkle.Texture(np.full((16, 16, 4), 0.25, np.float32))
    rng = np.random.default_rng(0)
    uv = rng.random((64, 2)).astype(np.float32) * 3
    fp = (rng.random((64, 4)).astype(np.float32) - 0.5) * 0.2
    for f in FILTERS:
        out = tex.sample(uv, fp, filter=f)
        assert out.shape == (64, 4) and out.dtype == np.float32
        assert np.allclose(out, 0.25, atol=1e-5), f


def test_bilinear_at_texel_centres_and_between():
    pixels = np.array([[[0, 0, 0, 1], [1, 1, 1, 1]], [[0, 0, 0, 1], [1, 1, 1, 1]]], np.float32)
    tex = wrinkle.Texture(pixels, wrap="clamp", filter="bilinear")
    # Texel centres at s = 0.25 and 0.75; halfway between them the mean.
    out = tex.sample(np.array([[0.25, 0.5], [0.75, 0.5], [0.5, 0.5], [0.375, 0.5]], np.float32))
    assert np.allclose(out[:, 0], [0.0, 1.0, 0.5, 0.25], atol=1e-6)


def test_a_footprint_over_the_whole_texture_reads_its_mean():
    rng = np.random.default_rng(3)
    pixels = rng.random((64, 64, 4)).astype(np.float32)
    tex = wrinkle.Texture(pixels, mip_filter="box")
    mean = pixels.reshape(-1, 4).mean(axis=0)
    big = np.array([[1.0, 0.0, 0.0, 1.0]], np.float32)
    for f in ("trilinear", "sat", "ewa", "ripmap"):
        assert np.allclose(tex.sample([[0.5, 0.5]], big, filter=f)[0], mean, atol=0.02), f


def test_mipmap_levels_are_box_averages():
    rng = np.random.default_rng(4)
    pixels = rng.random((32, 16, 4)).astype(np.float32)
    levels = wrinkle.Texture(pixels, mip_filter="box").mipmap()
    assert [l.shape for l in levels] == [(32, 16, 4), (16, 8, 4), (8, 4, 4), (4, 2, 4), (2, 1, 4), (1, 1, 4)]
    assert np.allclose(levels[0], pixels)
    # With alpha, colour is averaged weighted by alpha (premultiplied) and stored straight; alpha is the box.
    blocks = pixels.reshape(16, 2, 8, 2, 4)
    alpha = blocks[..., 3:].mean(axis=(1, 3))
    colour = (blocks[..., :3] * blocks[..., 3:]).mean(axis=(1, 3)) / alpha
    assert np.allclose(levels[1], np.concatenate([colour, alpha], axis=-1), atol=1e-5)
    flat = pixels.reshape(-1, 4)
    top = np.append((flat[:, :3] * flat[:, 3:]).mean(axis=0) / flat[:, 3].mean(), flat[:, 3].mean())
    assert np.allclose(levels[-1][0, 0], top, atol=1e-5)
    # Opaque: the plain box average.
    pixels[..., 3] = 1.0
    levels = wrinkle.Texture(pixels, mip_filter="box").mipmap()
    assert np.allclose(levels[1], pixels.reshape(16, 2, 8, 2, 4).mean(axis=(1, 3)), atol=1e-6)


def test_srgb_bytes_are_decoded_to_linear():
    pixels = np.full((4, 4, 3), 128, np.uint8)
    srgb = wrinkle.Texture(pixels, srgb=True).sample([0.5, 0.5])
    linear = wrinkle.Texture(pixels, srgb=False).sample([0.5, 0.5])
    c = 128 / 255
    assert np.allclose(srgb[:3], ((c + 0.055) / 1.055) ** 2.4, atol=1e-4)
    assert np.allclose(linear[:3], c, atol=1e-6) and np.isclose(srgb[3], 1.0)


def test_a_batch_equals_single_lookups_and_runs_in_parallel_sizes():
    rng = np.random.default_rng(5)
    tex = wrinkle.Texture((rng.random((128, 128, 4)) * 255).astype(np.uint8), filter="ewa")
    n = 40000
    uv = rng.random((n, 2)).astype(np.float32)
    fp = (rng.random((n, 4)).astype(np.float32) - 0.5) * 0.05
    batch = tex.sample(uv, fp)
    picks = rng.integers(0, n, 50)
    for i in picks:
        assert np.array_equal(tex.sample(uv[i], fp[i]), batch[i])
    assert np.array_equal(tex.sample(np.asfortranarray(uv), np.asfortranarray(fp)), batch)


def test_bad_texture_arguments():
    with pytest.raises(ValueError, match="filter"):
        wrinkle.Texture(np.zeros((4, 4, 4), np.float32), filter="blur")
    with pytest.raises(ValueError, match="wrap"):
        wrinkle.Texture(np.zeros((4, 4, 4), np.float32), wrap="tile")
    with pytest.raises(ValueError, match="shape"):
        wrinkle.Texture(np.zeros((4, 4, 2), np.float32))
    with pytest.raises(ValueError, match="NaN"):
        wrinkle.Texture(np.full((4, 4, 4), np.nan, np.float32))
    with pytest.raises(TypeError):
        wrinkle.Texture(np.zeros((4, 4, 4), np.int32))
    tex = wrinkle.Texture(np.zeros((4, 4, 4), np.float32))
    with pytest.raises(ValueError, match="footprint"):
        tex.sample(np.zeros((3, 2), np.float32), np.zeros((2, 4), np.float32))
    with pytest.raises(ValueError, match="uv"):
        tex.sample(np.zeros((3, 3), np.float32))
    with pytest.raises(ValueError, match="max_aniso"):
        tex.sample([0.5, 0.5], max_aniso=0.0)
    with pytest.raises(ValueError, match="lod_bias"):
        wrinkle.Texture(np.zeros((4, 4, 4), np.float32), lod_bias=float("nan"))


def test_lod_bias_scales_the_footprint():
    """A bias of -1 reads as the footprint halved, exactly (OpenGL's GL_TEXTURE_LOD_BIAS on the level)."""
    rng = np.random.default_rng(3)
    pixels = rng.integers(0, 256, (64, 64, 4), dtype=np.uint8)
    plain, finer = wrinkle.Texture(pixels), wrinkle.Texture(pixels, lod_bias=-1.0)
    uv = rng.random((200, 2), dtype=np.float32)
    fp = (rng.random((200, 4), dtype=np.float32) - 0.5) * np.float32(0.2)
    assert np.array_equal(finer.sample(uv, fp), plain.sample(uv, fp * np.float32(0.5)))
    assert not np.array_equal(finer.sample(uv, fp), plain.sample(uv, fp))
