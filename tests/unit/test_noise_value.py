"""The procedural-wood thesis's value noise (spec/004 §6 criteria 2 and 6–9): the numpy twin
against the properties the digest derives.
"""

from __future__ import annotations

import numpy as np
import pytest

from app.sim.noise.value import ValueNoise, ease_in, ease_in_out


def test_ease_curves():  # criterion 2
    assert (ease_in_out(0.0) == 0 and ease_in_out(1.0) == 1
            and ease_in_out(0.5) == pytest.approx(0.5))
    assert ease_in_out(-3.0) == 0 and ease_in_out(7.0) == 1
    h = 1e-6
    assert abs(ease_in_out(h) - ease_in_out(0.0)) / h < 1e-4
    assert abs(ease_in_out(1.0) - ease_in_out(1.0 - h)) / h < 1e-4
    t = np.linspace(0, 1, 11)
    assert np.allclose(ease_in(t), t * t)


def test_periodic_in_256_and_no_seam_at_zero():  # criterion 6
    twin = ValueNoise(1)
    rng = np.random.default_rng(7)
    pts = rng.uniform(-40, 40, size=(5000, 3))
    for k in range(3):
        shifted = pts.copy()
        shifted[:, k] += 256.0
        assert np.abs(twin.noise3(shifted) - twin.noise3(pts)).max() <= 1e-4
    eps = 1e-5
    for k in range(3):
        a = np.zeros((200, 3)) + rng.uniform(-5, 5, (200, 3))
        a[:, k] = -eps
        b = a.copy()
        b[:, k] = eps
        assert np.abs(twin.noise3(a) - twin.noise3(b)).max() < 1e-3


def test_c1_continuity_across_cell_faces():  # criterion 7
    twin = ValueNoise(1)
    rng = np.random.default_rng(8)
    eps = 1e-4
    for k in range(3):
        pts = rng.uniform(0, 30, size=(2000, 3))
        pts[:, k] = np.floor(pts[:, k])  # on a lattice plane
        lo, hi = pts.copy(), pts.copy()
        lo[:, k] -= eps
        hi[:, k] += eps
        assert np.abs(twin.noise3(hi) - twin.noise3(lo)).max() < 1e-3
        slope = (twin.noise3(hi) - twin.noise3(lo)) / (2 * eps)
        assert np.abs(slope).max() < 1e-2  # the fade's derivative vanishes on the faces


def test_octave_formula():  # criterion 8
    twin = ValueNoise(2)
    rng = np.random.default_rng(9)
    p = rng.uniform(-20, 20, size=(3000, 3))
    assert np.allclose(twin.octaves(p, 1), twin.noise3(p), atol=1e-12)
    for d in (2, 3, 5, 8):
        explicit = (sum(2.0**-i * twin.noise3(2.0**i * p) for i in range(d))
                    / sum(2.0**-i for i in range(d)))
        assert np.abs(twin.octaves(p, d) - explicit).max() <= 1e-5
    assert (np.allclose(twin.octaves(p, 0), twin.octaves(p, 1))
            and np.allclose(twin.octaves(p, 12), twin.octaves(p, 8)))


def test_statistics_per_depth():  # criterion 9
    twin = ValueNoise(1)
    rng = np.random.default_rng(10)
    p = rng.uniform(-50, 50, size=(6000, 3))
    expected = {1: 0.185, 3: 0.121, 8: 0.107}
    tol = {1: 0.02, 3: 0.015, 8: 0.015}
    stds = []
    for d in range(1, 9):
        v = twin.octaves(p, d)
        stds.append(v.std(axis=0).mean())
        assert np.all(np.abs(v.mean(axis=0) - 0.5) < 0.02)
        if d in expected:
            assert np.all(np.abs(v.std(axis=0) - expected[d]) < tol[d]), (d, v.std(axis=0))
        c = np.corrcoef(v.T)
        assert np.abs(c[np.triu_indices(3, 1)]).max() < 0.1
    assert all(b <= a + 2e-3 for a, b in zip(stds, stds[1:]))
    raw = twin.table.reshape(-1, 3)
    assert abs(raw.std() - 0.289) < 0.005
