"""The whole sailing boat (app/sim/boat.py: hull, rigid body, buoyancy, sails, keel, skeg,
navigation, wake) swept where it could fail: every buoyancy method, wind 0–40 m/s from every
side, frame steps 1/240…1/10 s, the helm hard over, an upside-down start, a 1-minute storm —
finite, bounded speed, floating at the end. (The boat physics' own stability tests,
tests/stability/test_buoyancy_stability.py, sweep masses and the query lag.)"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.effects.wind.effect import wind_velocity
from app.sim import buoyancy as bu
from app.sim.boat import METHODS, BoatSim
from app.sim.rigid_body import quat_from_axis_angle


def _sail(sim, water, wind, seconds, dt):
    speeds = []
    for i in range(int(round(seconds / dt))):
        sim.step(dt, water, wind, (i + 1) * dt)
        assert sim.body.finite()
        speeds.append(np.linalg.norm(sim.body.velocity))
    return np.array(speeds)


@pytest.mark.parametrize("method, wind_speed, direction", [
    ("probes", 40.0, 270.0), ("probe_forces", 0.0, 0.0), ("probe_forces", 40.0, 135.0),
    ("hydrostatic", 12.0, 0.0), ("hydrostatic", 40.0, 270.0), ("hydrostatic", 25.0, 135.0)])
def test_every_method_in_any_wind_stays_finite_and_bounded(method, wind_speed, direction):
    assert set(METHODS) == {"probes", "probe_forces", "hydrostatic"}
    sim = BoatSim(method=method, heading_deg=0.0)
    sim.controls.helm = 0.6
    speeds = _sail(sim, bu.SineWater(0.8, 40.0, 0.3), wind_velocity(wind_speed, direction),
                   12.0, 1 / 15)
    # never faster than a planing dinghy; never sunk or launched
    assert speeds.max() < 12.0, (method, wind_speed, direction, speeds.max())
    y = sim.body.position[1] + sim.draft
    assert -2.0 < y < 2.0, (method, wind_speed, direction, y)


def test_frame_steps_from_1_240_to_1_10_s_sail_alike():
    """The same 10 s of sailing at frame steps of 1/240, 1/30 and 1/10 s ends within a metre or
    so (the integrator cuts every frame into substeps of at most boat.max_substep)."""
    ends = []
    for step in (1 / 240, 1 / 30, 1 / 10):
        sim = BoatSim(heading_deg=0.0)
        _sail(sim, bu.FlatWater(), wind_velocity(8.0, 90.0), 10.0, step)
        ends.append(sim.body.position[[0, 2]])
    travelled = np.linalg.norm(ends[0])
    assert travelled > 5.0
    for end in ends[1:]:
        assert np.linalg.norm(end - ends[0]) < 0.05 * travelled + 0.5


def test_at_rest_on_flat_water_in_no_wind_nothing_moves():
    sim = BoatSim(heading_deg=30.0)
    start = sim.body.position.copy()
    _sail(sim, bu.FlatWater(), (0.0, 0.0), 30.0, 1 / 60)
    assert np.abs(sim.body.position - start).max() < 1e-3
    assert len(sim.wake) > 0 and sim.wake.foam(np.array([0.0]), np.array([0.0]), 30.0)[0] < 1e-3


def test_an_upside_down_start_ends_floating():
    sim = BoatSim(method="hydrostatic")
    sim.body.set_orientation(quat_from_axis_angle((0.0, 0.0, 1.0), math.pi), keep="com")
    _sail(sim, bu.FlatWater(), wind_velocity(6.0, 0.0), 30.0, 1 / 30)
    assert sim.body.finite()
    y = sim.body.position[1]
    assert abs(y) < 3.0


def test_a_storm_with_the_sails_up_for_a_minute():
    sim = BoatSim(method="hydrostatic", heading_deg=45.0)
    speeds = _sail(sim, bu.storm_sea(6.0), wind_velocity(25.0, 90.0), 60.0, 1 / 20)
    assert speeds.max() < 15.0
