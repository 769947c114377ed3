"""Noise and patterns: Perlin's published values, lattice zeros, sums against their definition, bakes
against the CLI."""

import numpy as np
import pytest

import wrinkle


def test_perlins_published_value():
    # Perlin's reference ImprovedNoise: noise(3.14, 42, 7) = 0.13691995878400012.
    assert np.isclose(wrinkle.noise.perlin([3.14, 42.0, 7.0], variant="improved")[0], 0.13691995878400012, atol=2e-6)


def hashed_noise(points, seed=0):
    """The default noise as docs/procedural.md describes it, in float64: Perlin's improved noise whose corner
    gradient is the top four bits of ((seed' ^ i*PX ^ j*PY ^ k*PZ) * MIX) mod 2^32, seed' the high half of the
    first SplitMix64 output of the seed."""
    m64, m32 = (1 << 64) - 1, (1 << 32) - 1
    s = (seed + 0x9E3779B97F4A7C15) & m64
    s = ((s ^ (s >> 30)) * 0xBF58476D1CE4E5B9) & m64
    s = ((s ^ (s >> 27)) * 0x94D049BB133111EB) & m64
    seed32 = (s ^ (s >> 31)) >> 32
    primes, mix = (501125321, 1136930381, 1720413743), 0x27D4EB2D

    def grad(h, x, y, z):
        u = x if h < 8 else y
        v = y if h < 4 else (x if h in (12, 14) else z)
        return (u if h & 1 == 0 else -u) + (v if h & 2 == 0 else -v)

    def fade(t):
        return t * t * t * (t * (t * 6 - 15) + 10)

    out = []
    for x, y, z in points:
        i, j, k = int(np.floor(x)), int(np.floor(y)), int(np.floor(z))
        fx, fy, fz = x - i, y - j, z - k
        n = {}
        for c in range(8):
            a, b, d = c & 1, c >> 1 & 1, c >> 2
            v = seed32 ^ ((i + a) * primes[0] & m32) ^ ((j + b) * primes[1] & m32) ^ ((k + d) * primes[2] & m32)
            n[c] = grad(((v * mix) & m32) >> 28, fx - a, fy - b, fz - d)
        u, v, w = fade(fx), fade(fy), fade(fz)
        lerp = lambda t, p, q: p + t * (q - p)
        near = lerp(v, lerp(u, n[0], n[1]), lerp(u, n[2], n[3]))
        far = lerp(v, lerp(u, n[4], n[5]), lerp(u, n[6], n[7]))
        out.append(lerp(w, near, far))
    return np.array(out)


def test_the_default_noise_is_the_documented_hash():
    p = (np.random.default_rng(3).random((300, 3)) * 80 - 40).astype(np.float32)
    assert np.allclose(wrinkle.noise.perlin(p), hashed_noise(p.astype(np.float64)), atol=2e-6)
    assert np.allclose(wrinkle.noise.perlin(p, variant="hashed"), wrinkle.noise.perlin(p))
    assert not np.allclose(wrinkle.noise.perlin(p, variant="improved"), wrinkle.noise.perlin(p), atol=0.05)


def test_noise_is_zero_on_the_lattice():
    rng = np.random.default_rng(0)
    lattice = rng.integers(-50, 50, (1000, 3)).astype(np.float32)
    assert np.all(wrinkle.noise.perlin(lattice) == 0)
    assert np.all(wrinkle.noise.perlin(lattice[:, :2]) == 0)


def test_sums_follow_their_definition():
    rng = np.random.default_rng(1)
    p = (rng.random((5000, 3)) * 20).astype(np.float32)
    one = wrinkle.noise.fbm(p, octaves=1)
    assert np.allclose(one, wrinkle.noise.perlin(p), atol=1e-6)
    # Octave i reads noise(f_i p + i * shift), the shift decorrelating the octaves at the origin.
    second = 2 * p + np.array([0.379, 0.617, 0.853], np.float32)
    two = wrinkle.noise.fbm(p, octaves=2, lacunarity=2.0, gain=0.5)
    expect = wrinkle.noise.perlin(p) + 0.5 * wrinkle.noise.perlin(second)
    assert np.allclose(two, expect, atol=1e-5)
    t = wrinkle.noise.turbulence(p, octaves=2)
    assert np.allclose(t, np.abs(wrinkle.noise.perlin(p)) + 0.5 * np.abs(wrinkle.noise.perlin(second)), atol=1e-5)
    assert not np.array_equal(wrinkle.noise.perlin(p, seed=7), wrinkle.noise.perlin(p))


def test_patterns_return_t_and_colour():
    p = np.random.default_rng(2).random((100, 3)).astype(np.float32)
    t, rgb = wrinkle.noise.pattern("marble", p)
    assert t.shape == (100,) and rgb.shape == (100, 3)
    assert np.all((t >= 0) & (t <= 1))
    assert np.array_equal(wrinkle.noise.marble(p), rgb)
    # A checker of scale 1 has cells of 0.5: t is 0 or 1 for point samples.
    t, _ = wrinkle.noise.pattern("checker", np.array([[0.25, 0.25], [0.75, 0.25]], np.float32), scale=1.0)
    assert sorted(t.tolist()) == [0.0, 1.0]
    names = [k for k, _ in wrinkle.noise.kinds()]
    assert "marble" in names and "clouds" in names


def test_bake_matches_the_cli(cli, tmp_path):
    out = tmp_path / "m.exr"
    cli("texture", "marble", "-o", out, "--size", "48x32", "--seed", 3, "--octaves", 4)
    t, rgb = wrinkle.noise.bake("marble", 48, 32, seed=3, octaves=4)
    assert t.shape == (32, 48) and rgb.shape == (32, 48, 3)
    exr = wrinkle.read_exr(out)
    assert np.array_equal(np.stack([exr["R"], exr["G"], exr["B"]], axis=-1), rgb)


def test_tileable_bakes_join_at_the_edges():
    t, _ = wrinkle.noise.bake("fbm", 64, 64, tileable=True, scale=4)
    wrapped = np.abs(t[:, 0] - t[:, -1]).mean()
    inner = np.abs(np.diff(t, axis=1)).mean()
    assert wrapped < 2 * inner


def test_bad_noise_arguments():
    with pytest.raises(ValueError, match="points"):
        wrinkle.noise.perlin(np.zeros((4, 4), np.float32))
    with pytest.raises(ValueError, match="NaN"):
        wrinkle.noise.perlin(np.full((4, 3), np.nan))
    with pytest.raises(ValueError, match="octaves"):
        wrinkle.noise.fbm(np.zeros((4, 3)), octaves=0)
    with pytest.raises(ValueError, match="variant"):
        wrinkle.noise.perlin(np.zeros((4, 3)), variant="simplex")
    with pytest.raises(ValueError, match="unknown option"):
        wrinkle.noise.pattern("marble", np.zeros((4, 3)), colour=[1, 1, 1])
    with pytest.raises(ValueError, match="kind"):
        wrinkle.noise.bake("plasma", 8, 8)
    with pytest.raises(ValueError, match="size"):
        wrinkle.noise.bake("fbm", 10**6, 10**6)
    with pytest.raises(ValueError, match="cannot tile"):
        wrinkle.noise.bake("wood", 8, 8, tileable=True)
