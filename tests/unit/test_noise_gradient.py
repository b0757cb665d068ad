"""Gradient and cellular noise (issue 3, items 1 and 4) on numpy: Perlin's permutation and
reference values, the quintic fade, the PCG hash, the fractal sums and the Perlin–Worley
formula (spec/001 §1.1 and B2–B5).
"""

from __future__ import annotations

import numpy as np
import pytest

from app.sim.noise import cellular, fractal, gradient
from tests.helpers.noise import _reference_noise

RNG = np.random.default_rng(20021)


def test_reference_permutation_and_seeds():
    ref = gradient.permutation(None)
    assert sorted(ref.tolist()) == list(range(256))
    assert ref[:6].tolist() == [151, 160, 137, 91, 90, 15] and ref[-1] == 180
    assert np.array_equal(gradient.permutation(0), ref)
    other = gradient.permutation(5)
    assert sorted(other.tolist()) == list(range(256)) and not np.array_equal(other, ref)
    assert np.array_equal(other, np.random.default_rng(5).permutation(256))
    with pytest.raises(ValueError, match="negative"):
        gradient.permutation(-1)


def test_perlin3_reproduces_the_reference_implementation():
    # Published values of ImprovedNoise (Java, double precision), to the last bit.
    assert gradient.perlin3(3.14, 42, 7) == 0.13691995878400012
    assert gradient.perlin3(-4.2, 10, 6) == 0.14208000000000043
    assert gradient.perlin3(0.5, 0.5, 0.5) == -0.25
    pts = RNG.uniform(-300, 300, (400, 3))
    twin = gradient.perlin3(*pts.T)
    scalar = np.array([_reference_noise(*q) for q in pts])
    assert np.array_equal(twin, scalar)  # bit for bit, negative and > 256 coordinates included


def test_quintic_fade_makes_the_twin_c2(monkeypatch):
    h = 2.0**-10
    base = RNG.uniform(-20, 20, (300, 3))
    base[:, 0] = np.round(base[:, 0])  # on faces x = integer

    def second_derivative_jump():
        xs = base[:, 0][None] + np.arange(-2, 3)[:, None] * h
        v = gradient.perlin3(xs, base[:, 1][None], base[:, 2][None])
        second = (v[2:] - 2 * v[1:-1] + v[:-2]) / h**2  # centred at -h, 0, +h
        return np.abs(second[2] - second[0]).max()

    # the second derivative just left of the face equals the one just right of it (C2)
    assert second_derivative_jump() < 0.5  # O(2h·|n'''|) ~ 0.15
    # with the 1985 cubic fade 3t^2 - 2t^3 the same measure sees the jump in it
    monkeypatch.setattr(gradient, "fade", lambda t: t * t * (3.0 - 2.0 * t))
    assert second_derivative_jump() > 5.0  # ~15


# ---- Worley properties ---------------------------------------------------------------------------

def test_hash_is_pcg4d_in_uint32():
    x, y, z, w = cellular.pcg4d(np.array([0, -1]), np.array([0, 7]), np.array([0, 2**31]),
                                np.array([0, 5]))
    for arr in (x, y, z, w):
        assert arr.dtype == np.uint32
    # first element by hand in Python integers (mod 2^32)
    m = 0xFFFFFFFF
    v = [(1013904223) & m] * 4
    for i in range(2):
        v[0] = (v[0] + v[1] * v[3]) & m
        v[1] = (v[1] + v[2] * v[0]) & m
        v[2] = (v[2] + v[0] * v[1]) & m
        v[3] = (v[3] + v[1] * v[2]) & m
        if i == 0:
            v = [a ^ (a >> 16) for a in v]
    assert [int(x[0]), int(y[0]), int(z[0]), int(w[0])] == v
    ox, oy, oz = cellular.feature_offset3(np.arange(-50, 50), 3, -9)
    for o in (ox, oy, oz):
        assert o.min() >= 0.0 and o.max() < 1.0
        assert np.array_equal(o, o.astype(np.float32))  # exact in float32: bit-identical on the GPU


# ---- fractal sums --------------------------------------------------------------------------------

def test_fbm_is_the_normalised_octave_sum():
    pts = RNG.uniform(-10, 10, (2000, 3))
    octaves, lac, gain = 5, 2.0, 0.55
    explicit = sum(gain**i * gradient.perlin3(*(pts * lac**i).T, seed=4) for i in range(octaves))
    norm = sum(gain**i for i in range(octaves))
    got = fractal.perlin_fbm3(*pts.T, octaves=octaves, lacunarity=lac, gain=gain, seed=4)
    assert np.allclose(got, explicit / norm, atol=1e-14)
    turb = sum(gain**i * np.abs(gradient.perlin3(*(pts * lac**i).T, seed=4))
               for i in range(octaves)) / norm
    assert np.allclose(fractal.perlin_turbulence3(*pts.T, octaves, lac, gain, seed=4), turb,
                       atol=1e-14)
    wor = sum(gain**i * cellular.worley_inverted_f1(cellular.worley3(*(pts * lac**i).T, seed=4)[0])
              for i in range(3)) / sum(gain**i for i in range(3))
    assert np.allclose(fractal.worley_fbm3(*pts.T, 3, lac, gain, seed=4), wor, atol=1e-14)
    # one octave is the base noise (spec/001 B5); H gives gain = L^−H
    assert np.array_equal(fractal.perlin_fbm3(*pts.T, octaves=1), gradient.perlin3(*pts.T))
    assert np.allclose(fractal.perlin_fbm2(pts[:, 0], pts[:, 1], 4, 2.0, H=1.0),
                       fractal.perlin_fbm2(pts[:, 0], pts[:, 1], 4, 2.0, gain=0.5), atol=0)
    assert fractal.gain_for(3.0, H=0.5) == pytest.approx(3.0**-0.5)
    assert fractal.gain_for() == 0.5
    with pytest.raises(ValueError, match="not both"):
        fractal.gain_for(2.0, gain=0.5, H=1.0)
    with pytest.raises(ValueError, match="octaves"):
        fractal.perlin_fbm3(0.1, 0.2, 0.3, octaves=0)
    with pytest.raises(ValueError, match="integer lacunarity"):
        fractal.perlin_fbm3_periodic(0.1, 0.2, 0.3, 4, lacunarity=2.5)


def test_perlin_worley_formula():
    p = np.linspace(-1.2, 1.2, 25)[:, None]
    w = np.linspace(0.0, 1.0, 11)[None]
    got = fractal.perlin_worley_remap(p, w)
    p01 = np.clip(0.5 + 0.5 * p, 0, 1)
    remap = 0.0 + (p01 - (w - 1.0)) * (1.0 - 0.0) / (1.0 - (w - 1.0))  # remap(P, W − 1, 1, 0, 1)
    assert np.allclose(got, np.clip(remap, 0, 1), atol=1e-15)
    assert np.allclose(fractal.perlin_worley_remap(p, 1.0), p01[:, 0][:, None])  # W = 1 → P
    assert np.allclose(fractal.perlin_worley_remap(p, 0.0), (p01 + 1) / 2)     # W = 0 → (P+1)/2
    assert got.min() >= 0.0 and got.max() <= 1.0
