"""Counts the calls that make the CPU wait for the GPU in the window's frame loop: run under
Xvfb as ``python stall_driver.py SCENE[:GROUP.NAME=VALUE,...] ...``, it opens the real window
on each scene (with those settings), draws a few frames to warm up (programs, bakes, probes
are made there), then counts over 100 frames of ``NaturaWindow.frame`` (the scene's frame,
the display pass, the panel, the HUD, ImGui) every ``ctx.finish()``, every synchronous read
of a framebuffer, texture or buffer and every query result read (moderngl's, and the
pipeline-statistics queries Natura reads through raw GL), by the file and line that called
it. Prints ``RESULT {json}``.
"""

from __future__ import annotations

import collections
import json
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FRAMES = 100
WARMUP = 5
#: the window's size: small, the frame loop's calls do not depend on it (the multisampled
#: passes of the surfaces lab and the village cost by the pixel: 96x54 → 64x36 halves them)
SIZE = (64, 36)

#: moderngl calls that wait for the GPU: the method (or property) and the name it is counted by
SYNCING = [("Context", "finish"), ("Framebuffer", "read"), ("Framebuffer", "read_into"),
           ("Texture", "read"), ("Texture", "read_into"), ("TextureCube", "read"),
           ("Texture3D", "read"), ("TextureArray", "read"), ("Buffer", "read"),
           ("Buffer", "read_into"), ("Query", "elapsed"), ("Query", "samples"),
           ("Query", "primitives")]


def instrument(counts: collections.Counter, active: list[bool]) -> None:
    import moderngl

    from app.gpu import timing

    def caller() -> str:
        for frame in reversed(traceback.extract_stack()[:-2]):
            path = Path(frame.filename)
            if ROOT in path.parents and "tests" not in path.parts:
                return f"{path.relative_to(ROOT).as_posix()}:{frame.lineno}"
        return "?"

    classes = {**{c: getattr(moderngl, c) for c, _ in SYNCING},
               "PipelineStatistics": timing.PipelineStatistics}
    for cls_name, name in [*SYNCING, ("PipelineStatistics", "count")]:
        cls = classes[cls_name]
        original = cls.__dict__.get(name)
        if original is None:
            continue
        label = f"{cls_name}.{name}"
        if isinstance(original, property):
            def getter(self, _p=original, _label=label):
                if active[0]:
                    counts[(_label, caller())] += 1
                return _p.fget(self)
            setattr(cls, name, property(getter))
        else:
            def method(self, *args, _f=original, _label=label, **kwargs):
                if active[0]:
                    counts[(_label, caller())] += 1
                return _f(self, *args, **kwargs)
            setattr(cls, name, method)


def main(scenes: list[str]) -> int:
    sys.path.insert(0, str(ROOT))
    counts: collections.Counter = collections.Counter()
    active = [False]
    instrument(counts, active)
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    result = {}
    for arg in scenes:
        scene, _, sets = arg.partition(":")
        params = scene_params(scene, sets=[s for s in sets.split(",") if s])
        win = W.NaturaWindow(scene, params, get_scene(scene).new_camera(), SIZE)
        try:
            for _ in range(WARMUP):
                win.wnd.clear()
                win.frame(1 / 60)
                win.wnd.swap_buffers()
            counts.clear()
            active[0] = True
            t0 = time.perf_counter()
            for _ in range(FRAMES):
                win.wnd.clear()
                win.frame(1 / 60)
                win.wnd.swap_buffers()
            active[0] = False
            result[scene] = {"frames": FRAMES, "seconds": round(time.perf_counter() - t0, 2),
                             "calls": [[what, where, n] for (what, where), n in counts.items()],
                             "render_error": win.render_error}
        finally:
            active[0] = False
            win.close()
    print("RESULT " + json.dumps(result), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
