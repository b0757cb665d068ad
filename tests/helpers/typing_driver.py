"""Types into the window's shader editor with real X events (xdotool under Xvfb), at a high
and at a low frame rate, and prints the findings as one ``RESULT {json}`` line (read by
tests/window/test_window_typing.py).

A high frame rate: one character typed, then frames drawn until the editor has it, then the
next. A low frame rate: the whole line is typed while no frame is drawn (every key event of it
arrives within one frame, as behind a frame that lasts as long as the typing), then frames.

``brackets``: on a user's copy, a line with brackets typed both ways and saved with Ctrl+S;
the file must hold exactly what was typed (the widget's own pairing saved `x(y))`). First, in
one slow frame, Ctrl+F and "wind": the panel's search box gets all of "wind".

``backspace``: on Natura's own shaders, Ctrl+S then two BackSpaces in one slow frame: the
BackSpaces were pressed while the text had the keyboard, so they erase text there, and the
"Save into a copy" dialog that opens after them keeps its offered folder name whole.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tests.helpers.editor_driver import _chord, _click, _type, _until  # noqa: E402
from tests.helpers.window_driver import XKeys  # noqa: E402

#: what the tests type: brackets typed over, one closer that was not typed for the user (the
#: last), nested pairs and a pair before a closer
LINE = "// x(y) a[i] {b(c)} f())"


def _open(win, keys: XKeys, frag: Path) -> None:
    keys.tap("F2")
    win.editor.open(frag)
    keys.frames(3)
    x0, y0, x1, y1 = win.editor.text_rect
    _click(keys, (x0 + x1) / 2, (y0 + y1) / 2)
    _chord(keys, "ctrl", "End")


def _burst(keys: XKeys, args: list[str], arrived) -> int:
    """Send X events with xdotool while no frame is drawn; dispatch them (as a frame's end
    does) until ``arrived()``; returns the frames drawn meanwhile (0: all in one frame)."""
    subprocess.run(["xdotool", *args], check=True, timeout=60)
    frames = 0
    while not keys.dispatch(arrived, wait_s=5.0):
        keys.frames(1)  # never in practice: xdotool returns once the server has them all
        frames += 1
    return frames


def _last_line(win) -> str:
    return win.editor.editor.get_text().rstrip("\n").split("\n")[-1]


def brackets_run(work: str) -> int:
    from app import DEFAULT_SHADER_ROOT
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    work_dir = Path(work)
    os.chdir(work_dir)
    shaders = work_dir / "my-glsl"
    shutil.copytree(DEFAULT_SHADER_ROOT, shaders)
    frag = shaders / "sky" / "sky.frag"
    params = scene_params("sky", shader_root=shaders, sets=["time.hour=10"])
    win = W.NaturaWindow("sky", params, get_scene("sky").new_camera(), (720, 450), shaders)
    keys = XKeys(win, "^Natura .* sky$")
    out: dict = {}
    # in one slow frame, from the scene: Ctrl+F, then "wind" for the panel's search box (the box
    # takes the keyboard a frame after it is asked to, and drops that frame's characters)
    n = len(keys.received)
    _burst(keys, ["key", "--delay", "2", "ctrl+f"], lambda: sum(
        1 for e in keys.received[n:] if e[0] == "release") >= 2)
    _burst(keys, ["type", "--delay", "2", "wind"], lambda: sum(
        1 for e in keys.received[n:] if e[0] == "char") >= 4)
    _until(keys, lambda: len(win.panel_state.search) >= 4, 120)
    keys.frames(2)
    out["search_after_ctrl_f"] = win.panel_state.search
    _open(win, keys, frag)
    keys.tap("Return")
    for char in LINE:  # a high frame rate: each character shown before the next is typed
        _type(keys, char)
    _until(keys, lambda: _last_line(win) == LINE, 120)
    out["fast_line"] = _last_line(win)
    keys.tap("Return")
    n = len(keys.received)
    out["slow_frames_between"] = _burst(keys, ["type", "--delay", "2", LINE], lambda: sum(
        1 for e in keys.received[n:] if e[0] == "char") >= len(LINE))
    _until(keys, lambda: _last_line(win) == LINE, 240)
    out["slow_line"] = _last_line(win)
    _chord(keys, "ctrl", "s")
    # ImGui hands a slow frame's key events out over the next frames: Ctrl+S comes after them
    _until(keys, lambda: win.editor.saves >= 1, 600)
    saved = frag.read_text().rstrip("\n").split("\n")
    out["saved_lines"] = saved[-2:]
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def backspace_run(work: str) -> int:
    from app import DEFAULT_SHADER_ROOT
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    work_dir = Path(work)
    os.chdir(work_dir)
    own = DEFAULT_SHADER_ROOT / "sky" / "sky.frag"
    params = scene_params("sky", sets=["time.hour=10"])
    win = W.NaturaWindow("sky", params, get_scene("sky").new_camera(), (720, 450))
    keys = XKeys(win, "^Natura .* sky$")
    out: dict = {}
    _open(win, keys, own)
    _type(keys, "\n// abc", lambda: _last_line(win) == "// abc")
    n = len(keys.received)
    out["slow_frames_between"] = _burst(
        keys, ["key", "--delay", "2", "ctrl+s", "BackSpace", "BackSpace"],
        lambda: sum(1 for e in keys.received[n:] if e[0] == "release") >= 4)
    out["asks_for_copy"] = _until(keys, lambda: win.editor.modal_open, 120)
    keys.frames(3)
    out["copy_name"] = win.editor.copy_name
    out["editor_line"] = _last_line(win)
    keys.tap("Return")
    _until(keys, lambda: not win.editor.modal_open, 60)
    copy = work_dir / out["copy_name"] if out["copy_name"] else None
    saved = copy / "sky" / "sky.frag" if copy is not None else None
    out["saved_line"] = (saved.read_text().rstrip("\n").split("\n")[-1]
                         if saved is not None and saved.is_file() else None)
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


if __name__ == "__main__":
    runs = {"brackets": brackets_run, "backspace": backspace_run}
    sys.exit(runs[sys.argv[2]](sys.argv[1]))
