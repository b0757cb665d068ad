"""``natura bench SCENE``: time each pass of a scene, write JSON (docs/architecture.md,
"Measuring", describes the rounds, the references and the pipeline statistics).

Besides the whole frame, the same rounds run the frame part by part
(``app.gpu.timing.FrameClock``): the update step (:data:`CPU_PART`), each pass as it runs inside
the frame — into the targets the frame uses, such as the village's multisampled twin — ending
with its own ``ctx.finish()``, and the scene's own work between passes (clears, resolves); the
report's ``frame_accounting`` gives each part, their sum beside the whole frame, and the
remainder between the two.

``natura bench boat`` is not a scene: ``NUMPY_BENCHES`` lists such benches (numpy only, no GL
context), each a few sections with a report, a chart and a summary.
"""

from __future__ import annotations

import datetime
import importlib
import importlib.util
import json
import math
import platform
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ..effects.base import Pass
from ..gpu.programs import draw_fullscreen, fullscreen
from ..gpu.timing import BETWEEN_PASSES, FrameClock, quartiles_of, time_interleaved
from ..imageio import next_free_path, write_text_atomic
from ..runtime import Session

TRIVIAL = fullscreen("common/constant")


def trivial_pass(session: Session, target, draws: int = 1) -> Pass:
    """The reference: a constant-colour full-screen triangle, drawn ``draws`` times per run."""
    prog = session.gpu.program("bench", TRIVIAL)

    def run():
        target.use()
        prog.set("uColor", (0.5, 0.5, 0.5, 1.0))
        for _ in range(draws):
            draw_fullscreen(prog)

    return Pass("reference.fullscreen", run)


#: a reference run should last at least this long: a 0.05 ms draw alone is swamped by one
#: scheduling hiccup, and every per-round ratio divides by it
REFERENCE_MIN_MS = 2.0


def reference_draws(ctx, single: Callable[[], None], min_ms: float = REFERENCE_MIN_MS,
                    most: int = 4096) -> int:
    """How many draws of the reference make one timed run last ``min_ms`` (median of 5)."""
    import statistics
    import time

    single()
    times = []
    for _ in range(5):
        ctx.finish()
        t0 = time.perf_counter()
        single()
        ctx.finish()
        times.append((time.perf_counter() - t0) * 1e3)
    per = max(statistics.median(times), 1e-4)
    return int(min(most, max(1, math.ceil(min_ms / per))))


#: what the report's per-pass fields mean (written into the JSON beside them)
FIELDS = {
    "median_ms, p25_ms, p75_ms": "wall time of one run with ctx.finish() on both sides, over "
                                 "the rounds",
    "ratio_to_fullscreen": "median over the rounds of (this pass ÷ reference.fullscreen of "
                           "the same round); _p25 and _p75 its quartiles. The reference's "
                           "times are per draw: each of its runs draws it timing."
                           "reference_draws times (enough for about 2 ms), so one scheduling "
                           "hiccup does not swamp a round",
    "pipeline": "GL_ARB_pipeline_statistics_query counts of one run (and samples_passed)",
    "frame": "the whole frame: the scene's update step and its render, one run",
    "frame_accounting": "the frame run part by part in the same rounds: the update step "
                        "(CPU: simulation/uniforms), each pass as it runs inside the frame "
                        "(into the frame's own targets) ending with its own ctx.finish(), and "
                        "the scene's work between passes (clears, resolves); per part the "
                        "median and quartiles over the rounds, issue_median_ms (until its work "
                        "was queued) and alone_median_ms (the pass from a cleared bench "
                        "target, where timed); sum_ms of the parts' medians beside frame_ms "
                        "(the whole frame, no finish inside), remainder_ms = frame_ms − sum_ms",
    "covered_pixels": "pixels of the bench target that differ from the clear after one run "
                      "from a cleared target (0: the pass draws only into its own targets)",
    "fragments_per_covered_pixel": "fragment_shader_invocations ÷ covered_pixels: overdraw, "
                                   "helper and block shading",
    "fragments_per_image_pixel": "fragment_shader_invocations ÷ width·height",
    "cost_per_fragment_vs_fullscreen": "(this pass's ms per 1,000,000 fragment invocations) ÷ "
                                       "(reference.fullscreen's): the cost of a fragment "
                                       "relative to a constant shader, all of the pass's time "
                                       "put on its fragments",
}


def _covered(target) -> int:
    """Pixels of ``target`` that differ from ``target.clear()``'s colour or depth."""
    import numpy as np

    colour = target.read()
    changed = np.any(colour != np.array([0.0, 0.0, 0.0, 1.0], dtype=np.float32), axis=-1)
    if getattr(target, "depth", None) is not None:
        changed |= target.read_depth() < 1.0
    return int(changed.sum())


def _pipeline(gpu, target, passes, inner) -> tuple[dict, dict]:
    """Counts of one run of each pass (none timed: the queries stay out of the timed rounds),
    and the status to record (supported, and the reason where not)."""
    from ..gpu.timing import PIPELINE_EXTENSION, PipelineStatistics

    stats = PipelineStatistics(gpu.ctx)
    status: dict = {"extension": PIPELINE_EXTENSION, "supported": stats.available,
                    "reason": stats.reason}
    counts: dict = {}
    if not stats.available:
        return counts, status
    for p in passes:
        if p.name in inner:  # from a cleared target, the clear left out of the counts
            target.clear()
            got = stats.count(inner[p.name])
        else:
            got = stats.count(p.run)
        if got is None:
            status.update(supported=False, reason=stats.reason)
            return {}, status
        entry: dict = {"pipeline": got}
        if p.name != "reference.clear":
            gpu.ctx.finish()
            entry["covered_pixels"] = _covered(target)
        counts[p.name] = entry
    return counts, status


def at_most(size: tuple[int, int], limit: tuple[int, int]) -> tuple[int, int]:
    """A sweep's own size ``limit`` never above the bench's ``--size``: each side the smaller of
    the two, so a small ``--size`` makes the whole run small (the sweeps record what they used)."""
    return min(int(size[0]), int(limit[0])), min(int(size[1]), int(limit[1]))


def ratio_text(q: dict) -> str:
    """A time ratio's median, quartiles and rounds: ``×1.23 [1.10–1.40] over 9 rounds``."""
    return f"×{q['median']:.2f} [{q['p25']:.2f}–{q['p75']:.2f}] over {q['n']} rounds"


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend: charts are files, no display is needed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def write_chart(fig, path, force: bool = False, title: str | None = None) -> None:
    """Finish a bench chart: its ``title`` (when given) and tight layout, then written atomically
    and never over an existing file without ``force`` (``app.imageio.save_figure``); the figure is
    closed whatever happens."""
    import matplotlib.pyplot as plt

    from ..imageio import save_figure

    if title is not None:
        fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        # tight_layout leaves a placeholder layout engine behind, and savefig draws the whole
        # figure once more (unrendered) for any engine before the real draw: the layout is
        # done, so no engine — the same PNG, one draw fewer (a third of a chart's time)
        fig.set_layout_engine(None)
    try:
        save_figure(fig, path, force=force)
    finally:
        plt.close(fig)


#: seconds of timed rounds after which ``natura bench`` stops adding rounds (at least 5 are
#: run) unless --repeat asks for a number
ROUNDS_BUDGET_S = 6.0


#: the part of a frame that is the scene's update step: every effect's CPU work (simulation,
#: the slots it fills, the uniforms it computes ahead of its passes)
CPU_PART = "CPU: simulation/uniforms"
#: the frame run part by part: timed in the rounds beside the whole frame, reported in
#: ``frame_accounting`` (not among the passes)
ACCOUNTED = "frame, part by part"


@contextmanager
def clocked_passes(scene, clock: FrameClock):
    """While inside, every pass ``scene`` runs (``Scene.passes``, however its ``render`` calls
    it: once per eye, or split around a resolve) is a part of ``clock``."""
    plain = scene.passes

    def passes(frame, target) -> list[Pass]:
        return [Pass(p.name, lambda p=p: clock.part(p.name, p.run), p.stage)
                for p in plain(frame, target)]

    setattr(scene, "passes", passes)
    try:
        yield
    finally:
        delattr(scene, "passes")


def _accounting(result, records: list[tuple[dict, dict]], passes: dict) -> dict:
    """The frame's parts over the timed rounds (their medians and quartiles, the time until
    each part's work was queued, its time alone from a cleared target where the bench timed
    it), their sum beside the whole frame, and the remainder between the two."""
    import statistics

    records = records[-result.rounds:] if result.rounds else []
    names: list[str] = []
    for parts, _ in records:
        names += [n for n in parts if n not in names and n != BETWEEN_PASSES]
    if any(BETWEEN_PASSES in parts for parts, _ in records):
        names.append(BETWEEN_PASSES)
    table: dict = {}
    for name in names:
        p25, med, p75 = quartiles_of([parts.get(name, 0.0) for parts, _ in records])
        entry = {"median_ms": med, "p25_ms": p25, "p75_ms": p75,
                 "issue_median_ms": statistics.median(issue.get(name, 0.0)
                                                      for _, issue in records)}
        if name in passes:
            entry["alone_median_ms"] = passes[name]["median_ms"]
        table[name] = entry
    total = sum(e["median_ms"] for e in table.values())
    frame = passes["frame"]["median_ms"]
    remainder = frame - total
    return {"parts": table, "sum_ms": total, "frame_ms": frame,
            "accounted_frame_ms": result.quartiles(ACCOUNTED)[1],
            "remainder_ms": remainder,
            "remainder_share": remainder / frame if frame > 0 else 0.0,
            "rounds": len(records)}


def accounting_lines(report: dict) -> list[str]:
    """The frame accounting as ``natura bench`` prints it: every part of the frame, their sum,
    the whole frame and the remainder."""
    acc = report.get("frame_accounting")
    if not acc:
        return []
    lines = [f"{'frame, part by part':40s} {'in the frame ms [p25–p75]':>28s}  {'alone ms':>9s}"
             "  share"]
    frame = acc["frame_ms"]
    for name, e in acc["parts"].items():
        spread = f"{e['median_ms']:.3f} [{e['p25_ms']:.3f}–{e['p75_ms']:.3f}]"
        alone = f"{e['alone_median_ms']:.3f}" if "alone_median_ms" in e else "—"
        share = f"{100.0 * e['median_ms'] / frame:5.1f} %" if frame > 0 else ""
        lines.append(f"  {name:38s} {spread:>28s}  {alone:>9s}  {share}")
    lines.append(f"  {'sum of the parts':38s} {acc['sum_ms']:>28.3f}")
    lines.append(f"  {'frame (timed whole)':38s} {frame:>28.3f}")
    lines.append(f"  {'remainder (frame − sum)':38s} {acc['remainder_ms']:>28.3f}  "
                 f"{'':9s}  {100.0 * acc['remainder_share']:5.1f} %")
    return lines


def bench_scene(session: Session, size: tuple[int, int], warmup: int = 3, repeat: int = 15,
                seed: int = 0, budget_s: float | None = None) -> dict:
    gpu = session.gpu
    target = gpu.target("bench", "scene radiance", size)
    clock = FrameClock(gpu.ctx)
    records: list[tuple[dict, dict]] = []

    def whole_frame():
        session.scene.render(session.scene.frame(size, 0.0), target)

    def accounted_frame():
        clock.begin()
        made: list = []
        clock.part(CPU_PART, lambda: made.append(session.scene.frame(size, 0.0)))
        with clocked_passes(session.scene, clock):
            session.scene.render(made[0], target)
        records.append((clock.end(), dict(clock.issue)))

    try:
        frame = session.scene.frame(size, 0.0)
        session.scene.render(frame, target)  # first frame: lazy resources are created here
        # each effect pass starts from a cleared target: with the depth buffer of the previous
        # repetition left in place, depth-tested passes would time rejected fragments only
        def cleared(p: Pass) -> Pass:
            def run():
                target.clear()
                p.run()

            inner[p.name] = p.run
            return Pass(p.name, run)

        raw = session.scene.bench_passes(frame, target)
        names = [p.name for p in raw]
        seen: dict[str, int] = {}
        for i, p in enumerate(raw):  # two passes of one name: both kept, numbered
            if names.count(p.name) > 1:
                seen[p.name] = seen.get(p.name, 0) + 1
                raw[i] = Pass(f"{p.name} #{seen[p.name]}", p.run, p.stage)
        inner: dict[str, Callable[[], None]] = {}  # the effect passes without their clear
        single = trivial_pass(session, target)
        draws = reference_draws(gpu.ctx, single.run)
        passes = [trivial_pass(session, target, draws), Pass("reference.clear", target.clear)]
        passes += [cleared(p) for p in raw]
        passes.append(Pass("frame", whole_frame))
        hardware = not gpu.caps.software
        variants = {p.name: p.run for p in passes}
        variants[ACCOUNTED] = accounted_frame
        result = time_interleaved(gpu.ctx, variants, warmup, repeat,
                                  seed=seed, gpu_queries=hardware, budget_s=budget_s)
        reference = result.timings["reference.fullscreen"]  # its times per draw
        reference.wall_ms[:] = [t / draws for t in reference.wall_ms]
        reference.gpu_ms[:] = [t / draws for t in reference.gpu_ms]
        counts, pipeline_status = _pipeline(gpu, target, [single, *passes[1:]], inner)
    finally:
        gpu.free(target)
    ref = "reference.fullscreen"
    pixels = size[0] * size[1]
    report_passes: dict = {}
    ref_frags = counts.get(ref, {}).get("pipeline", {}).get("fragment_shader_invocations", 0)
    for name, t in result.timings.items():
        if name == ACCOUNTED:
            continue
        p25, med, p75 = result.quartiles(name)
        ratio = result.ratio(name, ref)
        entry: dict = {**t.summary(), "p25_ms": p25, "p75_ms": p75,
                       "ratio_to_fullscreen": ratio["median"],
                       "ratio_to_fullscreen_p25": ratio["p25"],
                       "ratio_to_fullscreen_p75": ratio["p75"]}
        entry["median_ms"] = med
        if t.gpu_ms:  # GPU timer queries (hardware only): their quartiles too
            entry["gpu_p25_ms"], entry["gpu_median_ms"], entry["gpu_p75_ms"] = \
                quartiles_of(t.gpu_ms)
        if name in counts:
            c = counts[name]
            entry.update(c)
            frags = c["pipeline"].get("fragment_shader_invocations", 0)
            covered = c.get("covered_pixels")
            if frags:
                entry["fragments_per_image_pixel"] = frags / pixels
                if covered:
                    entry["fragments_per_covered_pixel"] = frags / covered
                if ref_frags:
                    entry["cost_per_fragment_vs_fullscreen"] = ratio["median"] * ref_frags / frags
        report_passes[name] = entry
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
        "rounds_budget_s": budget_s,
        "timing": {"method": "interleaved", "rounds": result.rounds, "seed": seed,
                   "order": "every pass once per round, shuffled", "reference": ref,
                   "reference_draws": draws},
        "pipeline_statistics": pipeline_status,
        "fields": FIELDS,
        "parameters": {k: (list(v) if isinstance(v, tuple) else v)
                       for k, v in session.params.values().items()},
        "passes": report_passes,
        "frame_accounting": _accounting(result, records, report_passes),
    }


def scene_sweeps(scene: str):
    """The speed/accuracy sweeps of a scene: the module ``app/bench/<scene>.py`` when there is
    one (it defines ``sweep(session, size, ...)``, ``chart(report, path)`` and
    ``summary(report)``), else None. Adding a scene's sweeps is adding that module."""
    if not scene.isidentifier() or importlib.util.find_spec(f"{__name__}.{scene}") is None:
        return None
    module = importlib.import_module(f"{__name__}.{scene}")
    return module if all(hasattr(module, f) for f in ("sweep", "chart", "summary")) else None


@dataclass(frozen=True)
class NumpyBench:
    """A bench that is not a scene: numpy only, no GL context is created. Each section is a
    module under app/bench with ``run(quick=False) -> dict``, ``chart(report, path,
    force=False)`` and ``summary(report) -> str``; its report goes into the JSON under the
    section's key, its chart beside the JSON, named by the section's suffix (``FILE.png``,
    ``FILE-polar.png``)."""

    name: str
    about: str
    #: (key in the report, module under app/bench, chart suffix, title)
    sections: tuple[tuple[str, str, str, str], ...]

    def module(self, key: str):
        (name,) = [m for k, m, _, _ in self.sections if k == key]
        return importlib.import_module(f"{__name__}.{name}")

    def chart_suffixes(self) -> tuple[str, ...]:
        return tuple(suffix for _, _, suffix, _ in self.sections)

    def run(self, quick: bool = False, progress: Callable[[str], None] | None = None) -> dict:
        """Every section's report, with the time each took, under one dict."""
        import os
        import time

        report: dict = {"bench": self.name, "about": self.about, "quick": quick,
                        "python": platform.python_version(), "cpus": os.cpu_count(),
                        "when": datetime.datetime.now(datetime.timezone.utc).isoformat(
                            timespec="seconds"),
                        "sections": {k: title for k, _, _, title in self.sections},
                        "seconds": {}}
        for key, _, _, title in self.sections:
            if progress is not None:
                progress(title)
            start = time.perf_counter()
            report[key] = self.module(key).run(quick=quick)
            report["seconds"][key] = round(time.perf_counter() - start, 2)
        return report


#: the benches that are not scenes, by the name ``natura bench NAME`` takes (never a scene's)
NUMPY_BENCHES = {
    "boat": NumpyBench("boat", "the floating boat's physics (app/bench/boat.py) and the sailing "
                       "speed polar (app/bench/polar.py), numpy only",
                       (("physics", "boat", ".png", "boat physics"),
                        ("polar", "polar", "-polar.png", "speed polar"))),
}


def write_report(report: dict, out: str | None, force: bool = False) -> Path:
    if out:
        path = Path(out)
    else:
        folder = Path("bench-results")
        folder.mkdir(exist_ok=True)
        path = next_free_path(folder, report["scene"], ".json")
    return write_text_atomic(path, json.dumps(report, indent=2) + "\n", force=force)
