"""The maritime map (spec/000 §2, §6 criterion 36) typed as real X key events with xdotool into
the maritime window under Xvfb: the held helm, throttle and sails keys move their parameters at
their rates, C switches the camera, Space the UI mode and free navigation, 4 forces the storm,
Esc opens the pause menu (time stops; Resume is clicked with the real pointer) and Esc twice
quits — in the driver's window and in ``natura window maritime``, which exits with status 0.

The scene runs small (tiny cloud bakes and FFT, no spin-up: tests/helpers/window_driver.py's
MARITIME_SMALL) so the window shows its first frame in about a second."""

from __future__ import annotations

import shutil

import pytest

from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


def test_maritime_keys_typed_in_the_window(tmp_path):
    r, _ = drive("maritime-keys", tmp_path)
    dt = r["dt"]
    assert r["render_error"] == ""
    assert {"Ship###natura-hud-ship", "Weather and time###natura-hud-weather"} <= set(
        r["hud_windows"])
    # Right held a third of a second: the helm to starboard at 0.8 per second, exactly per frame
    right = r["right"]
    assert right["frames"] >= 18 and right["helm0"] == 0.0
    assert right["helm"] == pytest.approx(min(1.0, 0.8 * right["frames"] * dt), rel=1e-6)
    left = r["left"]
    assert left["frames"] >= 8
    assert left["helm"] == pytest.approx(left["helm0"] - 0.8 * left["frames"] * dt, rel=1e-6)
    assert r["h_centres"] == 0.0
    up = r["up"]
    assert up["frames"] >= 10
    assert up["throttle"] == pytest.approx(up["throttle0"] + 0.5 * up["frames"] * dt, rel=1e-6)
    down = r["down"]
    assert down["frames"] >= 5
    assert down["throttle"] == pytest.approx(max(-1.0, down["throttle0"]
                                                 - 0.5 * down["frames"] * dt), rel=1e-6)
    z = r["z"]
    assert z["frames"] >= 5
    assert z["sails"] == pytest.approx(max(-1.0, z["sails0"] - 0.4 * z["frames"] * dt), rel=1e-6)
    # 1 2 3: calm, fair, overcast, each with its wind
    assert r["weathers"] == [["calm", 3.0], ["fair", 8.0], ["overcast", 12.0]]
    x = r["x"]
    assert x["sails"] == pytest.approx(x["sails0"] + 0.4 * x["frames"] * dt, rel=1e-6)
    assert r["held_after"] == []  # released keys stop: nothing stuck
    # C: chase → free (W flies the camera), C: chase again
    assert (r["camera0"], r["c_camera"], r["cc_camera"]) == ("chase", "free", "chase")
    w = r["free_w"]
    assert w["m"] == pytest.approx(w["speed"] * w["frames"] * dt, rel=1e-6)
    # Space: free navigation (mouse look, pointer captured), the HUD says so; Space: UI mode
    assert r["ui_mode0"] is True
    assert r["space"]["ui_mode"] is False and r["space"]["mouse_look"] is True
    assert r["space"]["exclusive"] is True and "navigation" in r["space"]["mode_line"]
    again = r["space_again"]
    assert again["ui_mode"] is True and again["mouse_look"] is False
    assert again["exclusive"] is False and "UI mode" in again["mode_line"]
    # 4: the storm, with its wind, in the HUD too
    assert r["weather0"] == "fair"
    assert r["storm"] == {"weather": "storm", "wind_speed": 22.0, "hud_weather": "storm",
                          "hud_wind_speed": 22.0}
    # T plays time; Esc: the pause menu, time stopped, the clock still; Resume restores it
    assert r["t_playing"] is True
    esc = r["esc"]
    assert esc["paused"] and not esc["playing"] and not esc["closing"]
    assert "Paused###natura-pause" in esc["windows"]
    assert r["paused_hour_still"]
    assert r["resume"] == {"paused": False, "playing": True, "ui_mode": True}
    # Esc opens it again, and Esc while it is open quits
    assert r["esc_again_paused"] and r["esc_esc_closes"]


def test_natura_window_maritime_esc_esc_exits_0(tmp_path):
    r, _ = drive("maritime-cli-escape", tmp_path)
    assert r["running_after_first_esc"], r["stderr"]
    assert "paused" in r["stdout"]  # the first Esc opened the pause menu
    assert r["returncode"] == 0, r["stderr"]
    assert r["exit_after_second_esc_s"] < 10.0
