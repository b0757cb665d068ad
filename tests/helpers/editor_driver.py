"""Drives the window's shader editor with real X events (xdotool under Xvfb) and prints its
findings as one ``RESULT {json}`` line (read by tests/window/test_window_editor.py).

``copy``: the window runs on a user's copy of the shaders. F2 opens the editor; a click puts
the caret in sky.frag's text; Ctrl+End, then a broken line typed; Ctrl+S saves; the library
recompiles, the editor marks the line the compiler blames (its message as the marker's
tooltip) and the terminal prints it whole; Backspace removes the typo, Ctrl+S, the marker goes.

``own``: the window runs on Natura's own shaders. An edit, then Ctrl+S asks for a copy (the
modal's folder field has the focus); Ctrl+A selects its text, typing replaces it, Enter copies
the folder, moves the programs there and saves into the copy; Natura's file is untouched.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tests.helpers.window_driver import XKeys  # noqa: E402

TYPO = "float natura_typo = ;"
#: the compare run's window: room for the A/B pane and for the top of the panel's first quality
#: chart (at y = 455: ImGui draws no chart below the window's bottom edge), not more: the live
#: planet behind them costs by the pixel (760x480 before)
SIZE = (600, 480)


def _type(keys: XKeys, text: str, done=None) -> None:
    """Type ``text`` as X events; wait until the window has received its characters and, with
    ``done``, until ``done()`` holds (the widget has taken them all in: ImGui takes a character
    a frame)."""
    n = len(keys.received)
    subprocess.run(["xdotool", "type", "--delay", "20", text], check=True, timeout=60)
    printable = len(text.replace("\n", ""))  # a newline arrives as the Return key, not a char

    def typed():
        return sum(1 for e in keys.received[n:] if e[0] == "char") >= printable

    for _ in range(400):
        if keys.dispatch(typed):
            break
        keys.frames(1)
    keys.frames(1)
    if done is not None:
        _until(keys, done, 120)


def _click(keys: XKeys, x: float, y: float) -> None:
    subprocess.run(["xdotool", "mousemove", "--window", keys.id, str(int(x)), str(int(y)),
                    "click", "1"], check=True, timeout=30)
    keys.frames(4)


def _chord(keys: XKeys, *names: str) -> None:
    """Keys held together (Ctrl+S): each down in order, a frame drawn with them all down, then
    each up in reverse and a frame after."""
    for name in names:
        keys.down(name)
    keys.frames(1)
    for name in reversed(names):
        keys.up(name)
    keys.frames(1)


def _until(keys: XKeys, check, frames: int = 240) -> bool:
    for _ in range(frames):
        if check():
            return True
        keys.frames(1)
    return bool(check())


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def copy_run(work: str) -> int:
    from app import DEFAULT_SHADER_ROOT
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    work_dir = Path(work)
    os.chdir(work_dir)
    shaders = work_dir / "my-glsl"
    shutil.copytree(DEFAULT_SHADER_ROOT, shaders)
    frag = shaders / "sky" / "sky.frag"
    original = frag.read_text()
    params = scene_params("sky", shader_root=shaders, sets=["time.hour=10"])
    win = W.NaturaWindow("sky", params, get_scene("sky").new_camera(), (720, 450), shaders)
    keys = XKeys(win, "^Natura .* sky$")
    out: dict = {}
    keys.tap("F2")
    out["f2_shows_editor"] = win.editor.shown
    win.editor.open(frag)
    keys.frames(3)
    x0, y0, x1, y1 = win.editor.text_rect
    out["text_rect"] = [x0, y0, x1, y1]
    _click(keys, (x0 + x1) / 2, (y0 + y1) / 2)
    out["editor_has_keyboard"] = bool(win.imgui.get_io().want_capture_keyboard)
    _chord(keys, "ctrl", "End")
    _type(keys, "\n" + TYPO, lambda: TYPO in win.editor.editor.get_text())
    out["modified_before_save"] = win.editor.modified
    lines = win.editor.editor.get_text().split("\n")
    out["typo_line"] = next((i for i, line in enumerate(lines) if TYPO in line), -1)
    cam_before = list(win.scene.camera.position)
    _chord(keys, "ctrl", "s")
    out["saved_on_disk"] = TYPO in frag.read_text()
    out["camera_kept"] = list(win.scene.camera.position) == cam_before  # S did not fly back
    _until(keys, lambda: bool(win.editor.marked))
    out["markers"] = {str(k): v for k, v in win.editor.marked.items()}
    out["errors"] = [str(e) for e in win.session.gpu.shaders.errors()]
    _chord(keys, "shift", "Home")  # the typed line selected, then deleted with its newline
    keys.tap("BackSpace", hold_frames=1)
    keys.tap("BackSpace", hold_frames=1)
    _chord(keys, "ctrl", "s")
    _until(keys, lambda: not win.session.gpu.shaders.errors() and not win.editor.marked)
    out["errors_after_fix"] = [str(e) for e in win.session.gpu.shaders.errors()]
    out["markers_after_fix"] = list(win.editor.marked)
    out["file_restored"] = frag.read_text().rstrip("\n") == original.rstrip("\n")
    out["saves"] = win.editor.saves
    keys.tap("F2")
    out["f2_hides_editor"] = not win.editor.shown
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def own_run(work: str) -> int:
    from app import DEFAULT_SHADER_ROOT
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    work_dir = Path(work)
    os.chdir(work_dir)
    own = DEFAULT_SHADER_ROOT / "sky" / "sky.frag"
    own_sha = _sha(own)
    params = scene_params("sky", sets=["time.hour=10"])
    win = W.NaturaWindow("sky", params, get_scene("sky").new_camera(), (720, 450))
    keys = XKeys(win, "^Natura .* sky$")
    out: dict = {}
    keys.tap("F2")
    win.editor.open(own)
    keys.frames(3)
    x0, y0, x1, y1 = win.editor.text_rect
    _click(keys, (x0 + x1) / 2, (y0 + y1) / 2)
    _chord(keys, "ctrl", "End")
    _type(keys, "\n// my note", lambda: "// my note" in win.editor.editor.get_text())
    _chord(keys, "ctrl", "s")
    out["asks_for_copy"] = _until(keys, lambda: win.editor.modal_open, 60)
    out["offered_name"] = win.editor.copy_name
    _chord(keys, "ctrl", "a")
    _type(keys, "lesson1")
    _until(keys, lambda: win.editor.copy_name == "lesson1", 60)  # ImGui takes a char a frame
    out["typed_name"] = win.editor.copy_name
    keys.tap("Return")
    _until(keys, lambda: not win.editor.modal_open, 60)
    copy = work_dir / "lesson1"
    out["copy_made"] = (copy / "common").is_dir()
    out["saved_in_copy"] = (copy / "sky" / "sky.frag").is_file() and (
        "// my note" in (copy / "sky" / "sky.frag").read_text())
    out["own_untouched"] = _sha(own) == own_sha
    out["library_root"] = str(win.session.gpu.shaders.root)
    out["editor_file"] = str(win.editor.file.path) if win.editor.file else None
    out["errors"] = [str(e) for e in win.session.gpu.shaders.errors()]
    out["no_temp_left"] = sorted(p.name for p in work_dir.iterdir())
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def compare_run(work: str) -> int:
    """The issue's last step, in the planet window: F3 opens the A/B pane on the scene's
    methods 2 and 4 (the optical-depth LUT against Hillaire), a click on Compare renders both
    (timed in interleaved rounds) with the heat map and the errors against the reference."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    os.chdir(work)
    from app.teach.quality import pick

    params = scene_params("planet", sets=["planet.ground_noise_size=256"])
    picks = pick("planet", 0.02, None, None, params=params, size=SIZE)  # --quality auto
    picks.apply(params)
    # the panel as wide as in a large window (a window this small gets a narrower one, whose
    # wrapped lines push the chart below the panel's bottom)
    W.panel_size = lambda window: (380.0, 620.0)
    win = W.NaturaWindow("planet", params, get_scene("planet").new_camera(), SIZE,
                         screenshot_dir="shots", quality=picks)
    keys = XKeys(win, "^Natura .* planet$")
    out: dict = {}
    out["quality_charts"] = win.quality.plots_drawn  # the panel's charts of the picks
    out["quality_chosen"] = [c.point.label for c in picks if c.point is not None
                             and c.status == "chosen"]
    keys.tap("F3")  # its frames (one with F3 held, one after) draw the pane and its button
    out["f3_shows"] = win.compare.shown
    out["a"], out["b"] = win.compare.a_text, win.compare.b_text
    out["size"] = list(win.compare.result.size) if win.compare.result else None
    x0, y0, x1, y1 = win.compare.button_rect
    params_before = dict(win.params.values())
    _click(keys, (x0 + x1) / 2, (y0 + y1) / 2)
    _until(keys, lambda: win.compare.result is not None or win.compare.problem, 30)
    r = win.compare.result
    out["problem"] = win.compare.problem
    if r is not None:
        out["size"] = list(r.size)
        out["ms"] = [r.a.ms, r.b.ms]
        out["errors"] = [r.a.error, r.b.error]
        out["heat_max"] = int(r.heat.max())
        out["caption"] = r.caption
        out["textures"] = sorted(win.compare.textures)
    out["live_params_kept"] = dict(win.params.values()) == params_before
    out["progress_frames"] = win.progress_frames
    win.compare.layout = 1
    keys.frames(1)
    out["still_rendering"] = win.render_error is None
    # Ctrl+F puts the caret in the panel's search box; Ctrl+A then typing replaces the text
    _chord(keys, "ctrl", "f")
    _type(keys, "shadow")
    _until(keys, lambda: win.panel_state.search == "shadow", 60)
    out["search_typed"] = win.panel_state.search
    _chord(keys, "ctrl", "a")
    _type(keys, "lut")
    _until(keys, lambda: win.panel_state.search == "lut", 60)
    out["search_replaced"] = win.panel_state.search
    win.close()
    print("RESULT " + json.dumps(out, default=str))
    return 0


if __name__ == "__main__":
    runs = {"copy": copy_run, "own": own_run, "compare": compare_run}
    sys.exit(runs[sys.argv[2]](sys.argv[1]))
