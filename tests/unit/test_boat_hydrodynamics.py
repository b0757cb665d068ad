"""The boat's added mass and radiation damping (docs/theory/000-maritime.md#added-mass): the
committed BEM numbers (tools/added_mass.py, resources/boat/hydrodynamics.json) are current for
the hull generator and pass the solver's box check; the rigid-body step applies them; the fitted
heave and pitch modes lie within 10 % of the BEM reference with the energy decaying; the sailing
model's waterline comes from the mesh."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.bench import boat as bench
from app.errors import ParamError
from app.sim import buoyancy as bu
from app.sim import hull as hl
from app.sim import sailing as sl
from app.sim.boat import BoatSim
from app.sim.rigid_body import Hydrodynamics, RigidBody


@pytest.fixture(scope="module")
def mesh():
    return hl.make_hull()


@pytest.fixture(scope="module")
def table():
    return bu.hydrodynamics_table()


# -- the committed numbers ---------------------------------------------------------------------


def test_the_committed_numbers_are_for_this_hull_and_this_body(mesh, table):
    """Change the hull generator, the centre of mass or the inertia rule and this fails: rerun
    tools/added_mass.py (its command is in the file)."""
    assert table["hull_fingerprint"] == hl.hull_fingerprint(mesh)
    assert "tools/added_mass.py" in table["command"]
    for row in table["masses"]:
        body = bu.boat_body(mesh, row["mass"])
        assert row["draft"] == pytest.approx(hl.draft_for_mass(mesh, row["mass"]), abs=1e-7)
        assert np.allclose(row["com"], body.com, atol=1e-7)
        assert np.allclose(row["inertia"], body.inertia_body, rtol=1e-7, atol=1e-6)


def test_another_hull_is_refused_in_one_line(mesh):
    other = hl.make_hull(hl.HullParams(beam=2.4))
    with pytest.raises(ParamError, match="another hull"):
        bu.hull_hydrodynamics(other, 2500.0)
    assert BoatSim(hull=hl.HullParams(beam=2.4)).hydrodynamics is False  # default: off there
    with pytest.raises(ParamError):
        BoatSim(hull=hl.HullParams(beam=2.4), hydrodynamics=True)


def test_the_solver_passes_the_box_check(table):
    """Issue 39's check: a 4 × 2 m box at 0.5 m draft heaves in 1.42 s without added mass and
    2.16 s with it (the tool runs it before the hull, with the same solver settings)."""
    box = table["box"]
    assert box["size"] == [4.0, 2.0, 0.5]
    assert box["period_dry"] == pytest.approx(1.42, abs=0.005)
    assert box["period_added"] == pytest.approx(2.16, rel=0.02)


def test_the_coefficients_are_physical(mesh, table):
    for row in table["masses"]:
        a, b = np.array(row["constant"]["added_mass"]), np.array(row["constant"]["damping"])
        for k in (1, 3, 5):  # heave, pitch, roll
            assert a[k, k] > 0 and b[k, k] > 0
        assert a[1, 3] == pytest.approx(a[3, 1], rel=0.05)  # reciprocity (BEM: to the panels)
        assert np.allclose(a[[0, 2, 4]], 0) and np.allclose(b[:, [0, 2, 4]], 0)
    # heavier boat, deeper draft: less added mass per kilogram in heave
    ratios = [r["constant"]["added_mass"][1][1] / r["mass"] for r in table["masses"]]
    assert all(x > y for x, y in zip(ratios, ratios[1:]))
    h = bu.hull_hydrodynamics(mesh, 2750.0)  # between two rows
    lo, hi = (np.array(r["constant"]["added_mass"]) / r["mass"] for r in table["masses"][3:5])
    assert np.allclose(h.added_mass / 2750.0, 0.5 * (lo + hi))


# -- the rigid-body step -----------------------------------------------------------------------


def _heave_only(a33: float, b33: float) -> Hydrodynamics:
    a, b = np.zeros((6, 6)), np.zeros((6, 6))
    a[1, 1], b[1, 1] = a33, b33
    return Hydrodynamics(a, b)


def test_added_mass_slows_the_acceleration_and_damping_takes_momentum():
    m = 1000.0
    body = RigidBody(m, np.eye(3) * 500.0, hydrodynamics=_heave_only(2000.0, 0.0))

    def push(b, t):  # the weight carried, plus 300 N up
        return np.array([0.0, m * 9.81 + 300.0, 0.0]), np.zeros(3)

    body.step(1.0, push)
    assert body.velocity[1] == pytest.approx(300.0 / 3000.0, rel=1e-9)
    body = RigidBody(m, np.eye(3) * 500.0, velocity=(0.0, 1.0, 0.0),
                     hydrodynamics=_heave_only(2000.0, 600.0))

    def float_(b, t):
        return np.array([0.0, m * 9.81, 0.0]), np.zeros(3)

    body.step(2.0, float_)  # v' = −B v/(m + A): e^(−0.2 s⁻¹ · 2 s)
    assert body.velocity[1] == pytest.approx(math.exp(-0.4), rel=2e-3)
    body.step(1.0, float_, hydrodynamics=False)  # off for a step: the body alone
    assert body.velocity[1] == pytest.approx(math.exp(-0.4), rel=2e-3)


def test_an_added_mass_that_leaves_no_mass_is_refused():
    with pytest.raises(ParamError, match="positive definite"):
        RigidBody(1000.0, np.eye(3), hydrodynamics=_heave_only(-2000.0, 0.0))


# -- the modes against the BEM reference -------------------------------------------------------


def test_fit_modes_recovers_two_close_damped_modes():
    t = np.arange(0.0, 8.0, 1.0 / 120.0)
    s1, s2 = complex(-0.9, 2 * math.pi / 1.8), complex(-0.6, 2 * math.pi / 1.75)
    ch = [np.exp(s1.real * t) * (0.02 * np.cos(s1.imag * t)) + np.exp(s2.real * t) * 0.004
          * np.cos(s2.imag * t + 0.3),
          np.exp(s1.real * t) * (0.003 * np.sin(s1.imag * t)) + np.exp(s2.real * t) * 0.03
          * np.cos(s2.imag * t)]
    fitted = bench.fit_modes(t, np.array(ch), order=4)
    periods = sorted(m["period"] for m in fitted)
    assert periods == pytest.approx([1.75, 1.8], abs=1e-6)
    zeta = {round(m["period"], 3): m["zeta"] for m in fitted}
    assert zeta[1.8] == pytest.approx(0.9 / abs(s1), rel=1e-6)


@pytest.mark.parametrize("mass", [2500.0])
def test_heave_and_pitch_within_ten_percent_of_the_bem_reference_and_decaying(mesh, mass):
    """The scene's boat (2.5 t) on Kerner's pressure integration with the committed
    coefficients: the fitted heave and pitch periods within 10 % of the coupled BEM reference
    (frequency-dependent coefficients, each mode at its own frequency), damped alike; the body
    alone (before) is nearly twice as fast and never decays."""
    ref = bu.reference_modes(mesh, mass)
    method = bu.HydrostaticBuoyancy.undamped(mesh)
    fit = bench.free_decay_modes(mesh, mass, method, True, 5.0, substep=1.0 / 120.0)
    for k in ("heave", "pitch"):
        assert fit[k]["period"] == pytest.approx(ref[k]["period"], rel=0.10), (k, fit, ref)
        assert fit[k]["zeta"] == pytest.approx(ref[k]["zeta"], rel=0.25), (k, fit, ref)
        assert fit[k]["decay"] < 0.4  # the amplitude falls by more than half each period
    before = bench.free_decay_modes(mesh, mass, method, False, 5.0, substep=1.0 / 120.0)
    assert before["heave"]["period"] < 0.6 * ref["heave"]["period"]
    assert abs(before["heave"]["zeta"]) < 0.01


def test_the_free_decay_loses_its_energy(mesh):
    """Radiation damping alone (no Kerner drag): lifted 5 cm, the boat's energy above rest falls
    below 1 % in six seconds; without the coefficients it keeps it."""
    mass = 2500.0
    method = bu.HydrostaticBuoyancy.undamped(mesh)
    left = {}
    for hydro in (True, False):
        body = bu.boat_body(mesh, mass, max_substep=1.0 / 120.0, hydrodynamics=hydro)
        rest = bu.hydrostatic_energy(mesh, body)["total"]
        body.com_world = body.com_world + [0.0, 0.05, 0.0]
        e0 = bu.hydrostatic_energy(mesh, body)["total"] - rest
        bench._simulate(body, method, bu.FlatWater(), 6.0, 1.0 / 60.0)
        left[hydro] = (bu.hydrostatic_energy(mesh, body)["total"] - rest) / e0
    assert left[True] < 0.01 and left[False] > 0.9, left


def test_the_boat_sim_has_the_coefficients_by_default_and_a_switch(mesh):
    sim = BoatSim(method="hydrostatic")
    assert sim.hydrodynamics and sim.body.hydrodynamics is not None
    water = bu.FlatWater()
    for i in range(30):
        sim.step(1.0 / 60.0, water, (0.0, 0.0), (i + 1) / 60.0)
    assert sim.body.finite()
    sim.hydrodynamics = False
    assert sim.body.hydrodynamics is None
    sim.reset()
    assert not sim.hydrodynamics
    sim.hydrodynamics = True
    sim.reset()
    assert sim.hydrodynamics
    probes = BoatSim(method="probes")  # kinematic: the step runs without them
    for i in range(10):
        probes.step(1.0 / 60.0, water, (3.0, 0.0), (i + 1) / 60.0)
    assert probes.body.finite()


# -- the waterline -----------------------------------------------------------------------------


def test_the_sailing_waterline_is_the_meshs_at_its_displacement(mesh):
    draft = hl.draft_for_mass(mesh, 2500.0)
    lwl = hl.waterline_length(mesh, draft)
    z = np.linspace(-4.0, 4.0, 80001)  # the half-breadths' extent, sampled every 0.1 mm
    wet = z[hl.waterline_half_beam(mesh, draft, z) > 0]
    assert lwl == pytest.approx(float(wet.max() - wet.min()), abs=2e-4)
    assert lwl == pytest.approx(7.27, abs=0.005)  # issue 39; 0.88 × LOA was 7.04
    sim = BoatSim(mass=2500.0)
    assert sim.sailing.hull.lwl == pytest.approx(lwl, abs=1e-12)
    assert sim.sailing.hull.hull_speed == pytest.approx(0.4 * math.sqrt(9.81 * lwl), rel=0.01)
    assert sl.Hull().lwl == pytest.approx(lwl, abs=0.005)  # the polar's default boat
    heavy = BoatSim(mass=5000.0)
    assert heavy.sailing.hull.lwl > lwl  # deeper, longer waterline
