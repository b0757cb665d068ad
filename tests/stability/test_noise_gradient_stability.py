"""Gradient and cellular noise at huge coordinates (beyond 2^24, up to 1e30): the GLSL library
stays finite and inside its bounds, and the numpy twin stays finite.
"""

from __future__ import annotations

import numpy as np

from app.sim.noise import gradient
from tests.helpers.noise import HUGE_EXPR, _huge_twin, f32, glsl


def test_huge_coordinates_stay_finite_and_bounded(noise_probe):
    # beyond 2^24 every float32 is an integer: the GPU's wrap by 6 or 3 is inexact there (the
    # noise is meaningless anyway) but must stay in range: finite, bounded values, no crash
    pts = f32([(1e10, -1e10, 3e9), (-1e30, 1e30, 1e20), (2.0**31, 0.5, -0.5),
               (-(2.0**31), 2.0**40, 7.0)])
    got = glsl(noise_probe, HUGE_EXPR, pts)
    assert np.isfinite(got).all()
    assert np.abs(got[:, [0, 1, 3]]).max() <= gradient.PERLIN3_BOUND
    assert got[:, 2].min() >= 0.0 and got[:, 2].max() < 2.0
    assert np.isfinite(_huge_twin(pts)).all()
    assert np.abs(glsl(noise_probe, "PerlinNoise3(P.xyz)", pts)[:, 0]
                  - gradient.perlin3(*pts.T)).max() < 1e-6
