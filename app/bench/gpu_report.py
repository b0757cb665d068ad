"""One prepared measurement of everything, for the few minutes a GPU machine is lent:
``python -m app.bench.gpu_report [--small] [--out DIR]`` (``tools/gpu_report.sh`` installs and
runs it).

What it measures, in one process on one context, and writes as ``DIR/gpu-report.json`` and
one Markdown page ``DIR/gpu-report.md``:

1. the context (``natura doctor``'s line) and the path every scene takes on it
   (``Effect.context_paths``: compute or fragment FFT, deferred or forward ocean, …), so the
   report says which ran;
2. every scene's frame at 1920×1080, each pass timed in interleaved rounds
   (``app.bench.bench_scene``: medians and quartiles of wall time, and of GPU timer queries on
   a hardware GPU);
3. the maritime and village frames against the 16.7 ms budget of 60 frames per second (GPU
   time where there are timer queries, wall time otherwise);
4. the theses' own tables: the atmosphere thesis's methods × sizes × ground and space
   (``app.bench.planet.thesis_table``), the cloud thesis's Table 6.1 (``app.bench.clouds.table``),
   the grass methods at 10k–1M blades (``app.bench.village_grass``), the FFT ocean's grid sizes
   (``app.bench.ocean.fft_sweep``).

``--small`` runs the same at the sizes a software renderer can afford (80×45 frames in two
rounds, one size per table, the smallest counts: :data:`SMALL`), in well under three minutes on
llvmpipe (about half a minute with the driver report): CI runs it, so the GPU run is known to
work before a GPU is ever lent.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

BUDGET_MS = 1000.0 / 60.0
BUDGET_SCENES = ("maritime", "village")


@dataclass(frozen=True)
class Plan:
    size: tuple[int, int]
    warmup: int
    rounds: int
    budget_s: float
    planet_sizes: tuple[tuple[int, int], ...]
    cloud_sizes: tuple[tuple[int, int], ...]
    grass_counts: tuple[int, ...]
    grass_size: tuple[int, int]
    fft_sizes: tuple[int, ...]
    fft_cascades: tuple[int, ...]
    #: repetitions of each cell of the atmosphere table (a median of whole frames)
    planet_repeat: int


FULL = Plan(size=(1920, 1080), warmup=3, rounds=9, budget_s=8.0,
            planet_sizes=((800, 600), (1280, 720), (1920, 1080)),
            cloud_sizes=((512, 512), (800, 800), (1920, 1080)),
            grass_counts=(10_000, 100_000, 300_000, 1_000_000), grass_size=(1920, 1080),
            fft_sizes=(64, 128, 256, 512), fft_cascades=(1, 3), planet_repeat=9)
#: what proves the plumbing at a software renderer's sizes: 80×45 frames (every pass of every
#: scene runs at it; llvmpipe's cost at 160×90 is a third more), no warm-up (every bench
#: renders a first frame before it times anything), two rounds (the fewest that have
#: quartiles), one size, count or FFT grid per table and one repetition of each of the
#: atmosphere table's 16 cells (4 methods × 2 views × frame and scattering pass) — every
#: scene, table, row kind and field the full run has, in ~12 s of CPU on llvmpipe
SMALL = Plan(size=(80, 45), warmup=0, rounds=2, budget_s=1.5,
             planet_sizes=((80, 60),), cloud_sizes=((64, 64),), grass_counts=(10_000,),
             grass_size=(80, 45), fft_sizes=(64,), fft_cascades=(1,), planet_repeat=1)


def _frame_entry(report: dict) -> dict:
    passes = report["passes"]
    frame = passes["frame"]
    out = {k: frame.get(k) for k in ("median_ms", "p25_ms", "p75_ms", "gpu_median_ms",
                                     "gpu_p25_ms", "gpu_p75_ms", "n")}
    out["passes"] = {name: {k: e.get(k) for k in ("median_ms", "p25_ms", "p75_ms",
                                                  "gpu_median_ms", "gpu_p25_ms", "gpu_p75_ms")}
                     for name, e in passes.items() if not name.startswith("reference.")
                     and name != "frame"}
    return out


def run(plan: Plan, progress=print) -> dict:
    from ..gpu.context import caps_of, create_headless_context, describe_context
    from ..runtime import open_session, scene_params
    from ..scenes import SCENES
    from ..teach.doctor import paths_by_scene
    from . import bench_scene

    t_start = time.perf_counter()
    ctx = create_headless_context()
    caps = caps_of(ctx)
    # each scene's parameters declared once (every GLSL annotation read: ~40 ms a scene here),
    # for the paths and then for the scene's own session
    declared = {scene: scene_params(scene) for scene in SCENES}
    report: dict = {"context": describe_context(ctx), "renderer": caps.renderer,
                    "software_renderer": caps.software, "gl_version": caps.version_code,
                    "gpu_timers": caps.gpu_timers, "plan": plan.__dict__,
                    "paths": paths_by_scene(caps, declared.__getitem__), "scenes": {},
                    "tables": {}}
    progress(f"context: {report['context']}")

    def session_of(scene: str, sets=()):
        return open_session(scene, scene_params(scene, sets=list(sets)), ctx=ctx)

    for scene in SCENES:
        t0 = time.perf_counter()
        with open_session(scene, declared.pop(scene), ctx=ctx) as session:
            bench = bench_scene(session, plan.size, plan.warmup, plan.rounds,
                                budget_s=plan.budget_s)
        report["scenes"][scene] = _frame_entry(bench)
        f = report["scenes"][scene]
        progress(f"{scene}: frame {f['median_ms']:.2f} ms wall"
                 + (f", {f['gpu_median_ms']:.2f} ms GPU" if f.get("gpu_median_ms") else "")
                 + f" ({time.perf_counter() - t0:.1f} s)")
    report["budget"] = {}
    for scene in BUDGET_SCENES:
        f = report["scenes"][scene]
        ms = f.get("gpu_median_ms") or f["median_ms"]
        report["budget"][scene] = {"ms": ms, "clock": "gpu" if f.get("gpu_median_ms") else "wall",
                                   "budget_ms": BUDGET_MS, "within": ms <= BUDGET_MS}
    report["tables"] = _tables(plan, session_of, ctx, progress)
    report["seconds"] = round(time.perf_counter() - t_start, 1)
    ctx.release()
    return report


def _tables(plan: Plan, session_of, ctx, progress) -> dict:
    from ..gpu.device import Gpu
    from . import clouds, ocean, planet, village_grass

    def table(label: str, open_, measure):
        t0 = time.perf_counter()
        held = open_()
        try:
            out = measure(held)
        finally:
            held.release()
        progress(f"{label} ({time.perf_counter() - t0:.1f} s)")
        return out

    return {
        "planet": table("planet table", lambda: session_of("planet"), lambda s: planet.thesis_table(
            s, plan.planet_sizes, plan.warmup, plan.planet_repeat)),
        "clouds": table("clouds Table 6.1", lambda: session_of("clouds"), lambda s: clouds.table(
            s, plan.cloud_sizes, plan.warmup, max(2, plan.rounds // 3))),
        "grass": table("grass methods", lambda: Gpu(ctx), lambda gpu: village_grass.speed_table(
            gpu, plan.grass_counts, plan.grass_size, rounds=plan.rounds,
            budget_s=plan.budget_s * 4)),
        "ocean_fft": table("FFT sizes", lambda: session_of("ocean"), lambda s: ocean.fft_sweep(
            s, plan.size, plan.fft_sizes, plan.fft_cascades, plan.warmup, plan.rounds)),
    }


def _ms(entry: dict, key: str = "median_ms") -> str:
    v = entry.get(key)
    return "—" if v is None else f"{v:.2f}"


def markdown(report: dict) -> str:
    lines = ["# Natura GPU report", "", f"`{report['context']}`", "",
             f"Frames at {report['plan']['size'][0]}×{report['plan']['size'][1]}, "
             f"{report['plan']['rounds']} interleaved rounds; "
             + ("GPU timer queries beside wall time." if report["gpu_timers"] else
                "wall time only (a software renderer: no GPU timers)."), "",
             "## Paths on this context", ""]
    for what, ways in sorted(report["paths"].items()):
        lines.append(f"- {what}: " + "; ".join(f"{how} [{scenes}]" if len(ways) > 1 else how
                                               for how, scenes in ways))
    lines += ["", "## Frames", "",
              "| scene | wall ms (p25–p75) | GPU ms (p25–p75) | slowest pass |",
              "|---|---|---|---|"]
    for scene, f in report["scenes"].items():
        slow = max(f["passes"].items(), key=lambda kv: kv[1].get("gpu_median_ms")
                   or kv[1].get("median_ms") or 0.0, default=(None, {}))
        key = "gpu_median_ms" if report["gpu_timers"] else "median_ms"
        slowest = f"{slow[0]} {_ms(slow[1], key)} ms" if slow[0] else "—"
        lines.append(f"| {scene} | {_ms(f)} ({_ms(f, 'p25_ms')}–{_ms(f, 'p75_ms')}) | "
                     f"{_ms(f, 'gpu_median_ms')} ({_ms(f, 'gpu_p25_ms')}–"
                     f"{_ms(f, 'gpu_p75_ms')}) | {slowest} |")
    lines += ["", "## The 16.7 ms budget (60 fps)", ""]
    for scene, b in report["budget"].items():
        lines.append(f"- {scene}: {b['ms']:.2f} ms ({b['clock']}) — "
                     + ("within" if b["within"] else "over") + " the budget")
    t = report["tables"]
    lines += ["", "## Atmosphere thesis: methods × sizes", "",
              "| view | size | method | ms | fps | fps vs method 1 |", "|---|---|---|---|---|---|"]
    for r in t["planet"]["rows"]:
        lines.append(f"| {r['view']} | {r['size'][0]}×{r['size'][1]} | {r['method']} | "
                     f"{r['ms']:.2f} | {r['fps']:.0f} | {r['ratio_fps_to_method_1']:.2f} |")
    lines += ["", "## Cloud thesis Table 6.1", "",
              "| preset | size | thesis's march ms | with the speed work ms | speed-up |",
              "|---|---|---|---|---|"]
    for r in t["clouds"]["rows"]:
        lines.append(f"| {r['preset']} | {r['size'][0]}×{r['size'][1]} | {r['thesis_ms']:.2f} | "
                     f"{r['speed_work_ms']:.2f} | {r['speedup']:.2f} |")
    lines += ["", "## Grass methods (net of the clear)", "",
              "| method | blades | ms | blades per second |", "|---|---|---|---|"]
    for r in t["grass"]:
        lines.append(f"| {r['method']} | {r['blades']:,} | {r['net_ms']:.2f} | "
                     f"{r['blades_per_s']:.3g} |")
    lines += ["", "## FFT ocean: grid sizes", "", "| N | cascades | frame ms | simulation ms |",
              "|---|---|---|---|"]
    for r in t["ocean_fft"]["rows"]:
        if "skipped" in r:
            lines.append(f"| {r['fft_size']} | {r['cascades']} | skipped: {r['skipped']} | |")
        else:
            lines.append(f"| {r['fft_size']} | {r['cascades']} | {r['ms_frame']:.2f} | "
                         f"{r['ms_sim']:.2f} |")
    lines += ["", f"({report['seconds']} s in all.)", ""]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", action="store_true", help="llvmpipe sizes (CI)")
    ap.add_argument("--out", default="gpu-report", help="folder for gpu-report.json and .md")
    args = ap.parse_args(argv)
    from ..imageio import write_text_atomic

    report = run(SMALL if args.small else FULL, progress=lambda s: print(s, flush=True))
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out / "gpu-report.json", json.dumps(report, indent=1, default=str) + "\n",
                      force=True)
    write_text_atomic(out / "gpu-report.md", markdown(report), force=True)
    print(out / "gpu-report.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
