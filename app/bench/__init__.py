"""``natura bench SCENE``: time each pass of a scene, write JSON.

Each pass is timed with ``ctx.finish()`` around it, after a warm-up, as the median of N runs
(docs/architecture.md, "Measuring"). A trivial full-screen pass is timed in the same run, so
ratios to it hold across machines even where absolute times (llvmpipe) mean little. GPU timer
queries are added only on a hardware GPU.
"""

from __future__ import annotations

import datetime
import importlib
import importlib.util
import json
import platform
from pathlib import Path

from ..effects.base import Pass
from ..gpu.programs import draw_fullscreen, fullscreen
from ..gpu.timing import time_call
from ..imageio import next_free_path, write_text_atomic
from ..runtime import Session

TRIVIAL = fullscreen("common/constant")


def trivial_pass(session: Session, target) -> Pass:
    prog = session.gpu.program("bench", TRIVIAL)

    def run():
        target.use()
        prog.set("uColor", (0.5, 0.5, 0.5, 1.0))
        draw_fullscreen(prog)

    return Pass("reference.fullscreen", run)


def bench_scene(session: Session, size: tuple[int, int], warmup: int = 3, repeat: int = 15) -> dict:
    gpu = session.gpu
    target = gpu.target("bench", "scene radiance", size)
    try:
        frame = session.scene.frame(size, 0.0)
        session.scene.render(frame, target)  # first frame: lazy resources are created here
        # each effect pass starts from a cleared target: with the depth buffer of the previous
        # repetition left in place, depth-tested passes would time rejected fragments only
        def cleared(p: Pass) -> Pass:
            def run():
                target.clear()
                p.run()

            return Pass(p.name, run)

        passes = [trivial_pass(session, target), Pass("reference.clear", target.clear)]
        passes += [cleared(p) for p in session.scene.bench_passes(frame, target)]
        passes.append(Pass("frame", lambda: session.scene.render(frame, target)))
        hardware = not gpu.caps.software
        timings = {p.name: time_call(gpu.ctx, p.name, p.run, warmup, repeat, gpu_queries=hardware)
                   for p in passes}
    finally:
        gpu.free(target)
    ref = timings["reference.fullscreen"].median_ms
    return {
        "scene": session.scene.name,
        "size": list(size),
        "renderer": gpu.caps.renderer,
        "gl_version": gpu.caps.version_code,
        "software_renderer": gpu.caps.software,
        "python": platform.python_version(),
        "when": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "warmup": warmup,
        "repeat": repeat,
        "parameters": {k: (list(v) if isinstance(v, tuple) else v)
                       for k, v in session.params.values().items()},
        "passes": {
            name: {**t.summary(), "ratio_to_fullscreen": (t.median_ms / ref) if ref > 0 else None}
            for name, t in timings.items()
        },
    }


def scene_sweeps(scene: str):
    """The speed/accuracy sweeps of a scene: the module ``app/bench/<scene>.py`` when there is
    one (it defines ``sweep(session, size, ...)``, ``chart(report, path)`` and
    ``summary(report)``), else None. Adding a scene's sweeps is adding that module."""
    if not scene.isidentifier() or importlib.util.find_spec(f"{__name__}.{scene}") is None:
        return None
    module = importlib.import_module(f"{__name__}.{scene}")
    return module if all(hasattr(module, f) for f in ("sweep", "chart", "summary")) else None


def write_report(report: dict, out: str | None, force: bool = False) -> Path:
    if out:
        path = Path(out)
    else:
        folder = Path("bench-results")
        folder.mkdir(exist_ok=True)
        path = next_free_path(folder, report["scene"], ".json")
    return write_text_atomic(path, json.dumps(report, indent=2) + "\n", force=force)
