"""What the window's panel and panes show a user, in a real window under Xvfb (read by
tests/window/test_window_panel.py); findings as one ``RESULT {json}`` line.

``first-frame``: the maritime window's first frame has measured no frame time yet (it shows
dashes, not a made-up 16.67 ms); after a few frames it shows measured ones.
``ocean-panel``: the ocean window's panel opens on the ocean's own section, the others closed.
``maritime-cover``: the share of the maritime view the panel and the HUD cover at 960x540.
``village-wind``: Ctrl+F and "wind" typed as real keys in the village window: what the panel
says about the wind names the village's readers of it, not sails or a flag.
``toon-compare``: F3 in the shading window compares two toon modes (its default A/B) with a
click: no error figure against the scene's parallax reference, which judges another method.
"""

from __future__ import annotations

import json
import os
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from tests.helpers.editor_driver import _chord, _click, _type, _until  # noqa: E402
from tests.helpers.window_driver import MARITIME_SMALL, VILLAGE_SMALL, XKeys, _spy  # noqa: E402


def _window(scene: str, sets: list[str], size: tuple[int, int]):
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    params = scene_params(scene, sets=sets)
    return W.NaturaWindow(scene, params, get_scene(scene).new_camera(), size)


def first_frame(work: str) -> int:
    os.chdir(work)
    win = _window("maritime", MARITIME_SMALL, (320, 180))
    texts: list = []
    undo = _spy(win.imgui, "text", texts)
    out: dict = {}
    win.run(1)  # as `natura window maritime` draws its first frame
    out["first"] = [t["text"] for t in texts if t["text"].startswith("frame ")]
    texts.clear()
    win.run(3)
    out["later"] = [t["text"] for t in texts if t["text"].startswith("frame ")]
    undo()
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def ocean_panel(work: str) -> int:
    os.chdir(work)
    win = _window("ocean", ["ocean.fft_size=64", "ocean.mesh_segments=96"], (640, 480))
    opened: list = []
    original = win.imgui.collapsing_header

    def spy(label, *args, **kw):
        result = original(label, *args, **kw)
        shown = result[0] if isinstance(result, tuple) else result
        opened.append((str(label).split("##")[0], bool(shown)))
        return result

    win.imgui.collapsing_header = spy
    try:
        win.run(2)
    finally:
        win.imgui.collapsing_header = original
    last = opened[len(opened) // 2:]  # the second frame's headers
    out = {"open": [label for label, shown in last if shown],
           "closed": [label for label, shown in last if not shown],
           "scene_groups": [h.group for h in win.panel_state._headers[1]]}
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def village_wind(work: str) -> int:
    os.chdir(work)
    # the light village of the key test (a coarse island, 3000 blades, a small shadow map, no
    # MSAA): the panel's lines name the effects and their parameters, whatever their values;
    # the default village cost this test about 1 s more CPU (4.9-5.9 s against 3.9 s)
    win = _window("village", [*VILLAGE_SMALL, "time.hour=10"], (640, 480))
    keys = XKeys(win, "^Natura .* village$")
    _chord(keys, "ctrl", "f")
    _type(keys, "wind")
    _until(keys, lambda: win.panel_state.search == "wind", 60)
    drawn: list = []
    undo = [_spy(win.imgui, name, drawn) for name in ("text", "text_wrapped", "text_disabled")]
    keys.frames(2)
    for u in undo:
        u()
    lines = sorted({d["text"] for d in drawn})
    out = {"search": win.panel_state.search, "wind_lines": [t for t in lines if "wind" in t],
           "sails_or_flag": [t for t in lines if re.search(r"\bsails?\b|\bflags?\b", t)]}
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def toon_compare(work: str) -> int:
    os.chdir(work)
    win = _window("shading", ["shading.turntable=0"], (600, 400))
    keys = XKeys(win, "^Natura .* shading$")
    win.show_panel = False
    keys.tap("F3")
    out: dict = {"a": win.compare.a_text, "b": win.compare.b_text}
    x0, y0, x1, y1 = win.compare.button_rect
    _click(keys, (x0 + x1) / 2, (y0 + y1) / 2)
    _until(keys, lambda: win.compare.result is not None or win.compare.problem, 60)
    r = win.compare.result
    out["problem"] = win.compare.problem
    if r is not None:
        out["errors"] = [r.a.error, r.b.error]
        out["caption"] = r.caption
    drawn: list = []
    undo = _spy(win.imgui, "text_wrapped", drawn)
    keys.frames(2)
    undo()
    out["shown"] = sorted({d["text"] for d in drawn if d["text"].startswith("error")})
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def _covered(rects, size) -> float:
    """The share of a window of ``size`` that the rectangles (x0, y0, x1, y1) cover."""
    import numpy as np

    w, h = size
    mask = np.zeros((h, w), dtype=bool)
    for x0, y0, x1, y1 in rects:
        mask[max(int(y0), 0):max(int(y1), 0), max(int(x0), 0):max(int(x1), 0)] = True
    return float(mask.mean())


def maritime_cover(work: str) -> int:
    """At 960x540 (and 1920x1080), the share of the maritime view that the panel and the HUD
    cover, from the rectangles ImGui drew them in."""
    os.chdir(work)
    out: dict = {}
    for size in ((960, 540), (1920, 1080)):
        # the scene drawn at half the window (what is covered does not depend on it)
        win = _window("maritime", [*MARITIME_SMALL, "output.scale=0.5"], size)
        win.run(3)
        rects = {"panel": win.panel_rect, **{k: v for k, v in win.hud_rects.items()
                                             if k in ("ship", "weather")}}
        out[f"{size[0]}x{size[1]}"] = {
            "window": list(win.wnd.size), "rects": rects,
            "covered": _covered(rects.values(), win.wnd.size)}
        win.close()
    print("RESULT " + json.dumps(out))
    return 0


if __name__ == "__main__":
    runs = {"first-frame": first_frame, "ocean-panel": ocean_panel,
            "village-wind": village_wind, "toon-compare": toon_compare,
            "maritime-cover": maritime_cover}
    sys.exit(runs[sys.argv[2]](sys.argv[1]))
