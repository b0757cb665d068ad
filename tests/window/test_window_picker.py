"""``natura`` with no scene named opens the scene picker (issue 38): the gallery's thumbnails,
maritime first; a click on a thumbnail, or the arrows and Enter, open that scene in the window,
and Esc quits without opening one. Driven with real X events under Xvfb
(tests/helpers/picker_driver.py)."""

from __future__ import annotations

import shutil

import pytest

from tests.helpers import picker_driver
from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

pytestmark = [
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


def test_a_click_on_a_thumbnail_opens_that_scene(tmp_path):
    result, _ = drive("click:sky", tmp_path, picker_driver.__file__)
    assert result["picker"], result
    assert result["order"][0] == "maritime" and len(result["order"]) == 11
    assert result["scene_window"] == "Natura — sky", result
    assert result["returncode"] == 0, result["stderr"]


def test_the_arrows_and_enter_open_the_highlighted_scene_and_esc_opens_none(tmp_path):
    result, _ = drive("keys", tmp_path, picker_driver.__file__)
    assert result["picker"] and result["scene_window"] == f"Natura — {result['order'][1]}", result
    assert result["returncode"] == 0, result["stderr"]
    result, _ = drive("escape", tmp_path, picker_driver.__file__)
    assert result["picker"] and result["scene_window"] is None, result
    assert result["returncode"] == 0 and "context:" not in result["stderr"], result["stderr"]
