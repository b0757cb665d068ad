"""Flying from the ground to space is seamless: crossing the top of the atmosphere, or the
altitude where Hillaire's lookups hand over to marching, changes the image only a little."""

from __future__ import annotations

import numpy as np
import pytest

from app.colour import to_srgb8
from app.runtime import open_session, render_frames, scene_params


@pytest.fixture(scope="module")
def planet(gl_ctx):
    session = open_session("planet", scene_params("planet", sets=["planet.sun_disk=false",
                                                                   "planet.star_intensity=0"]),
                           ctx=gl_ctx)
    yield session
    session.release()


def shot(session, method, altitude):
    session.params.set("planet.method", method)
    session.scene.camera.set(position=(0.0, altitude, 60.0), yaw=0.0, pitch=-20.0, fov=70.0)
    img = next(render_frames(session, (96, 54)))
    return to_srgb8(img[..., :3], session.scene.exposure(), "exponential").astype(float)


@pytest.mark.parametrize("method", ["brute_force", "lut", "shadowed", "hillaire"])
def test_crossing_the_top_of_the_atmosphere_is_continuous(planet, method):
    top = 60000.0
    below, above = shot(planet, method, top - 50.0), shot(planet, method, top + 50.0)
    assert np.isfinite(below).all() and np.isfinite(above).all()
    assert np.abs(below - above).mean() < 2.0  # 8-bit levels: 100 m of flight changes little


@pytest.mark.parametrize("method", ["lut", "hillaire"])
def test_a_climb_changes_the_image_smoothly(planet, method):
    altitudes = [2.0, 1000.0, 10000.0, 30000.0, 59000.0, 61000.0, 66000.0, 120000.0, 600000.0]
    frames = [shot(planet, method, a) for a in altitudes]
    steps = [np.abs(a - b).mean() for a, b in zip(frames, frames[1:])]
    # the step across the top (59 → 61 km) is no bigger than the climb's ordinary steps
    assert steps[4] <= max(steps[:4] + steps[5:]) + 1.0, steps
