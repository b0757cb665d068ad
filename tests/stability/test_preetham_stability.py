"""The Preetham sky with the sun below the horizon, down to the nadir: no NaN, no negative
value, equal to the numpy twin, and dark (no main light) once the sun is 6° below.
"""

from __future__ import annotations

import numpy as np
import pytest

from app.sim.camera import Camera
from tests.helpers.preetham import render


@pytest.mark.parametrize("elev", [-90.0, -45.0, -6.0, -3.0, -0.01, 0.0])
def test_sun_below_horizon_no_nan_and_fades(preetham_rig, elev):
    cam = Camera(position=(0, 2, 0), yaw=0.0, pitch=0.0, fov=120.0)
    img, twin, frame = render(preetham_rig, cam, {"preetham.sun_elevation": elev,
                                         "preetham.sun_azimuth": 0.0})
    assert np.isfinite(img).all() and (img >= 0.0).all()
    assert np.allclose(img, twin, rtol=2e-3, atol=1e-6)
    if elev <= -6.0:
        assert img.max() == 0.0
        assert frame.main_light.intensity == 0.0
    assert np.isfinite(frame.main_light.color).all()
