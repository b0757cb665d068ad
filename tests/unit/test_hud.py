"""The maritime HUD's logic without a window (spec/000 §2, §6 criterion 36): the held
``hold:NAME=RATE`` keys of the controller, the key map's actions, ``cycle:`` steps, the angle
fold of the wind dial and the dial's geometry. The HUD figures of a running scene
(wind_relative = wind direction − heading) are in tests/gl/test_maritime_hud.py; the keys typed
into a real window in tests/window/test_window_maritime.py."""

from __future__ import annotations

import math

import pytest

from app.params import Param, ParamSet
from app.runtime import scene_params
from app.scenes.keymaps import FLY
from app.scenes.maritime import MARITIME, WEATHER
from app.scenes.ocean import OCEAN
from app.scenes.planet import ATMOSPHERE_THESIS
from app.sim.camera import Camera
from app.sim.maths import wrap_degrees as wrap180
from app.ui.hud import dial_arrow, dial_point, mode_line
from app.ui.keymap import Controller, cycle_value, parse_hold
from tests.helpers.keys import action_kind, action_parameter, hold


def _boat_params() -> ParamSet:
    return ParamSet([Param("boat.helm", 0.0, -1.0, 1.0, "helm"),
                     Param("boat.throttle", 0.0, -1.0, 1.0, "throttle"),
                     Param("boat.sails", 0.55, -1.0, 1.0, "sails")])


def test_held_helm_moves_at_its_rate_and_clamps_at_the_range():
    c, cam, p = Controller(keymap=MARITIME), Camera(), _boat_params()
    c.press("RIGHT")
    c.update(cam, 0.5, p)
    assert p["boat.helm"] == pytest.approx(0.4)  # 0.8 per second
    c.update(cam, 0.25, p)
    assert p["boat.helm"] == pytest.approx(0.6)
    c.update(cam, 10.0, p)
    assert p["boat.helm"] == 1.0  # clamped at the top of its range
    c.release("RIGHT")
    c.update(cam, 1.0, p)
    assert p["boat.helm"] == 1.0  # released: it stays where it was
    c.press("LEFT")
    c.update(cam, 1.0, p)
    assert p["boat.helm"] == pytest.approx(0.2)
    c.update(cam, 10.0, p)
    assert p["boat.helm"] == -1.0  # and at the bottom
    c.release("LEFT")
    assert not c.held


def test_throttle_and_sails_keys_and_opposite_keys_cancel():
    c, cam, p = Controller(keymap=MARITIME), Camera(), _boat_params()
    hold(c, "UP", cam, 1.0, p)
    assert p["boat.throttle"] == pytest.approx(0.5)
    hold(c, "DOWN", cam, 0.5, p)
    assert p["boat.throttle"] == pytest.approx(0.25)
    hold(c, "X", cam, 0.5, p)
    assert p["boat.sails"] == pytest.approx(0.75)
    c.press("Z")
    c.update(cam, 0.25, p)
    assert p["boat.sails"] == pytest.approx(0.65)
    c.press("X")  # both held: −0.4 + 0.4 per second
    c.update(cam, 1.0, p)
    assert p["boat.sails"] == pytest.approx(0.65)
    c.release("Z")
    c.release("X")
    assert not c.held


def test_release_stops_and_nothing_sticks():
    c, cam, p = Controller(keymap=MARITIME), Camera(), _boat_params()
    c.release("RIGHT")  # a release without its press (the press went to a text field)
    c.press("RIGHT")
    c.press("RIGHT")  # auto-repeat presses: still one held action
    c.release("RIGHT")
    c.update(cam, 1.0, p)
    assert p["boat.helm"] == 0.0 and not c.held
    c.press("RIGHT")
    c.release_all()  # the window lost the keyboard
    c.update(cam, 1.0, p)
    assert p["boat.helm"] == 0.0
    # a hold on a parameter the scene lacks, and updates without parameters, do nothing
    c.press("RIGHT")
    c.update(cam, 1.0, ParamSet([]))
    c.update(cam, 1.0)
    c.release("RIGHT")
    assert not c.held
    # a hold never moves the camera
    cam2 = Camera(position=(1.0, 2.0, 3.0), yaw=10.0, pitch=5.0)
    hold(c, "LEFT", cam2, 1.0, p)
    assert cam2.position == (1.0, 2.0, 3.0) and (cam2.yaw, cam2.pitch) == (10.0, 5.0)


def test_hold_parsing_and_a_hold_in_any_key_map():
    assert parse_hold("hold:boat.helm=-0.8") == ("boat.helm", -0.8)
    for bad in ("hold:boat.helm", "hold:=1", "set:boat.helm=1"):
        with pytest.raises(ValueError):
            parse_hold(bad)
    from app.scenes.keymaps import KeyMap

    custom = KeyMap("custom", {"K": "hold:sky.sun_size=0.1"})
    p = ParamSet([Param("sky.sun_size", 0.05, 0.0, 1.0, "sun")])
    c = Controller(keymap=custom)
    hold(c, "K", Camera(), 2.0, p)
    assert p["sky.sun_size"] == pytest.approx(0.25)


def test_maritime_actions_all_resolve_to_known_kinds():
    params = scene_params("maritime")
    for keymap in (MARITIME, FLY, OCEAN, ATMOSPHERE_THESIS):
        for key, action in keymap.bindings.items():
            resolved = keymap.resolve(action)
            assert action_kind(resolved) is not None, (keymap.name, key, action)
    kinds = {key: action_kind(MARITIME.resolve(a)) for key, a in MARITIME.bindings.items()}
    assert kinds["LEFT"] == kinds["RIGHT"] == kinds["UP"] == kinds["Z"] == "hold"
    assert kinds["C"] == "cycle" and kinds["NUMBER_4"] == "set" and kinds["H"] == "set"
    assert MARITIME.bindings["SPACE"] == "toggle_ui"
    assert MARITIME.bindings["ESCAPE"] == "pause_menu" and MARITIME.bindings["T"] == "toggle_time"
    for key, action in MARITIME.bindings.items():
        name = action_parameter(MARITIME.resolve(action))
        if name is None:
            continue
        assert name in params, (key, action)
        if action.startswith("set:"):  # the value is one the parameter accepts
            params.spec(name).validate(action.partition("=")[2]
                                       if params.spec(name).kind == "choice"
                                       else float(action.partition("=")[2]))
        if action.startswith("hold:"):
            spec = params.spec(name)
            assert spec.lo is not None and spec.hi is not None, name
    # the weather keys cover the forced states, in order
    assert [MARITIME.bindings[f"NUMBER_{i}"].partition("=")[2] for i in range(1, 5)] == \
        list(WEATHER)
    assert action_kind("no_such_action") is None and action_kind("hold:") is None


def test_cycle_steps_through_the_choices_and_wraps():
    params = scene_params("maritime")
    spec = params.spec("maritime.camera")
    assert cycle_value(spec, "chase") == "free"
    assert cycle_value(spec, "free") == "chase"
    weather = params.spec("maritime.weather")
    seen, w = [], params["maritime.weather"]
    for _ in range(len(weather.choices)):
        w = cycle_value(weather, w)
        seen.append(w)
    assert sorted(seen) == sorted(weather.choices) and w == params["maritime.weather"]
    assert cycle_value(Param("x.on", True, kind="bool"), True) is False
    mode = Param("x.mode", 0, 0, 3, kind="int")
    assert [cycle_value(mode, v) for v in (0, 1, 2, 3)] == [1, 2, 3, 0]
    with pytest.raises(ValueError):
        cycle_value(Param("x.v", 1.0, 0.0, 2.0), 1.0)


@pytest.mark.parametrize("angle, folded", [(0.0, 0.0), (180.0, 180.0), (-180.0, 180.0),
                                           (190.0, -170.0), (-190.0, 170.0), (360.0, 0.0),
                                           (540.0, 180.0), (-0.5, -0.5), (725.0, 5.0),
                                           (-359.0, 1.0)])
def test_wrap180(angle, folded):
    assert wrap180(angle) == pytest.approx(folded)
    assert -180.0 < wrap180(angle) <= 180.0


def test_wind_dial_geometry():
    c = (100.0, 100.0)
    assert dial_point(c, 10.0, 0.0) == pytest.approx((100.0, 90.0))  # the bow is up
    assert dial_point(c, 10.0, 90.0) == pytest.approx((110.0, 100.0))  # starboard right
    assert dial_point(c, 10.0, -90.0) == pytest.approx((90.0, 100.0))
    assert dial_point(c, 10.0, 180.0) == pytest.approx((100.0, 110.0))
    tail, head = dial_arrow(c, 10.0, 90.0)  # wind blowing to starboard: from port
    assert tail == pytest.approx((90.0, 100.0)) and head == pytest.approx((110.0, 100.0))
    tail, head = dial_arrow(c, 10.0, 180.0)  # a following wind comes from the bow's side
    assert tail[1] < head[1]
    for a in (-135.0, -30.0, 45.0, 170.0):
        tail, head = dial_arrow(c, 10.0, a)
        assert math.dist(tail, head) == pytest.approx(20.0)
        assert math.atan2(head[0] - c[0], c[1] - head[1]) == pytest.approx(math.radians(a))


def test_the_hud_says_which_mode_is_on():
    assert "UI mode" in mode_line(True) and "Space" in mode_line(True)
    assert "navigation" in mode_line(False).lower() and "Space" in mode_line(False)
    assert "Esc" in mode_line(False, paused=True)
