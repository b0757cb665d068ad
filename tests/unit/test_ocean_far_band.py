"""The ocean far plane's band of screen rows (app/effects/ocean/deferred.py: far_band) against
a per-pixel evaluation of the far plane's own test (glsl/ocean/far_inputs.frag): every row with a
pixel whose ray meets y = 0 beyond the mesh lies in the band, and the band is not much wider."""

from __future__ import annotations

import numpy as np
import pytest

from app.effects.ocean.deferred import far_band
from app.sim.camera import Camera


def rows_needed(cam: Camera, w: int, h: int, far_start: float) -> np.ndarray:
    """Row indices (0 at the top) where some pixel centre's ray meets the sea beyond far_start."""
    d = cam.ray_directions(w, h)
    down = -d[..., 1]
    with np.errstate(divide="ignore"):
        reach = cam.position[1] * np.hypot(d[..., 0], d[..., 2]) / down
    hit = (down > 1e-6) & (reach >= far_start)
    return np.nonzero(hit.any(axis=1))[0]


@pytest.mark.parametrize("height,pitch,yaw", [(4.0, -2.0, 262.0), (4.0, 0.0, 10.0),
                                               (400.0, -10.0, 30.0), (2000.0, -30.0, 200.0),
                                               (50.0, 20.0, 0.0), (4.0, -20.0, 90.0),
                                               (10000.0, -60.0, 45.0)])
def test_band_holds_every_row_the_far_plane_shows(height, pitch, yaw):
    w, h, far_start = 160, 90, 528.0
    cam = Camera(position=(0.0, height, 0.0), yaw=yaw, pitch=pitch, fov=60.0)
    need = rows_needed(cam, w, h, far_start)
    band = far_band(cam, w / h, h, far_start)
    if need.size == 0:
        return
    assert band is not None
    lo, hi = band
    centres = 1.0 - (need + 0.5) / h * 2.0  # NDC y of the rows' centres (row 0 at the top)
    assert np.all((centres > lo) & (centres < hi))
    assert (hi - lo) * h / 2.0 <= need.size + 2 * 2 + 1  # the rows, the margins and one more


@pytest.mark.parametrize("height,pitch", [(4.0, 89.9), (4.0, -89.9), (0.0, -10.0), (-3.0, 0.0)])
def test_band_is_empty_when_no_ray_reaches_past_the_mesh(height, pitch):
    cam = Camera(position=(0.0, height, 0.0), yaw=0.0, pitch=pitch, fov=60.0)
    assert far_band(cam, 16 / 9, 90, 2640.0) is None
    if height > 0:
        assert rows_needed(cam, 160, 90, 2640.0).size == 0
