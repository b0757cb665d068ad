"""The maritime scene's HUD figures from a running session (spec/000 §2, §6 criterion 36): the
wind dial is the wind's direction minus the boat's heading, folded into (−180, 180]; the time
readout is the scene's clock; the sliders show the parameters; a forced weather state shows
its wind. The HUD's drawing and keys are tested in the window (tests/window/
test_window_maritime.py), its plain logic in tests/unit/test_hud.py."""

from __future__ import annotations

import math

import pytest

from app.runtime import open_session, scene_params
from app.scenes.maritime import WEATHER
from app.sim.daynight import hour_label
from app.sim.maths import wrap_degrees as wrap180

SIZE = (32, 18)
SMALL = ["clouds_b.volume_resolution=16", "clouds_b.detail_resolution=8",
         "clouds_b.gradient_resolution=16", "ocean.fft_size=64", "ocean.mesh_segments=32",
         "boat.spin_up=0"]


@pytest.fixture
def maritime(gl_ctx):
    sessions = []

    def _open(*sets):
        s = open_session("maritime", scene_params("maritime", sets=[*SMALL, *sets]), ctx=gl_ctx)
        sessions.append(s)
        return s

    yield _open
    for s in sessions:
        s.release()


def test_wind_dial_is_wind_direction_minus_heading(maritime):
    s = maritime("boat.heading=300", "wind.direction=30", "time.hour=9.5")
    scene, p = s.scene, s.params
    scene.frame(SIZE, 0.0)
    hud = scene.hud()
    sim = scene.boat().sim
    assert hud.heading == pytest.approx(math.degrees(sim.heading) % 360.0)
    assert hud.heading == pytest.approx(300.0, abs=1.0)  # no spin-up: it starts on its heading
    assert hud.wind_relative == pytest.approx(wrap180(30.0 - hud.heading))
    assert hud.wind_relative == pytest.approx(90.0, abs=1.0)  # 30 − 300 wraps to +90
    for direction in (0.0, 45.0, 120.0, 200.0, 299.0, 359.0):
        p.set("wind.direction", direction)
        scene.frame(SIZE, 1 / 30)
        hud = scene.hud()
        assert hud.wind_direction == direction
        assert hud.heading == pytest.approx(math.degrees(scene.boat().sim.heading) % 360.0)
        assert hud.wind_relative == pytest.approx(wrap180(direction - hud.heading))
        assert -180.0 < hud.wind_relative <= 180.0
    # the time readout is the scene's clock; the sliders show the parameters
    assert hud.hour == p["time.hour"] and hour_label(hud.hour) == "09:30"
    assert hud.playing == p["time.playing"]
    p.set("boat.helm", 0.5)
    p.set("boat.sails", -0.25)
    p.set("boat.throttle", 0.75)
    scene.frame(SIZE, 1 / 30)
    hud = scene.hud()
    assert (hud.helm, hud.sails, hud.throttle) == (0.5, -0.25, 0.75)
    assert hud.camera == "chase" and math.isfinite(hud.speed)
    assert math.isfinite(hud.apparent_angle) and -180.0 <= hud.apparent_angle <= 180.0


def test_forced_weather_shows_in_the_hud(maritime):
    s = maritime()
    scene, p = s.scene, s.params
    scene.frame(SIZE, 0.0)
    assert scene.hud().weather == "fair"
    for state, values in WEATHER.items():
        p.set("maritime.weather", state)
        scene.frame(SIZE, 1 / 30)
        hud = scene.hud()
        assert hud.weather == state and hud.wind_speed == values["wind.speed"]
