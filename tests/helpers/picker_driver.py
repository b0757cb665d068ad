"""Drives ``natura window`` with no scene named (run under Xvfb by
tests/window/test_window_picker.py): starts it as a user does, waits for the scene picker's
window, acts on it with real X events (xdotool) and reports, as one ``RESULT {json}`` line,
which windows appeared and how the command ended.

Modes: ``click:SCENE`` clicks that scene's thumbnail (where :func:`app.ui.picker.tile_rects`
puts it); ``keys`` presses Right then Enter (the second tile); ``escape`` presses Esc.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time

SIZE = (960, 540)


def xdo(*args: str, timeout: float = 60.0) -> str:
    return subprocess.run(["xdotool", *args], capture_output=True, text=True, check=True,
                          timeout=timeout).stdout.strip()


def natura_windows() -> dict[str, str]:
    """{name: X window id} of the windows whose name starts with "Natura" (xdotool's own
    pattern is a regular expression that does not take the names' dash: compared here)."""
    found = subprocess.run(["xdotool", "search", "--name", "^Natura"], capture_output=True,
                           text=True).stdout.split()
    names = {subprocess.run(["xdotool", "getwindowname", wid], capture_output=True,
                            text=True).stdout.strip(): wid for wid in found}
    # a window closed between the search and its name's read has no name: not a window now
    return {name: wid for name, wid in names.items() if name.startswith("Natura")}


def wait_for(title: str, proc: subprocess.Popen, timeout: float = 120.0) -> str | None:
    """The X window id of the window named ``title`` (None: it never came, or the command
    ended first)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end and proc.poll() is None:
        wid = natura_windows().get(title)
        if wid is not None:
            return wid
        time.sleep(0.2)
    return None


def main(spec: str) -> int:
    mode, _, arg = spec.partition(":")
    from app.scenes import DEFAULT_SCENE
    from app.ui.picker import TITLE, tile_rects, tiles

    cmd = [sys.executable, "-m", "app.cli", "window", "--frames", "3",
           "--size", f"{SIZE[0]}x{SIZE[1]}"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    result: dict = {"mode": mode}
    try:
        picker = wait_for(TITLE, proc)
        result["picker"] = picker is not None
        if picker is not None:
            time.sleep(1.0)  # a few frames drawn: the thumbnails are up
            names = [t.scene for t in tiles(DEFAULT_SCENE)]
            result["order"] = names
            if mode == "click":
                x, y, w, h = tile_rects(SIZE, len(names))[names.index(arg)]
                xdo("mousemove", "--window", picker, str(int(x + w / 2)), str(int(y + h / 2)))
                time.sleep(0.3)
                xdo("click", "1")  # through the X test extension, as a person's click
            elif mode == "keys":
                xdo("windowfocus", "--sync", picker)
                xdo("key", "Right")
                time.sleep(0.3)
                xdo("key", "Return")
            else:
                xdo("windowfocus", "--sync", picker)
                xdo("key", "Escape")
            scene_window = None  # the scene's window that follows, if any
            end = time.monotonic() + 120.0
            while scene_window is None and proc.poll() is None and time.monotonic() < end:
                others = [name for name in natura_windows() if name != TITLE]
                scene_window = others[0] if others else None
                time.sleep(0.2)
            result["scene_window"] = scene_window
        out, err = proc.communicate(timeout=240)
    finally:
        if proc.poll() is None:
            proc.kill()
            out, err = proc.communicate()
    result.update(returncode=proc.returncode, stderr=err[-2000:], stdout=out[-2000:])
    print("RESULT " + json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[2]))  # argv[1]: the work folder (the current directory)
