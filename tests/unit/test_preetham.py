"""The Preetham analytic sky (spec/001 §1.8; Preetham, Shirley & Smits 1999) on numpy: the twin
(app/sim/preetham.py) against values worked by hand from the paper's appendix A.2 constants
(the paper prints the formulas and constants, not tables of results), and the sky's colour.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.sim import preetham as model

# ---- the paper's formulas -----------------------------------------------------------------------

def test_zenith_formulas_against_hand_worked_values():
    # Y_z = (4.0453 T − 4.9710) tan χ − 0.2155 T + 2.4192, χ = (4/9 − T/120)(π − 2θs)
    # T = 2, θs = 0: χ = 0.427778 π = 1.343904, tan χ = 4.331476 → 3.1196 · 4.331476 + 1.9882
    assert model.zenith_luminance(2.0, 0.0) == pytest.approx(15.50067, abs=1e-4)
    # θs = 90°: χ = 0, so Y_z = 2.4192 − 0.2155 T exactly
    for t in (2.0, 5.0, 10.0):
        assert model.zenith_luminance(t, math.pi / 2) == pytest.approx(2.4192 - 0.2155 * t,
                                                                       abs=1e-12)
    # x_z, y_z at θs = 0 are the last column: [T² T 1]·(0, 0.00394, 0.25886) and
    # (0, 0.00516, 0.26688)
    assert model.zenith_chromaticity(2.0, 0.0) == pytest.approx([2 * 0.00394 + 0.25886,
                                                                 2 * 0.00516 + 0.26688])
    # θs = 1 rad: the row sums; T² row of M_x sums to 0 → x_z = 2·0.00666 + 0.22435
    assert model.zenith_chromaticity(2.0, 1.0)[0] == pytest.approx(0.23767, abs=1e-9)
    # Perez coefficients at T = 2 (A_Y = 0.1787·2 − 1.4630, …)
    k = model.perez_coefficients(2.0)
    assert k[0] == pytest.approx([-1.1056, -0.2833, 5.2797, -2.3359, 0.2363])
    assert k[1][0] == pytest.approx(-0.2978) and k[2][3] == pytest.approx(-1.7419)


def test_zenith_of_the_distribution_is_the_zenith_value():
    # eq. 4 at θ = 0: F(0, θs)/F(0, θs) = 1, so the sky at the zenith is (x_z, y_z, Y_z)
    for t, elev in ((2.0, 70.0), (4.5, 30.0), (10.0, 5.0)):
        sun = model.sun_direction(elev, 123.0)
        xyY = model.sky_xyY(np.array([0.0, 1.0, 0.0]), sun, t)
        ts = math.radians(90.0 - elev)
        assert xyY[:2] == pytest.approx(model.zenith_chromaticity(t, ts), rel=1e-9)
        assert xyY[2] == pytest.approx(model.zenith_luminance(t, ts), rel=1e-9)


def test_xyY_to_srgb_white_point():
    # D65 white (x, y) = (0.3127, 0.3290) at Y = 1 maps to RGB ≈ (1, 1, 1)
    rgb = model.XYZ_to_linear_srgb(model.xyY_to_XYZ(np.array([0.3127, 0.3290, 1.0])))
    assert rgb == pytest.approx([1.0, 1.0, 1.0], abs=2e-3)


# ---- behaviour ----------------------------------------------------------------------------------

def test_bluer_at_zenith_than_horizon_at_noon():
    sun = model.sun_direction(75.0, 180.0)
    zen = model.sky_radiance(np.array([0.0, 1.0, 0.0]), sun, 2.5)
    hor = model.sky_radiance(model.sun_direction(1.0, 0.0), sun, 2.5)  # horizon, away from the sun

    def blue(c):
        return c[2] / c.sum()

    assert blue(zen) > blue(hor) + 0.05


# ---- the sea's ambient (beyond the paper) -------------------------------------------------------

@pytest.mark.parametrize("elev,turbidity", [(60.0, 2.5), (10.0, 6.0), (1.0, 2.0)])
def test_sky_ambient_is_the_cosine_weighted_mean_of_the_sky(elev, turbidity):
    sun = model.sun_direction(elev, 140.0)
    coarse = model.sky_ambient_rgb(sun, turbidity)
    fine = model.sky_ambient_rgb(sun, turbidity, elevations=96, azimuths=192)
    # 12 × 24 directions are within a few per cent of a fine quadrature
    assert coarse == pytest.approx(fine, rel=0.04)
    # a mean: between the darkest and the brightest of the upper hemisphere's directions
    d = np.random.default_rng(2).normal(size=(4000, 3))
    d[:, 1] = np.abs(d[:, 1])
    rgb = model.sky_rgb(d / np.linalg.norm(d, axis=1, keepdims=True), sun, turbidity)
    assert (coarse > rgb.min(axis=0)).all() and (coarse < rgb.max(axis=0)).all()
    # in the picture's units: exposure and twilight, like the sky itself
    assert model.sky_ambient(sun, turbidity, 0.1) == pytest.approx(0.1 * coarse)
    assert model.sky_ambient(model.sun_direction(-7.0, 0.0), turbidity, 0.1) == pytest.approx(0)


def test_sea_below_the_horizon_only_and_toward_the_horizon_colour():
    from app.sim.sea_plane import SeaPlane
    sun = model.sun_direction(30.0, 180.0)
    sea = SeaPlane(sky_ambient=tuple(model.sky_ambient(sun)), light_dir=tuple(sun),
                   light_radiance=(0.8, 0.7, 0.5), eye_height=300.0)
    d = np.array([[0.0, 0.5, -0.866], [0.0, -1e-5, -1.0], [0.0, -0.7, -0.714]])
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    with_sea = model.sky_radiance(d, sun, sea=sea)
    without = model.sky_radiance(d, sun)
    assert with_sea[0] == pytest.approx(without[0])        # the sky above is unchanged
    assert with_sea[1] == pytest.approx(without[1], rel=1e-3)  # the horizon meets the sky
    assert with_sea[2].sum() < 0.5 * without[2].sum()      # a darker sea below
