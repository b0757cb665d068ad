"""Typing in the F2 editor with real X key events (xdotool under Xvfb), at a high frame rate and
at a low one (every key of a line in one frame): brackets typed over as editors do, and keys that
go to the widget that had the keyboard when they were pressed. The trial saved `x(y))` for
`x(y)`, and a BackSpace typed after Ctrl+S erased the "Save into a copy" dialog's folder name;
and "wind" typed with Ctrl+F in one slow frame searched for "ind"."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

DRIVER = Path(__file__).parent.parent / "helpers" / "typing_driver.py"

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


def _drive(mode, work):
    return drive(mode, work, DRIVER)[0]


def test_typed_brackets_are_saved_as_typed_at_any_frame_rate(tmp_path):
    from tests.helpers.typing_driver import LINE

    r = _drive("brackets", tmp_path)
    assert r["search_after_ctrl_f"] == "wind"  # not "ind": Ctrl+F and typing in one frame
    assert r["slow_frames_between"] == 0  # the slow run's keys all arrived within one frame
    assert r["fast_line"] == LINE and r["slow_line"] == LINE
    assert r["saved_lines"] == [LINE, LINE]  # not `// x(y)) a[i]] {b(c))}} f()))`


def test_backspace_after_ctrl_s_in_a_slow_frame_erases_text_not_the_folder_name(tmp_path):
    r = _drive("backspace", tmp_path)
    assert r["slow_frames_between"] == 0
    assert r["asks_for_copy"] and r["copy_name"] == "my-glsl"  # the offered name, whole
    assert r["editor_line"] == "// a"  # both BackSpaces went to the text, which had the keys
    assert r["saved_line"] == "// a"
