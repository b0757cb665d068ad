"""The floating boat swept to where it could fail: frame steps 1/240…1/10 s, masses 10 kg to
20 t, readback lag 0–3 frames, exactly at rest, upside down, a 10-minute storm (app/sim/
buoyancy.py, app/sim/rigid_body.py): finite, bounded, no drift, no jumps."""

from __future__ import annotations

import numpy as np
import pytest

from app.sim import buoyancy as bu
from app.sim import hull as hl
from app.sim.rigid_body import quat_from_axis_angle

DTS = (1.0 / 240.0, 1.0 / 60.0, 1.0 / 30.0, 1.0 / 10.0)


def _hull_for(mass):
    """A hull scaled so ``mass`` floats at about a third of its volume (10 kg: a 1.1 m
    model, coarse; 20 t: 1.5× the 8 m yacht)."""
    if mass <= 100.0:
        return hl.make_hull(hl.HullParams().scaled(0.14), stations=11, around=5)
    if mass >= 10000.0:
        return hl.make_hull(hl.HullParams().scaled(1.5))
    return hl.make_hull()


def _run(body, method, water, seconds, dt, every=None):
    ys = []
    for i in range(int(round(seconds / dt))):
        body.step(dt, lambda b, t: method.forces(b, water, t))
        ys.append(body.position[1])
        if every is not None:
            every(body)
    return np.array(ys)


@pytest.mark.parametrize("mass", [10.0, 20000.0])
@pytest.mark.parametrize("dt", DTS)
def test_drop_settles_for_every_step_and_mass(dt, mass):
    mesh = _hull_for(mass)
    body = bu.boat_body(mesh, mass)
    rest = body.position[1]
    depth = float(mesh.vertices[:, 1].max())
    body.position = body.position + [0.0, 0.5 * depth, 0.0]
    body.set_orientation(quat_from_axis_angle((0.3, 0.0, 1.0), 0.3))
    e0 = bu.hydrostatic_energy(mesh, body)["total"]
    ys = _run(body, bu.HydrostaticBuoyancy(mesh, linear_damping=1.0, angular_damping=1.0),
              bu.FlatWater(), 8.0, dt)
    assert np.all(np.isfinite(ys)) and body.finite()
    assert bu.hydrostatic_energy(mesh, body)["total"] <= e0
    assert abs(ys[-1] - rest) < 0.05 * depth


@pytest.mark.parametrize("lag", [0, 1, 2, 3])
@pytest.mark.parametrize("method", ["hydrostatic", "probes"])
def test_readback_lag_in_a_sea_stays_finite_without_jumps(lag, method):
    mesh = hl.make_hull()
    dt = 1.0 / 60.0
    body = bu.boat_body(mesh, 3000.0, max_substep=dt)
    forces = (bu.HydrostaticBuoyancy(mesh) if method == "hydrostatic"
              else bu.ProbeForces.for_hull(mesh, 3000.0, 8))
    sea = bu.SineWater(amplitude=1.0, wavelength=60.0)
    water = bu.DelayedWater(sea, lag, dt)
    ys = _run(body, forces, water, 15.0, dt)
    assert np.all(np.isfinite(ys)) and body.finite()
    assert np.max(np.abs(np.diff(ys))) < 0.1  # < 6 m/s: the wave moves the boat ≲ 1 m/s
    late = ys[len(ys) // 3:]
    water_y = np.array([sea.at((i + 1) * dt).height(0.0, 0.0) for i in range(len(ys))])
    assert np.corrcoef(late, water_y[len(ys) // 3:])[0, 1] > 0.9


@pytest.mark.parametrize("method", ["hydrostatic", "probes"])
def test_exactly_at_rest_stays_at_rest(method):
    mesh = hl.make_hull()
    dt = 1.0 / 60.0
    body = bu.boat_body(mesh, 3000.0, max_substep=dt)
    start = body.position.copy()
    forces = (bu.HydrostaticBuoyancy(mesh) if method == "hydrostatic"
              else bu.ProbeForces.for_hull(mesh, 3000.0, 8))
    _run(body, forces, bu.FlatWater(), 60.0, dt)
    assert np.linalg.norm(body.position - start) < 1e-3
    assert abs(body.orientation[0]) > 1.0 - 1e-9


def test_upside_down_start_rights_or_floats_without_nan():
    mesh = hl.make_hull()
    body = bu.boat_body(mesh, 3000.0, max_substep=1.0 / 120.0)
    body.set_orientation(quat_from_axis_angle((0.0, 0.0, 1.0), 3.1), keep="com")
    body.position = body.position + [0.0, 1.0, 0.0]
    e0 = bu.hydrostatic_energy(mesh, body)["total"]
    energies = []
    _run(body, bu.HydrostaticBuoyancy(mesh), bu.FlatWater(), 30.0, 1.0 / 60.0,
         every=lambda b: energies.append(bu.hydrostatic_energy(mesh, b)["total"]))
    assert body.finite() and np.all(np.isfinite(energies))
    assert max(energies) <= e0 + 1.0
    # ends floating: slow, its centre of mass within the hull's depth of the surface
    assert np.linalg.norm(body.velocity) < 0.1
    assert abs(body.com_world[1]) < 1.4
    assert 0.9 * 3000.0 / hl.RHO_SEA < bu.hydrostatic_energy(mesh, body)["volume"] \
        < 1.1 * 3000.0 / hl.RHO_SEA


def test_ten_minute_storm_with_probes_and_one_with_kerner():
    mesh = hl.make_hull()
    dt = 1.0 / 60.0
    storm = bu.storm_sea(6.0)
    body = bu.boat_body(mesh, 3000.0, max_substep=dt)
    ys = _run(body, bu.ProbeForces.for_hull(mesh, 3000.0, 8), storm, 600.0, dt)
    assert np.all(np.isfinite(ys)) and body.finite()
    assert np.ptp(ys) < 2.0 * storm.amplitude.sum() + 2.0
    body = bu.boat_body(mesh, 3000.0, max_substep=dt)
    ys = _run(body, bu.HydrostaticBuoyancy(mesh), storm, 60.0, dt)
    assert np.all(np.isfinite(ys)) and body.finite()
    assert np.ptp(ys) < 2.0 * storm.amplitude.sum() + 2.0
    floater = bu.ProbeFloat(bu.probe_layout(mesh, 4, 0.44)[0])
    body = bu.boat_body(mesh, 3000.0)
    for i in range(3600):
        floater.update(body, storm.at((i + 1) * dt), dt)
    assert body.finite() and abs(body.position[1]) < 10.0
