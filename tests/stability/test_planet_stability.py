"""The `planet` scene swept to where its methods could fail (issue 4 item 7): sun from the zenith
to 20° below the horizon, camera from the sea surface to 600 km and anywhere in space, looking
up, down and along the horizon, G up to 0.999, methods 1–4: finite, non-negative, bounded, and
no dark band above the horizon. Harness and conventions: tests/helpers/planet.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.sim import atmosphere as atm
from tests.helpers.planet import (
    DARK_SPACE,
    MODEL,
    SIZE,
    SPACE_VIEW,
    THESIS_METHODS,
    TOP,
    PlanetHarness,
    R,
    camera,
    dark_band_rows,
    horizon_rows,
    luminance,
    planet_centred,
    rays,
    sun_sets,
)


@pytest.fixture(scope="module")
def planet(gl_ctx):
    h = PlanetHarness(gl_ctx)
    yield h
    h.gpu.release()


# =============================================================================================
# Stability sweeps (issue 4 item 7)
# =============================================================================================

SWEEP_SUNS = (90.0, 30.0, 5.0, 0.0, -5.0, -20.0)
SWEEP_ALTITUDES = (0.0, 2.0, 1000.0, 30_000.0, 59_900.0, 60_000.0, 100_000.0, 600_000.0)


def test_sweep_sun_and_altitude_is_finite_and_horizon_has_no_dark_band(planet):
    """Method 2: sun from the zenith to 20° below the horizon, camera from 0 m to 10 × the
    atmosphere's height, looking along its horizon (0–3° above it at 0.19° per row): finite,
    non-negative, and inside the atmosphere no row above the horizon darker than 25 % of the rows
    on either side."""
    size = (32, 64)
    for alt in SWEEP_ALTITUDES:
        dip = math.degrees(math.acos(R / (R + alt)))
        for sun_el in SWEEP_SUNS:
            cam = camera(pos=(0.0, alt, 60.0), yaw=180.0, pitch=1.5 - dip, fov=12.0)
            shot = planet.shoot(cam, size, {"planet.method": "lut", **sun_sets(sun_el, 0.0),
                                            **DARK_SPACE})
            assert np.all(np.isfinite(shot.rgb)) and shot.rgb.min() >= 0.0, (alt, sun_el)
            if alt >= TOP or sun_el < 0.0:
                continue   # above the top the limb is meant to be bright against black space
            rows, band = horizon_rows(cam, size, shot)
            rows = np.maximum(rows, 1.0 / 255.0)
            assert len(band) >= 5, (alt, sun_el)
            assert dark_band_rows(rows, band, 0.25) == [], (alt, sun_el, np.round(rows, 3))


@pytest.mark.parametrize("method", THESIS_METHODS)
def test_sweep_views_and_g_are_finite(planet, method):
    """Methods 1–3 looking up, down and along the horizon, G up to 0.999, sun above and below the
    horizon, from the sea surface to 600 km: no NaN/Inf, non-negative, bounded."""
    size = (32, 18)
    for alt in (0.0, 2.0, 59_999.0, 600_000.0):
        for pitch in (89.0, 0.0, -89.0):
            for sun_el, g in ((90.0, 0.999), (0.0, 0.76), (-20.0, 0.999), (45.0, 0.7)):
                cam = camera(pos=(0.0, alt, 60.0), yaw=30.0, pitch=pitch, fov=70.0)
                shot = planet.shoot(cam, size, {"planet.method": method, **sun_sets(sun_el, 200.0),
                                                "atmosphere.g": g})
                rgb = shot.rgb
                assert np.all(np.isfinite(rgb)) and rgb.min() >= 0.0, (method, alt, pitch, sun_el,
                                                                       g)
                assert rgb.max() < 1e4, (method, alt, pitch, sun_el, g)


def test_space_renders_from_anywhere_outside_the_atmosphere(planet):
    for pos in ((0.0, 61_000.0, 0.0), (0.0, 600_000.0, 0.0), (3.0e6, 4.0e6, -2.0e6),
                (0.0, 3.6e7, 0.0), (-2.0e7, -6.36e6, 1.0e7)):
        cam = camera(pos=pos, fov=60.0)
        cam.look_at_direction(np.array([0.0, -R, 0.0]) - np.array(pos))
        for method in THESIS_METHODS:
            shot = planet.shoot(cam, (48, 27), {"planet.method": method, **sun_sets(30.0, 180.0)})
            assert np.all(np.isfinite(shot.rgb)), (pos, method)
            assert luminance(shot.display).max() > 0.05, (pos, method)   # the planet is in view


def test_hillaire_space_view_and_sweep_are_finite(planet):
    cam = camera(**SPACE_VIEW)
    d = rays(cam, SIZE).reshape(-1, 3)
    miss = ~atm.atmosphere_segment(planet_centred(cam), d, None,
                                   MODEL).hit.reshape(SIZE[1], SIZE[0])
    shot = planet.shoot(cam, SIZE, {"planet.method": "hillaire", **sun_sets(30.0, 180.0),
                                    "planet.debug_view": "in_scatter"})
    assert np.all(np.isfinite(shot.rgb)) and shot.rgb[miss].max() < 1.0 / 255.0
    for alt in (0.0, 2.0, 59_999.0, 600_000.0):
        for pitch in (89.0, 0.0, -89.0):
            for sun_el, g in ((90.0, 0.999), (-20.0, 0.76)):
                cam = camera(pos=(0.0, alt, 60.0), yaw=30.0, pitch=pitch, fov=70.0)
                rgb = planet.shoot(cam, (32, 18), {"planet.method": "hillaire",
                                                   **sun_sets(sun_el, 200.0),
                                                   "atmosphere.g": g}).rgb
                assert np.all(np.isfinite(rgb)) and rgb.min() >= 0.0, (alt, pitch, sun_el, g)
