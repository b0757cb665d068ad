"""Key maps as plain Python (spec/002 §9 criterion 9: the thesis's annex bindings)."""

from __future__ import annotations

import numpy as np
import pytest

from app.params import Param, ParamSet
from app.scenes.keymaps import FLY
from app.scenes.planet import ATMOSPHERE_THESIS
from app.sim.camera import Camera
from app.ui.keymap import Controller
from tests.helpers.keys import hold


def test_w_moves_forward_by_speed_times_dt():
    for keymap in (FLY, ATMOSPHERE_THESIS):
        c = Controller(keymap=keymap, speed=5.0)
        cam = Camera(position=(0, 2, 0), yaw=30, pitch=10)
        p0 = np.array(cam.position)
        hold(c, "W", cam, 0.5)
        c.update(cam, 0.5)
        assert np.allclose(np.array(cam.position) - p0, cam.forward() * 2.5)


def test_thesis_bindings():
    c = Controller(keymap=ATMOSPHERE_THESIS, speed=5.0, turbo_speed=1000.0)
    cam = Camera(position=(0, 2, 0), yaw=0, pitch=0)
    hold(c, "SPACE", cam, 1.0)
    assert cam.position[1] == pytest.approx(7.0)
    hold(c, "LEFT_CTRL", cam, 0.4)
    assert cam.position[1] == pytest.approx(5.0)
    hold(c, "E", cam, 0.5)
    assert cam.yaw == pytest.approx(30.0)  # turn right at 60°/s
    hold(c, "R", cam, 0.25)
    assert cam.pitch == pytest.approx(15.0)
    c.press("Z")
    assert c.turbo
    c.press("PLUS")
    assert c.turbo_speed == 2000.0
    c.press("MINUS")
    c.press("MINUS")
    assert c.turbo_speed == 500.0
    c.press("ASTERISK")
    assert c.turbo_speed == 50000.0
    c.press("SLASH")
    assert c.turbo_speed == 500.0
    p = np.array(cam.position)
    hold(c, "W", cam, 0.1)
    assert np.linalg.norm(np.array(cam.position) - p) == pytest.approx(50.0)  # turbo speed
    c.press("T")  # camera controls off
    p = np.array(cam.position)
    c.press("W")
    c.update(cam, 1.0)
    assert np.allclose(cam.position, p)
    c.press("T")
    events = [a for a, _ in c.take_events()]
    c.press("M")
    c.press("V")
    c.press("P")
    c.press("O")
    c.press("ESCAPE")
    assert [a for a, _ in c.take_events()] == ["toggle_auto_sun", "print_gl_version",
                                              "print_camera", "toggle_mouse", "quit"]
    assert all(a == "print" for a in events)


def test_up_down_move_the_sun():
    params = ParamSet([Param("planet.sun_elevation", 10.0, -90.0, 90.0, "sun")])
    c = Controller(keymap=ATMOSPHERE_THESIS, sun_rate=10.0)
    cam = Camera()
    hold(c, "UP", cam, 1.5, params)
    assert params["planet.sun_elevation"] == pytest.approx(25.0)
    c.press("DOWN")
    c.update(cam, 20.0, params)
    assert params["planet.sun_elevation"] == -90.0  # clamped


def test_release_of_unbound_key_and_unknown_key_are_harmless():
    c = Controller(keymap=FLY)
    assert c.press("NUMBER_7") is None
    c.release("NUMBER_7")
    assert c.held == set()


def test_ocean_keys_pick_the_wave_model_and_keep_the_fly_keys():
    from app.scenes.ocean import OCEAN

    c = Controller(OCEAN)
    for key, model in (("NUMBER_1", "sine"), ("NUMBER_2", "gerstner"), ("NUMBER_3", "fft")):
        c.press(key)
        c.release(key)
        assert c.take_events() == [(f"set:ocean.model={model}", None)]
    assert all(OCEAN.action(k) == a for k, a in FLY.bindings.items())
    assert any("Gerstner" in row[1] for row in OCEAN.help)


def test_bracket_keys_get_the_code_pyglet_delivers():
    """moderngl-window 3.1.1 gives LEFT_BRACKET / RIGHT_BRACKET pyglet's BRACELEFT / BRACERIGHT
    codes ({ }), but the [ ] keys deliver BRACKETLEFT / BRACKETRIGHT (0x5b / 0x5d, seen under
    Xvfb with xdotool): the window's table must name those."""
    from types import SimpleNamespace

    from app.ui.keymap import key_names

    mglw_keys = SimpleNamespace(LEFT_BRACKET=0x7B, RIGHT_BRACKET=0x7D, W=0x77, ACTION_PRESS=1)
    pyglet_key = SimpleNamespace(BRACKETLEFT=0x5B, BRACKETRIGHT=0x5D, RCTRL=0xFFE4)
    names = key_names(mglw_keys, pyglet_key)
    assert names[0x5B] == "LEFT_BRACKET" and names[0x5D] == "RIGHT_BRACKET"
    assert names[0xFFE4] == "RIGHT_CTRL" and names[0x77] == "W"
    assert 1 not in names  # ACTION_* are not keys
    assert key_names(mglw_keys)[0x7B] == "LEFT_BRACKET"  # without pyglet: its table only


@pytest.mark.filterwarnings("ignore:Importing PyGLM:PendingDeprecationWarning")
def test_every_bound_key_is_a_name_the_window_can_produce():
    """A typo in a key map ("LEFT_BRAKET", "CTRL") would bind a key that never fires."""
    from moderngl_window.context.base import BaseKeys

    from app.scenes.ocean import OCEAN
    from app.ui.keymap import CHARACTER_KEYS, CHARACTERS, PYGLET_KEY_NAMES

    window_names = {n for n in dir(BaseKeys) if n.isupper() and not n.startswith("ACTION_")}
    producible = (window_names | set(PYGLET_KEY_NAMES.values()) | set(CHARACTERS.values()))
    for keymap in (FLY, OCEAN, ATMOSPHERE_THESIS):
        unknown = set(keymap.bindings) - producible
        assert not unknown, (keymap.name, unknown)
        # a key whose key event is dropped must come through as a character instead
        assert not (set(keymap.bindings) & CHARACTER_KEYS) - set(CHARACTERS.values())
