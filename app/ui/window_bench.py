"""``natura bench SCENE --window``: frames per second in a real window, as a user gets them
(docs/architecture.md, "Measuring", says what is timed: vsync off, frames timed start to start
after untimed ones, with dynamic resolution at work).

Reported, never asserted: no test compares these numbers with anything.
"""

from __future__ import annotations

import os
import platform
import time

import numpy as np

from ..errors import UsageError
from ..gpu.context import describe_context
from .window import NaturaWindow

#: ``natura bench --window``'s default timed and untimed frames
WINDOW_FRAMES, WINDOW_WARMUP = 100, 10


def _quartiles(values) -> dict:
    a = np.asarray(values, dtype=np.float64)
    p25, med, p75 = (float(v) for v in np.percentile(a, [25, 50, 75]))
    return {"median_ms": med, "p25_ms": p25, "p75_ms": p75, "mean_ms": float(a.mean()),
            "min_ms": float(a.min()), "max_ms": float(a.max())}


def bench_window(scene_name: str, params, camera, size: tuple[int, int],
                 frames: int = WINDOW_FRAMES, warmup: int = WINDOW_WARMUP, shader_root=None,
                 setup=None, progress=None) -> dict:
    """Open the window on ``scene_name`` at ``size``, run ``warmup`` then ``frames`` frames and
    return the report (a dict, JSON-ready). ``progress(text)`` hears about each phase."""
    say = progress or (lambda text: None)
    win = NaturaWindow(scene_name, params, camera, size, shader_root, vsync=False)
    if setup is not None:
        setup(win.scene)
    times: list[float] = []
    scales: list[float] = []
    renderer = ""
    try:
        renderer = describe_context(win.ctx)
        say(f"{warmup} untimed frames (compiles, bakes, the scale settling)")
        last = time.perf_counter()
        n = 0
        total = warmup + frames
        report_every = max(1, frames // 4)
        while n < total + 1 and not win.wnd.is_closing:
            now = time.perf_counter()
            if n > warmup:  # frame n - 1 ran from `last` to `now`
                times.append((now - last) * 1000.0)
            if n == total:
                break
            dt = 1.0 / 60.0 if n == 0 else now - last
            last = now
            win.wnd.clear(0.0, 0.0, 0.0, 1.0)
            win.frame(dt, measured=n > 0)
            win.wnd.swap_buffers()
            if n >= warmup:
                scales.append(win.resolution.scale)
                done = n - warmup + 1
                if done % report_every == 0 and done < frames:
                    say(f"{done} of {frames} timed frames")
            n += 1
        internal = win.internal_size()
        window = tuple(int(v) for v in win.window_size)
        changes = [{"frame": f, "from": a, "to": b, "median_ms": round(m, 3)}
                   for f, a, b, m in win.resolution.changes]
        render_error = win.render_error
        auto = win.resolution.auto
    finally:
        win.close()
    if not times:
        raise UsageError("the window closed before a frame was timed: allowed a window left "
                         "open until the bench ends")
    stats = _quartiles(times)
    shares: dict[str, float] = {}
    for s in scales:
        key = f"{s:.4g}"
        shares[key] = shares.get(key, 0.0) + 1.0 / len(scales)
    return {
        "scene": scene_name,
        "kind": "window",
        "size": list(size),
        "window_size": list(window),
        "internal_size": list(internal),
        "renderer": renderer,
        "machine": f"{platform.machine()} {platform.system()}, {_cores()} CPU cores",
        "vsync": False,
        "panel": True,
        "warmup_frames": warmup,
        "frames": len(times),
        "frame_ms": stats,
        "fps": 1000.0 / stats["median_ms"],
        "fps_mean": 1000.0 * len(times) / sum(times),
        "budget_ms": float(params["output.frame_budget_ms"]),
        "scale_setting": "auto" if params["output.scale"] == 0.0 else params["output.scale"],
        "scale": {"auto": auto, "final": scales[-1] if scales else 1.0,
                  "min": min(scales, default=1.0), "max": max(scales, default=1.0),
                  "share": shares},
        "scale_changes": changes,
        "render_error": render_error,
        "times_ms": [round(t, 3) for t in times],
        "fields": {
            "frame_ms": "wall time from the start of one window frame to the start of the "
                        "next (scene, display pass, panel, swap, events), over the timed frames",
            "fps": "1000 / the median frame time",
            "fps_mean": "timed frames / their total time",
            "scale": "the internal scale per side each timed frame rendered at (dynamic "
                     "resolution, output.scale): the last one, the extremes and the share of "
                     "frames at each",
            "internal_size": "the scene's render size at the end (the window's × the scale)",
        },
    }


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def summary(report: dict) -> list[str]:
    """The lines ``natura bench --window`` prints."""
    t = report["frame_ms"]
    s = report["scale"]
    w, h = report["window_size"]
    iw, ih = report["internal_size"]
    shares = ", ".join(f"{k}: {v:.0%}" for k, v in sorted(s["share"].items(), reverse=True))
    lines = [
        f"window {w}x{h}, {report['frames']} frames after {report['warmup_frames']} untimed: "
        f"median {t['median_ms']:.1f} ms [{t['p25_ms']:.1f}–{t['p75_ms']:.1f}] → "
        f"{report['fps']:.1f} fps (mean {report['fps_mean']:.1f} fps)",
        f"scale {s['final']:.3g} at the end ({'auto' if s['auto'] else 'pinned'}, budget "
        f"{report['budget_ms']:g} ms): the scene at {iw}x{ih}; frames per scale: {shares}",
    ]
    if report.get("render_error"):
        lines.append(f"render error: {report['render_error']}")
    return lines
