"""Navigation, wind and sails (app/sim/sailing.py): spec/000 §6 criteria 12 and 13, the HUD's
wind angle (criterion 36), the apparent-wind sail, the keel and hull, and the speed polar."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.bench import polar as bench_polar
from app.effects.ocean.params import wind_vector as ocean_wind_vector
from app.errors import ParamError
from app.sim import sailing as sl

SETTINGS = settings(max_examples=150, deadline=None)
inputs = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**6, 10**6))
WIND_SPEEDS = (4.0, 8.0, 12.0)


@pytest.fixture(scope="module")
def polar():
    return sl.speed_polar(WIND_SPEEDS, np.arange(0.0, 180.1, 3.0))


# ---- conventions ----------------------------------------------------------------------------

def test_heading_is_a_compass_bearing_and_starboard_is_bow_cross_up():
    assert np.allclose(sl.heading_vector(0.0), [0, 0, -1])  # north
    assert np.allclose(sl.heading_vector(math.pi / 2), [1, 0, 0])  # east
    for psi in np.linspace(-3.0, 3.0, 13):
        bow = sl.heading_vector(psi)
        assert np.allclose(sl.starboard_vector(psi), np.cross(bow, sl.UP))
        assert sl.heading_of(bow) == pytest.approx(psi)


def test_wind_direction_is_the_oceans():
    for d in (0.0, 37.0, 90.0, 200.0, 359.0):
        v = sl.Wind(7.0, d).vector()
        assert v[1] == 0.0
        assert np.allclose(v[[0, 2]], 7.0 * ocean_wind_vector(d))
    assert sl.Wind(5.0, 90.0).xz() == pytest.approx((5.0, 0.0))  # toward east


def test_wind_angle_is_where_the_wind_comes_from():
    psi = 0.0  # bow north
    assert sl.wind_angle(sl.wind_vector(5.0, 180.0), psi) == pytest.approx(0.0)  # head to wind
    assert sl.wind_angle(sl.wind_vector(5.0, 270.0), psi) == pytest.approx(math.pi / 2)  # from E
    assert sl.wind_angle(sl.wind_vector(5.0, 90.0), psi) == pytest.approx(-math.pi / 2)  # from W
    assert abs(sl.wind_angle(sl.wind_vector(5.0, 0.0), psi)) == pytest.approx(math.pi)


@given(st.floats(-720, 720), st.floats(-10, 10))
@SETTINGS
def test_hud_wind_indicator_is_wind_angle_minus_heading(direction, psi):
    """Criterion 36: the HUD shows the wind's direction minus the boat's heading."""
    rel = sl.relative_wind_angle(direction, psi)
    assert -180.0 < rel <= 180.0
    d = (rel - (direction - math.degrees(psi))) % 360.0
    assert min(d, 360.0 - d) < 1e-7
    # and it is the wind's direction in the boat's frame (0 = toward the bow)
    w = sl.wind_vector(1.0, direction)
    ahead = float(w @ sl.heading_vector(psi))
    side = float(w @ sl.starboard_vector(psi))
    assert math.degrees(math.atan2(side, ahead)) == pytest.approx(rel, abs=1e-6) or \
        abs(abs(rel) - 180.0) < 1e-6


# ---- criterion 12: the NavigableObject --------------------------------------------------------

@given(inputs, inputs)
@SETTINGS
def test_navigation_inputs_are_clamped(direction, throttle):
    nav = sl.Navigation(direction=direction, throttle=throttle)
    for got, given_ in ((nav.direction, direction), (nav.throttle, throttle)):
        assert -1.0 <= got <= 1.0
        if isinstance(given_, float) and math.isnan(given_):
            assert got == 0.0
        else:
            assert got == min(1.0, max(-1.0, float(given_)))
    nav.direction = 1e9
    nav.throttle = -1e9
    assert (nav.direction, nav.throttle) == (1.0, -1.0)
    sail = sl.Sail(sails_direction=direction)
    assert -1.0 <= sail.sails_direction <= 1.0
    assert abs(sail.thesis_boom()) <= sail.max_angle + 1e-12


@given(st.lists(st.tuples(inputs, inputs, st.floats(0.0, 2.0)), min_size=1, max_size=40),
       st.floats(0.01, 3.0), st.floats(0.5, 20.0), st.floats(-50.0, 50.0))
@SETTINGS
def test_kinematic_step_never_exceeds_max_speed_or_turn_speed(steps, max_turn, max_speed, v0):
    nav = sl.Navigation(max_turn_speed=max_turn, max_speed=max_speed)
    psi, speed = 0.3, v0
    for direction, throttle, dt in steps:
        nav.direction, nav.throttle = direction, throttle
        new_psi, speed = nav.step(psi, speed, dt)
        assert abs(speed) <= max_speed + 1e-12
        assert -math.pi < new_psi <= math.pi
        turned = abs(math.remainder(new_psi - psi, 2 * math.pi))
        assert turned <= max_turn * dt + 1e-9
        assert abs(nav.yaw_rate()) <= max_turn
        psi = new_psi


def _simulate(nav: sl.Navigation, controls, surge=None, dt=0.02, steps=600):
    """Yaw and surge of a rigid body driven by ``nav.forces`` (semi-implicit Euler); ``surge``
    fixes the forward speed (a boat the sails drive) instead of integrating it."""
    psi, u, r = 0.0, 0.0 if surge is None else surge, 0.0
    rates, speeds = [], []
    for i in range(steps):
        nav.direction, nav.throttle = controls(i)
        state = sl.BoatState(u * sl.heading_vector(psi), psi, [0.0, -r, 0.0])
        force, torque = nav.forces(state)
        r += -torque[1] / nav.yaw_inertia * dt
        if surge is None:
            u += float(force @ sl.heading_vector(psi)) / nav.mass * dt
        psi += r * dt
        rates.append(r)
        speeds.append(u)
    return np.array(rates), np.array(speeds)


@pytest.mark.parametrize("mode", sl.NAVIGATION_MODES)
def test_forces_keep_speed_and_turn_rate_within_their_limits(mode):
    rng = np.random.default_rng(3)
    plan = rng.uniform(-3.0, 3.0, size=(600 // 50 + 1, 2))
    nav = sl.Navigation(max_turn_speed=0.4, max_speed=3.0, mode=mode)
    rates, speeds = _simulate(nav, lambda i: plan[i // 50])
    assert np.abs(speeds).max() <= 3.0 * (1 + 1e-9)
    assert np.abs(rates).max() <= 0.4 * 1.02
    # a boat driven by its sails past the motor's top speed: the rudder's rate is still limited
    nav = sl.Navigation(max_turn_speed=0.4, max_speed=3.0, mode=mode)
    rates, _ = _simulate(nav, lambda i: (1.0, 0.0), surge=6.0)
    assert np.abs(rates).max() <= 0.4 * 1.02
    assert rates[-1] == pytest.approx(0.4, rel=0.02)


def test_the_thesis_turns_standing_still_the_rudder_needs_way():
    still = sl.BoatState(np.zeros(3), 0.0)
    thesis = sl.Navigation(direction=1.0, mode="thesis")
    rudder = sl.Navigation(direction=1.0, mode="rudder")
    assert thesis.forces(still)[1][1] < 0.0  # a torque turning to starboard (about −y)
    assert np.allclose(rudder.forces(still)[1], 0.0)
    moving = sl.BoatState(2.0 * sl.heading_vector(0.0), 0.0)
    assert rudder.forces(moving)[1][1] < 0.0
    # the turning circle is the same at every speed: steady rate ∝ forward speed
    slow, _ = _simulate(sl.Navigation(mode="rudder"), lambda i: (1.0, 0.0), surge=1.0, steps=3000)
    fast, _ = _simulate(sl.Navigation(mode="rudder"), lambda i: (1.0, 0.0), surge=2.0, steps=3000)
    assert fast[-1] == pytest.approx(2.0 * slow[-1], rel=0.1)


def test_the_motor_never_pushes_past_its_target_nor_brakes_a_sailing_boat():
    nav = sl.Navigation(throttle=0.5, max_speed=4.0)
    fast = sl.BoatState(3.0 * sl.heading_vector(0.0), 0.0)  # target 2 m/s
    assert np.allclose(nav.forces(fast)[0], 0.0)
    slow = sl.BoatState(1.0 * sl.heading_vector(0.0), 0.0)
    assert float(nav.forces(slow)[0] @ sl.heading_vector(0.0)) > 0.0


# ---- criterion 13: the thesis's sail thrust -----------------------------------------------

def test_thesis_thrust_is_monotonic_in_the_cosine_to_the_sail_normal():
    sail = sl.Sail(mode="thesis")
    psi = 0.4
    rows = []
    for s in np.linspace(-1.0, 1.0, 21):
        sail.sails_direction = s
        b = sail.thesis_boom()
        normal = math.sin(b) * sl.heading_vector(psi) + math.cos(b) * sl.starboard_vector(psi)
        for d in np.linspace(0.0, 360.0, 73):
            w = sl.wind_vector(6.0, d)
            rows.append((abs(float(w @ normal)) / 6.0, float(sail.thesis_thrust(w, psi))))
    rows.sort()
    cos, thrust = np.array(rows).T
    assert np.all(np.diff(thrust) >= -1e-9)
    full = 0.5 * sl.RHO_AIR * 36.0 * sail.area
    assert thrust.max() == pytest.approx(full, rel=1e-3)
    sail.sails_direction = 0.3  # the wind along the sail's normal: the full thrust
    b = sail.thesis_boom()
    normal = math.sin(b) * sl.heading_vector(psi) + math.cos(b) * sl.starboard_vector(psi)
    w = sl.wind_vector(6.0, math.degrees(sl.heading_of(normal)))
    assert float(sail.thesis_thrust(w, psi)) == pytest.approx(full)
    chord = sl.wind_vector(6.0, math.degrees(sl.heading_of(np.cross(normal, sl.UP))))
    assert float(sail.thesis_thrust(chord, psi)) == pytest.approx(0.0, abs=1e-9)  # parallel
    # the force form pushes along the bow
    state = sl.BoatState(np.zeros(3), psi)
    force, torque = sail.forces(state, sl.Wind(6.0, 30.0))
    assert np.allclose(np.cross(force, sl.heading_vector(psi)), 0.0, atol=1e-9)


# ---- the lift/drag sail -------------------------------------------------------------------

def test_sail_coefficients_have_the_usual_shape():
    sail = sl.Sail()
    a = np.radians(np.linspace(0.0, 90.0, 901))
    cl, cd = sail.coefficients(a)
    i = int(np.argmax(cl))
    assert 1.2 <= cl[i] <= 1.5
    assert 15.0 <= math.degrees(a[i]) <= 25.0
    assert cl[-1] == pytest.approx(0.0, abs=1e-9)  # square to the wind: all drag
    assert cd[-1] == pytest.approx(sail.cd0 + sail.c_plate)
    assert np.all(np.diff(cd[a > math.radians(5)]) >= -1e-9)
    assert np.all(cl[a < math.radians(7)] == 0.0)  # luffing


def test_a_boat_running_at_the_wind_speed_feels_no_wind():
    wind = sl.Wind(6.0, 45.0)
    psi = math.radians(45.0)  # bow where the wind blows
    state = sl.BoatState(6.0 * sl.heading_vector(psi), psi)
    va = sl.apparent_wind(wind.vector(), state.velocity)
    assert np.allclose(va, 0.0, atol=1e-12)
    sail = sl.Sail()
    force, torque = sail.forces(state, wind)
    assert np.allclose(force, 0.0) and np.allclose(torque, 0.0)
    assert sl.sail_state(sail, wind, state).fill == 0.0
    # going upwind the apparent wind is stronger and comes from further ahead
    up = sl.BoatState(3.0 * sl.heading_vector(psi + math.radians(135)), psi + math.radians(135))
    va = sl.apparent_wind(wind.vector(), up.velocity)
    assert np.linalg.norm(va) > 6.0
    assert abs(sl.wind_angle(va, up.heading)) < abs(sl.wind_angle(wind.vector(), up.heading))


def test_the_sail_swings_to_leeward_and_flips_when_the_wind_crosses_the_bow():
    sail = sl.Sail(sails_direction=0.5)
    psi = 0.0
    states = {}
    for awa in (-120.0, -60.0, -20.0, 20.0, 60.0, 120.0):
        # wind from awa off the bow (positive: over starboard) blows toward awa + 180
        va = sl.wind_vector(8.0, awa + 180.0)
        st_ = sail.state(va, psi)
        states[awa] = st_
        assert st_.side == (-1 if awa > 0 else 1)  # the belly is away from the wind
        assert math.copysign(1.0, st_.boom) == st_.side
        assert abs(st_.boom) <= sail.max_angle + 1e-12
        assert st_.aoa >= 0.0
        # the sail's force has a component to leeward
        f = sail.aero_force(va, psi)
        assert float(f @ sl.starboard_vector(psi)) * st_.side > 0.0
    assert states[20.0].side != states[-20.0].side
    assert states[60.0].fill == 1.0
    # eased past the wind, the sail weathervanes and luffs
    sail.sails_direction = 1.0
    assert sail.state(sl.wind_vector(8.0, 30.0 + 180.0), psi).fill == 0.0
    # head to wind it luffs whatever the sheet
    for s in (0.0, 0.5, 1.0):
        sail.sails_direction = s
        assert sail.state(sl.wind_vector(8.0, 180.0), psi).fill == 0.0


@given(st.floats(0.0, 360.0), st.floats(-math.pi, math.pi), st.floats(0.5, 20.0),
       st.floats(-1.0, 1.0))
@SETTINGS
def test_a_wind_change_rotates_the_sail_force_accordingly(direction, turn, speed, sheet):
    """Turning the wind and the boat together turns the sail force by the same angle; a
    mirrored wind gives a mirrored force."""
    sail = sl.Sail(sails_direction=sheet)
    psi = 0.7
    f0 = sail.aero_force(sl.wind_vector(speed, direction), psi)
    f1 = sail.aero_force(sl.wind_vector(speed, direction + math.degrees(turn)), psi + turn)
    c, s = math.cos(turn), math.sin(turn)
    # a compass turn by θ: (x, z) → (x cos θ − z sin θ, x sin θ + z cos θ)
    rotated = np.array([f0[0] * c - f0[2] * s, 0.0, f0[0] * s + f0[2] * c])
    assert np.allclose(f1, rotated, atol=1e-9 * (1 + np.linalg.norm(f0)))
    # mirror about the bow: the wind from the other side
    awa = math.degrees(sl.wind_angle(sl.wind_vector(1.0, direction), psi))
    mirrored = math.degrees(psi) + 180.0 - awa  # the direction of the mirrored wind
    fm = sail.aero_force(sl.wind_vector(speed, mirrored), psi)
    bow, stbd = sl.heading_vector(psi), sl.starboard_vector(psi)
    if abs(abs(awa) - 180.0) > 1e-6 and abs(awa) > 1e-6:
        assert float(fm @ bow) == pytest.approx(float(f0 @ bow), abs=1e-6)
        assert float(fm @ stbd) == pytest.approx(-float(f0 @ stbd), abs=1e-6)


def test_the_sail_and_the_keel_make_the_heeling_couple():
    boat = sl.Boat(sail=sl.Sail(sails_direction=0.6))  # boom out 51°
    wind = sl.Wind(8.0, 270.0)  # from the east
    state = sl.BoatState(2.5 * sl.heading_vector(0.0), 0.0)  # bow north: a beam reach
    f, t = boat.sail.forces(state, wind)
    assert float(f @ sl.heading_vector(0.0)) > 0.0  # drive
    assert float(f @ sl.starboard_vector(0.0)) < 0.0  # heeling force to port (leeward)
    # torque = CE height·up × F: rolls the mast to port (about the bow, positive here)
    assert np.allclose(t, np.cross(boat.sail.ce_height * sl.UP, f))
    leeway = sl.BoatState(2.5 * sl.heading_vector(0.0) - 0.2 * sl.starboard_vector(0.0), 0.0)
    fh, th = boat.hull.forces(leeway)
    assert float(fh @ sl.starboard_vector(0.0)) > 0.0  # the keel pushes to windward
    # sail (leeward, above) and keel (windward, below) make the heeling couple of arm
    # CE height + CLR depth: the roll about the bow has the same sense (buoyancy rights it)
    bow = sl.heading_vector(0.0)
    assert float(th @ bow) * float(t @ bow) > 0.0
    total_f, total_t = boat.forces(leeway, wind)
    assert total_f.shape == (3,) and total_t.shape == (3,)


# ---- the hull -----------------------------------------------------------------------------

def test_hull_speed_and_a_steep_resistance_wall():
    hull = sl.Hull()
    ft = hull.lwl / 0.3048
    assert hull.hull_speed == pytest.approx(1.34 * math.sqrt(ft) * sl.KNOT, rel=0.01)
    u = np.linspace(0.0, 1.5 * hull.hull_speed, 200)
    r = hull.resistance(u)
    assert r[0] == 0.0 and np.all(np.diff(r) > 0.0)
    vh = hull.hull_speed
    assert hull.resistance(1.2 * vh) > 2.0 * hull.resistance(vh)
    assert hull.residuary_resistance(vh) / (hull.displacement * sl.G) == pytest.approx(
        hull.residuary * (0.4 / 0.3) ** 6)
    assert hull.keel_slope == pytest.approx(2 * math.pi * hull.keel_aspect / (hull.keel_aspect + 2))
    lam = np.radians(np.linspace(-90.0, 90.0, 181))
    cl = hull.keel_cl(lam)
    assert np.abs(cl).max() <= 1.2 + 1e-12 and np.all(cl * lam >= 0.0)


# ---- the speed polar ----------------------------------------------------------------------

def test_the_polar_has_a_no_go_zone_between_30_and_55_degrees(polar):
    twa = np.array(polar["twa"])
    for i, vt in enumerate(polar["wind_speeds"]):
        speed = np.array(polar["speed"][i])
        no_go = polar["no_go"][i]
        assert 30.0 <= no_go <= 55.0, (vt, no_go)
        assert np.all(speed[twa < no_go - 1.0] < 0.05 * speed.max())
        assert np.all(speed[(twa > no_go + 1.0) & (twa <= 150.0)] > 0.2 * speed.max())
        up, down = polar["upwind"][i], polar["downwind"][i]
        assert no_go <= up["twa"] <= 60.0 and up["vmg"] > 0.0
        assert down["twa"] >= 120.0 and down["vmg"] > 0.0


def test_beam_reach_speeds_grow_with_the_wind_and_stay_below_1_2_hull_speeds(polar):
    beam = polar["beam"]
    hull = polar["hull_speed"]
    assert all(b < c for b, c in zip(beam, beam[1:]))
    assert all(s["speed"] < 1.2 * hull for s in polar["max_speed"])
    # an 8 m boat: a few knots in light air, about the hull speed in a breeze
    assert 1.0 < beam[0] / sl.KNOT < 7.0
    assert 0.9 * hull < beam[2] < 1.2 * hull


def test_the_polar_is_symmetric_port_and_starboard():
    boat = sl.Boat()
    twa = np.radians([40.0, 60.0, 90.0, 135.0, 170.0])
    star = sl.steady_speed(boat, twa, 8.0)
    port = sl.steady_speed(boat, -twa, 8.0)
    assert np.allclose(star, port, rtol=1e-6)
    assert np.all(star > 0.0)


def test_no_wind_no_speed():
    assert np.all(sl.steady_speed(sl.Boat(), np.radians([60.0, 120.0]), 0.0) == 0.0)


def test_the_chart_and_summary(polar, tmp_path):
    text = bench_polar.summary(polar)
    assert len(text.splitlines()) == 1 + len(WIND_SPEEDS)
    assert "no-go" in text
    path = tmp_path / "polar.png"
    bench_polar.chart(polar, path)
    assert path.stat().st_size > 1000
    with pytest.raises(Exception):
        bench_polar.chart(polar, path)  # no overwrite without force
    bench_polar.chart(polar, path, force=True)


# ---- parameters -------------------------------------------------------------------------

@pytest.mark.parametrize("make, name", [
    (lambda: sl.Navigation(max_speed=0.0), "sailing.max_speed"),
    (lambda: sl.Navigation(max_turn_speed=float("nan")), "sailing.max_turn_speed"),
    (lambda: sl.Navigation(mode="jet"), "sailing.navigation"),
    (lambda: sl.Sail(area=-1.0), "sailing.sail_area"),
    (lambda: sl.Sail(max_angle=4.0), "sailing.max_angle"),
    (lambda: sl.Sail(max_angle=0.1, min_angle=0.2), "sailing.min_angle"),
    (lambda: sl.Sail(mode="kite"), "sailing.sail_mode"),
    (lambda: sl.Hull(lwl="long"), "sailing.lwl"),
    (lambda: sl.Hull(gm=float("inf")), "sailing.gm"),
    (lambda: sl.Wind(speed=-3.0), "sailing.wind_speed"),
    (lambda: sl.speed_polar((8.0, 1e4)), "sailing.wind_speed"),
])
def test_bad_parameters_are_one_line_errors_naming_them(make, name):
    with pytest.raises(ParamError) as err:
        make()
    message = str(err.value)
    assert "\n" not in message and len(message) <= 200
    assert message.startswith(name + "=") and "allowed" in message


def test_every_parameter_is_declared():
    params = {p.name: p for p in sl.sailing_params()}
    assert "sailing.max_turn_speed" in params and "sailing.max_angle" in params
    assert params["sailing.max_speed"].section == "spec/000 §1.4"
    for p in params.values():
        assert p.lo is not None and p.hi is not None and p.lo <= p.default <= p.hi
