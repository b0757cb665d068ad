"""Every documented window key (docs/commands.md "Window controls"), typed as real X key events with
xdotool into a window under Xvfb — never by calling the handler — each with an effect a test
can see: the camera moved or turned by speed × frames × dt, the clock moved 15 min a press, a
screenshot file appeared, the panel's pixels went, the process ended on Esc.

The ocean's 1 / 2 / 3 are typed the same way in tests/window/test_window.py
(test_ocean_models_switch_live_in_the_window)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


def _pressed(r, name: str) -> bool:
    return any(kind == "press" and key == name for kind, _, key in r["received"])


def test_fly_map_keys_typed_in_the_sky_window(tmp_path):
    r, _ = drive("fly-keys", tmp_path)
    step = r["speed"] * r["dt"]  # metres a frame
    assert r["render_error"] == ""
    # F1 hides the panel (its pixels go) and shows it again
    assert r["f1_hides"] and r["f1_again_shows"] and r["f1_panel_pixels"] > 2000
    # W A S D Q E: each moves the camera its way, speed × frames × dt, and no other way
    assert set(r["moves"]) == set("wsadqe")
    for key, m in r["moves"].items():
        assert m["frames"] >= 8, (key, m)
        assert m["along_m"] == pytest.approx(m["frames"] * step, rel=1e-6), (key, m)
        assert m["across_m"] < 1e-6, (key, m)
    # Shift held: 4x faster
    assert r["shift_fast_held"]
    assert r["shift_w"]["along_m"] == pytest.approx(4 * r["shift_w"]["frames"] * step, rel=1e-6)
    # R: back to the starting view after all that flying
    assert r["r_resets"] == {"position_error_m": 0.0, "yaw_error": 0.0, "pitch_error": 0.0}
    # M: mouse look on — real pointer motion 40 px right turns 6° right — and off again
    assert r["m_mouse_look"] and r["m_mouse_yaw"] == pytest.approx(40 * 0.15)
    assert r["m_again_off"] and r["m_off_mouse_yaw"] == 0.0
    # Space: time plays (the clock advances), Space again: paused
    assert r["space_plays"] and r["space_hour_advance"] > 0.01 and r["space_pauses"]
    # ] four times, [ six times: 15 minutes a press, each press
    steps = np.diff(r["bracket_hours"])
    assert list(np.round(steps, 9)) == [0.25] * 4 + [-0.25] * 6
    assert _pressed(r, "LEFT_BRACKET") and _pressed(r, "RIGHT_BRACKET")
    # Up / Down are the planet's sun keys: here they leave the camera alone (no crash)
    assert r["up_down_camera_still"]
    # P and F12: one new file each, on disk
    assert r["screenshots"] == ["shots/sky-0001.png", "shots/sky-0002.png"]
    assert r["shot_files"] == r["screenshots"]
    for shot in r["shot_files"]:
        assert (tmp_path / shot).stat().st_size > 1000
    assert r["escape_closes"]
    assert r["presses"] >= 30


def test_atmosphere_thesis_keys_typed_in_the_planet_window(tmp_path):
    """spec/002 §4's bindings: each key of the planet map, typed."""
    r, _ = drive("planet-keys", tmp_path)
    step, turn = r["speed"] * r["dt"], r["turn_rate"] * r["dt"]
    assert r["render_error"] == ""
    # M: the key map's toggle_auto_sun (a parameter action), twice
    assert r["auto_sun_after_m"] is not r["auto_sun_before"]
    assert r["auto_sun_after_m_m"] is r["auto_sun_before"]
    # Up / Down held: the sun rises and sinks at sun_rate
    for key, sign in (("sun_up", 1), ("sun_down", -1)):
        s = r[key]
        assert s["frames"] >= 10
        assert s["deg"] == pytest.approx(sign * s["frames"] * r["sun_rate"] * r["dt"]), key
    # W A S D, Space up, either Ctrl down
    assert set(r["moves"]) == {"w", "s", "a", "d", "space", "Control_L", "Control_R"}
    for key, m in r["moves"].items():
        assert m["frames"] >= 6 and m["along_m"] == pytest.approx(m["frames"] * step), (key, m)
    # xdotool's Control_R also presses the left Ctrl under Xvfb: check the right one was named
    assert _pressed(r, "RIGHT_CTRL") and _pressed(r, "LEFT_CTRL")
    # Q / E turn, R / F pitch, at turn_rate, each about its own axis only
    for key, axis, sign in (("q", "yaw", -1), ("e", "yaw", 1), ("r", "pitch", 1),
                            ("f", "pitch", -1)):
        t = r["turns"][key]
        other = "pitch" if axis == "yaw" else "yaw"
        assert t[axis] == pytest.approx(sign * t["frames"] * turn), (key, t)
        assert t[other] == 0.0, (key, t)
    assert r["o_mouse_look"] and r["o_again_off"]
    # Z: turbo on (W at the turbo speed), Z again: off
    assert r["z_turbo"] and r["z_again_off"]
    tw = r["turbo_w"]
    assert tw["m"] == pytest.approx(tw["frames"] * tw["turbo_speed"] * r["dt"]) and tw["m"] > 30
    # + − * / on the main keyboard, then on the keypad: ×2 ÷2 ×100 ÷100
    s0 = r["turbo_speeds"][0]
    cycle = [s0, 2 * s0, s0, 100 * s0, s0]
    assert r["turbo_speeds"] == pytest.approx(cycle + cycle[1:])
    # T: camera controls off (W held moves nothing), T: on again
    assert r["t_controls_off"] and r["t_off_moved_m"] == 0.0 and r["t_controls_on"]
    assert r["v_message"].startswith("OpenGL ")
    assert r["p_message"].startswith("camera (")
    assert r["f1_shows"] and r["f1_hides"]
    assert r["screenshots"] == ["screenshots/planet-0001.png"]
    assert (tmp_path / r["screenshots"][0]).stat().st_size > 500
    assert r["escape_closes"]
    assert r["presses"] >= 35


def test_escape_ends_natura_window(tmp_path):
    """`natura window sky` as a user starts it: Esc typed into it ends the process, status 0."""
    r, _ = drive("cli-escape", tmp_path)
    assert r["running_before_esc"], r  # it did not just run out of frames
    assert r["returncode"] == 0, r["stderr"]
    assert r["exit_after_esc_s"] < 10.0


def test_a_key_held_when_the_window_loses_the_focus_is_let_go(tmp_path):
    """A real focus change under Xvfb: W held, another window takes the keyboard, and W's
    release goes there. The window lets go of W when it loses the focus: the camera stops."""
    r, _ = drive("focus-loss", tmp_path)
    assert r["held_before"] == ["forward"] and r["moved_while_held_m"] > 0
    assert r["let_go"] and r["held_after"] == []
    assert r["moved_after_m"] == 0.0
