"""The floating boat's numpy physics (app/sim/rigid_body.py, app/sim/buoyancy.py) and the
figures of app/bench/boat.py: spec/000 §6 criteria 10 and 11, Archimedes, the heave period,
Kerner's drop test, the integrator's energy error."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.bench import boat as bench
from app.errors import ParamError
from app.sim import buoyancy as bu
from app.sim import hull as hl
from app.sim.ocean import floating_points_pose
from app.sim.rigid_body import (
    RigidBody,
    quat_from_axis_angle,
    quat_from_matrix,
    quat_to_matrix,
)


@pytest.fixture(scope="module")
def mesh():
    return hl.make_hull()


@pytest.fixture(scope="module")
def archimedes(mesh):
    """The quick Archimedes report (every mass of ``bench.MASSES``, 3000 kg among them), made
    once: its drafts are checked by one test, its summary and chart by another."""
    return bench.archimedes(mesh, quick=True)


# -- water surfaces and the thesis's floating object ------------------------------------------


def test_flat_water_gives_an_up_normal_and_no_displacement():
    pts = np.array([[-1.0, 0.0, -3.0], [1.0, 0.0, -3.0], [-1.0, 0.0, 3.0], [1.0, 0.0, 3.0]])
    n, d = floating_points_pose(bu.FlatWater().water, pts[:, 0], pts[:, 2])
    assert np.allclose(n, [0, 1, 0], atol=1e-6) and np.allclose(d, 0.0, atol=1e-12)


def test_tilted_plane_normal_is_recovered_within_a_degree():
    plane = bu.PlaneWater.tilted(0.05, -0.03, level=0.2)
    floater = bu.ProbeFloat(np.array([[-1.0, 0.4, -3.0], [1.0, 0.4, -3.0], [-1.0, 0.4, 3.0],
                                      [1.0, 0.4, 3.0]]))
    body = RigidBody(1000.0, np.eye(3) * 1000.0)
    n, _, _ = floater.target(body, plane)
    ang = math.degrees(math.acos(float(np.clip(n @ plane.plane_normal, -1, 1))))
    assert ang < 1.0
    for _ in range(600):  # 10 s at 60 Hz: settles on the plane
        floater.update(body, plane, 1.0 / 60.0)
    up = body.rotation[:, 1]
    assert math.degrees(math.acos(float(np.clip(up @ plane.plane_normal, -1, 1)))) < 1.0
    p = body.to_world(floater.floating_points)
    assert np.allclose(p[:, 1].mean(), plane.height(p[:, 0], p[:, 2]).mean(), atol=2e-3)


def test_probe_float_tracks_the_sea_within_its_smoothing_and_is_frame_rate_independent(mesh):
    pts = bu.probe_layout(mesh, 4, 0.44)[0]
    sea = bu.SineWater(amplitude=0.8, wavelength=60.0)
    finals = []
    for dt in (1.0 / 120.0, 1.0 / 30.0):
        floater = bu.ProbeFloat(pts, displacement_stiffness=20.0, rotation_stiffness=10.0)
        body = RigidBody(3000.0, np.eye(3) * 3000.0, position=(0.0, -0.44, 0.0))
        errs = []
        for i in range(int(round(12.0 / dt))):
            w = sea.at((i + 1) * dt)
            floater.update(body, w, dt)
            p = body.to_world(pts)
            errs.append(abs(p[:, 1].mean() - w.height(p[:, 0], p[:, 2]).mean()))
        # lag of a first-order filter at rate k on a wave of frequency ω: |err| ≤ A·ω/k
        assert max(errs[len(errs) // 2:]) < 0.8 * sea.omega[0] / 20.0 * 1.2
        finals.append(body.position[1])
    assert finals[0] == pytest.approx(finals[1], abs=0.03)
    off = bu.ProbeFloat(pts, simulate_flotation=False)
    body = RigidBody(3000.0, np.eye(3))
    off.update(body, sea, 0.1)
    assert np.all(body.position == 0.0)


def test_delayed_water_answers_the_sea_lag_frames_ago_held_per_frame():
    sea = bu.SineWater(amplitude=1.0, wavelength=40.0)
    late = bu.DelayedWater(sea, lag_frames=2, frame_dt=0.1).at(1.05)
    assert late.query_time == pytest.approx(0.8)
    assert late.height(3.0, 1.0) == pytest.approx(sea.at(0.8).height(3.0, 1.0))
    assert bu.DelayedWater(sea, 0, 0.1).at(1.05).query_time == pytest.approx(1.0)
    with pytest.raises(ParamError):
        bu.DelayedWater(sea, lag_frames=-1)


def test_sine_water_normals_match_finite_differences():
    sea = bu.storm_sea(6.0, time=3.0)
    assert sea.significant_height == pytest.approx(6.0)
    x, z = np.linspace(-50, 50, 64), np.linspace(-20, 30, 64)
    q = sea.water(x, z)
    e = 1e-4
    hx = (sea.height(x + e, z) - sea.height(x - e, z)) / (2 * e)
    hz = (sea.height(x, z + e) - sea.height(x, z - e)) / (2 * e)
    n = np.stack([-hx, np.ones_like(hx), -hz], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    assert np.allclose(q.normal, n, atol=1e-6)


# -- the rigid body ---------------------------------------------------------------------------


def test_free_fall_and_a_tumbling_body_stay_exact_and_bounded():
    body = RigidBody(2.0, np.diag([1.0, 2.0, 3.0]))
    body.step(1.0)
    assert body.velocity[1] == pytest.approx(-9.81)
    assert body.substeps(1.0 / 10.0) == 24 and body.substeps(1.0 / 240.0) == 1
    # torque-free spin about the unstable middle axis: |L| exact, energy bounded
    body = RigidBody(1.0, np.diag([1.0, 2.0, 3.0]), angular_velocity=(0.01, 10.0, 0.01),
                     gravity=(0, 0, 0))
    l0, e0 = body.momentum.copy(), body.kinetic_energy()
    for _ in range(1000):
        body.step(1.0 / 10.0)
    assert np.allclose(body.momentum, l0)
    assert body.kinetic_energy() == pytest.approx(e0, rel=0.1)
    assert np.linalg.norm(body.orientation) == pytest.approx(1.0)


def test_quaternions_round_trip():
    q = quat_from_axis_angle((1.0, -2.0, 0.5), 2.5)
    assert np.allclose(quat_from_matrix(quat_to_matrix(q)), q * np.sign(q[0]))
    r = quat_to_matrix(q)
    assert np.allclose(r @ r.T, np.eye(3))
    body = RigidBody(5.0, np.eye(3), position=(1, 2, 3), orientation=r, com=(0.1, 0.2, 0.3))
    assert np.allclose(body.position, [1, 2, 3])
    back = (body.to_world([[1.0, 2.0, 3.0]]) - body.position) @ body.rotation
    assert np.allclose(back, [[1.0, 2.0, 3.0]])


# -- the force methods ------------------------------------------------------------------------


def test_hydrostatic_forces_are_archimedes_exactly_in_flat_water(mesh):
    body = bu.boat_body(mesh, 3000.0)
    r = hl.heel_trim_rotation(0.2, -0.05)
    body.set_orientation(quat_from_matrix(r))
    body.position = body.position + [0.3, 0.05, -1.0]
    method = bu.HydrostaticBuoyancy.undamped(mesh)
    f, tau = method.forces(body, bu.FlatWater())
    corners = body.to_world(mesh.vertices)[mesh.triangles]
    sub = hl.submerged_below_plane(mesh, (0, 0, 0), (0, 1, 0), corners=corners)
    buoyancy = hl.RHO_SEA * 9.81 * sub.volume
    assert np.allclose(f, [0.0, buoyancy, 0.0], atol=1e-6 * buoyancy)
    expected = np.cross(sub.centre - body.com_world, [0.0, buoyancy, 0.0])
    assert np.allclose(tau, expected, atol=1e-6 * buoyancy)
    assert method.last["volume"] == pytest.approx(sub.volume, rel=1e-9)
    # a heeled boat rights itself (stbd down → torque about +z lifts starboard)
    assert tau[2] > 0


def test_probe_forces_carry_the_weight_with_the_hydrostatic_heave_stiffness(mesh):
    body = bu.boat_body(mesh, 3000.0)
    for n in (4, 8, 16, 32):
        probes = bu.ProbeForces.for_hull(mesh, 3000.0, n)
        assert len(probes.points) == n and probes.weights.sum() == pytest.approx(3000.0)
        f, tau = probes.forces(body, bu.FlatWater())
        assert f[1] == pytest.approx(3000.0 * 9.81) and np.linalg.norm(tau) < 1e-6 * f[1]
        f2, _ = probes.forces(body, bu.FlatWater(level=0.01))
        a_w = mesh.submerged(hl.draft_for_mass(mesh, 3000.0)).waterplane_area
        assert (f2[1] - f[1]) / 0.01 == pytest.approx(hl.RHO_SEA * 9.81 * a_w, rel=1e-6)


def test_drag_opposes_motion_and_vanishes_at_rest(mesh):
    body = bu.boat_body(mesh, 3000.0)
    method = bu.HydrostaticBuoyancy(mesh, linear_damping=0.5, angular_damping=0.5)
    f0, _ = method.forces(body, bu.FlatWater())
    body.velocity = np.array([0.5, -1.0, 2.0])
    f1, _ = method.forces(body, bu.FlatWater())
    assert (f1 - f0) @ body.velocity < 0
    assert 0.001 < method.last["cf"] < 0.01


# -- the bench's figures ----------------------------------------------------------------------


def test_archimedes_draft_within_a_percent(archimedes):
    rep = archimedes
    for r in rep["rows"]:
        assert abs(r["error"]) < 0.01, r
        assert r["exact"] < 1.4 and abs(r["trim"]) < 0.01
        assert r["probes8"] == pytest.approx(r["exact"], rel=0.01)


def test_heave_period_within_five_percent(mesh):
    rep = bench.periods(mesh, quick=True)
    assert abs(rep["heave_error"]) < 0.05, rep
    assert rep["roll"] == pytest.approx(rep["roll_expected"], rel=0.1)


def test_kerner_drop_test_settles_with_decaying_energy(mesh):
    rep = bench.drop_test(mesh, quick=True)
    for name in ("dropped", "pushed"):
        d = rep[name]
        assert d["finite"]
        w = d["windows"]
        assert w[0] > w[1] > w[3] and w[3] < 1e-3 * w[0], w
        assert d["final_y"] == pytest.approx(d["rest_y"], abs=0.01)


def test_energy_error_bounded_and_falls_with_the_step(mesh):
    rep = bench.energy_error(mesh, dts=(1 / 240, 1 / 60, 1 / 10), quick=True)
    one = [r["one_step"]["max"] for r in rep["rows"]]
    assert one[0] < one[1] < one[2] < 1.0
    for r in rep["rows"]:
        assert r["substeps"]["max"] < 0.03 and abs(r["substeps"]["drift"]) < 0.01


def test_summary_and_chart_of_a_small_report(mesh, archimedes, tmp_path):
    assert 3000.0 in bench.MASSES
    rep = {"triangles": len(mesh.triangles), "archimedes": archimedes,
           "periods": {"heave": 1.0, "heave_expected": 1.0, "heave_error": 0.0, "roll": 2.0,
                       "roll_expected": 2.0, "gm": 1.0},
           "drop": {k: {"t": [0, 1], "energy": [10.0, 1.0], "start_energy": 10.0,
                        "final_energy": 1.0, "windows": [10.0, 1.0]}
                    for k in ("dropped", "pushed")},
           "energy": {"rows": [{"dt": 0.1, "one_step": {"max": 0.1, "drift": 0.01},
                                "substeps": {"max": 0.01, "drift": 0.001}}], "periods": 4},
           "sea": {"tracking": {"t": [0, 1], "heave": [0, 1], "water": [0, 1],
                                "correlation": 1.0, "ratio": 1.0},
                   "storm": {"minutes": 1, "hs": 6.0, "finite": True, "heave_min": -1.0,
                             "heave_max": 1.0}},
           "speed": {"rows": [{"method": "hydrostatic", "force_error": 0.001,
                               "torque_error": 0.001, "draft_error": 0.0, "trim_error": 0.0,
                               "ms_eval": 0.4, "ms_frame": 2.0},
                              {"method": "float 4 (kinematic)", "ms_eval": 0.2,
                               "ms_frame": 0.2}]}}
    text = bench.summary(rep)
    assert "draft exact" in text and "heave period" in text
    out = bench.chart(rep, tmp_path / "boat.png")
    assert out is None and (tmp_path / "boat.png").stat().st_size > 1000
