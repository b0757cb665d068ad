"""The teaching panes in a real window under Xvfb, typed with real X events (xdotool): the
save → recompile → marked line → fix loop on a user's copy, the first save of Natura's own
shaders going into a copy (Ctrl+A and typing in the copy's folder field), and the A/B pane
comparing planet method 2 with Hillaire — on imgui-bundle ≥ 1.92, drawn by
app/ui/imgui_renderer.py."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

DRIVER = Path(__file__).parent.parent / "helpers" / "editor_driver.py"

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


def _drive(mode, work):
    return drive(mode, work, DRIVER)


def test_imgui_bundle_is_a_current_one():
    import imgui_bundle

    major, minor = (int(x) for x in imgui_bundle.__version__.split(".")[:2])
    assert (major, minor) >= (1, 92), imgui_bundle.__version__


def test_break_a_shader_see_the_marked_line_fix_it(tmp_path):
    r, proc = _drive("copy", tmp_path)
    assert r["f2_shows_editor"] and r["f2_hides_editor"]
    assert r["editor_has_keyboard"] and r["camera_kept"]  # Ctrl+S did not fly the camera back
    assert r["modified_before_save"] and r["saved_on_disk"]
    line = r["typo_line"]
    assert line >= 0 and list(r["markers"]) == [str(line)], r["markers"]
    message = r["markers"][str(line)]
    assert message.startswith(f"my-glsl/sky/sky.frag:{line + 1}: ") and "error" in message
    assert r["errors"] == [message]
    assert f"natura: shader error: {message}" in proc.stderr  # whole, on the terminal
    assert r["errors_after_fix"] == [] and r["markers_after_fix"] == []
    assert r["file_restored"] and r["saves"] == 2


def test_first_save_of_natura_own_shaders_goes_into_a_copy(tmp_path):
    r, _ = _drive("own", tmp_path)
    assert r["asks_for_copy"] and r["offered_name"] == "my-glsl"
    assert r["typed_name"] == "lesson1"  # Ctrl+A selected the offered name, typing replaced it
    assert r["copy_made"] and r["saved_in_copy"] and r["own_untouched"]
    assert Path(r["library_root"]) == (tmp_path / "lesson1").resolve()
    assert Path(r["editor_file"]) == (tmp_path / "lesson1" / "sky" / "sky.frag").resolve()
    assert r["errors"] == []
    assert r["no_temp_left"] == ["lesson1"]


def test_compare_method_2_against_hillaire_in_the_planet_window(tmp_path):
    r, _ = _drive("compare", tmp_path)
    assert r["f3_shows"] and r["problem"] is None
    assert r["quality_charts"] >= 1 and r["quality_chosen"]  # --quality auto's chosen point
    assert (r["a"], r["b"]) == ("planet.method=lut", "planet.method=hillaire")
    assert r["size"] == [160, 90]  # a software renderer starts small
    assert all(ms > 0 for ms in r["ms"]) and r["textures"] == ["a", "b", "heat"]
    err_lut, err_hillaire = r["errors"]
    assert 0 < err_lut < 0.1 and err_hillaire > 2 * err_lut  # multiple scattering adds light
    assert r["heat_max"] > 0
    caption = " ".join(r["caption"])
    assert " ms [" in caption and "B/A" in caption and "error vs reference" in caption
    assert r["live_params_kept"] and r["still_rendering"] and r["progress_frames"] > 0
    assert r["search_typed"] == "shadow" and r["search_replaced"] == "lut"  # Ctrl+F, Ctrl+A
