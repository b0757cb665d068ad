"""The village's grass, measured (spec/003 §2.9): the three methods of ``app/effects/grass`` at
equal blade counts, and the crossed billboards' side-view coverage against their number of
planes.

What a blade is (app/sim/grass.py): for ``geometry`` one pyramid per root triangle (6(S − 1) +
3 triangles, S = ``grass.gs_sections``); for ``billboard`` a unit counts as the 8 blades its
tuft texture shows, so N blades are ⌈N/8⌉ units of n crossed planes (2n triangles); for
``instanced`` one instance of the Bézier strip (2·segments − 1 triangles), culled per 8 m tile
and drawn with fewer segments beyond the LOD distance.

1. **speed** — ms of each method's pass (from a cleared target, so no method inherits the
   depth of the one before; the clear is timed alone in the same rounds and subtracted) at
   10k, 30k, 100k, 300k and 1M blades (quick: 10k and 30k) on the village's island, from a
   fixed camera over the meadow west of the plaza, at the scene's defaults; interleaved
   rounds (``app.gpu.timing.time_interleaved``), medians and quartiles; blades per second =
   blades ÷ the net median; the triangles drawn and, for the instanced method, the blades left
   after culling.
2. **coverage** — the fraction of the image a row of three crossed-billboard units (one per
   tuft) covers from a side view at grass level, far away with a narrow field (nearly
   orthographic), for n = 1, 2, 3, 4 planes, with the document's angles (θ_k = k·180°/n) and
   the repository's (−90° + Δ/2 + k·Δ), rendered single-sample (the alpha cutoff decides), and
   the numpy twin's figure (``app.sim.grass.side_coverage``). The thesis: "from three planes
   on the effect is practically the same" — the n = 3 → 4 change.

``run(gpu, quick)`` → dict; ``chart(report, path)`` (both panels); ``summary(report)`` →
lines. On llvmpipe absolute times mean little; the ratios within one interleaved set hold.
"""

from __future__ import annotations

import numpy as np

from ..effects.grass import Grass
from ..frame import FrameContext
from ..gpu.timing import time_interleaved
from ..params import ParamSet
from ..sim import grass as gs
from ..sim.camera import Camera
from ..sim.daynight import Light
from ..sim.village import Island
from . import pyplot, write_chart

OWNER = "bench-village-grass"
COUNTS = (10_000, 30_000, 100_000, 300_000, 1_000_000)
QUICK_COUNTS = (10_000, 30_000)
#: over the meadow west of the plaza, looking north-east across it
CAMERA = Camera(position=(-38.0, 7.0, 38.0), yaw=40.0, pitch=-16.0, fov=60.0, near=0.1,
                far=2000.0)
SUN = Light("sun", np.array([0.45, 0.75, -0.48]), (1.0, 0.96, 0.9), 3.0, (0.25, 0.3, 0.38))
#: the wind the speed section runs in: 8 m/s toward the east (w_i = 0.4)
WIND = np.array([8.0, 0.0])
DEFINITIONS = {
    "geometry": "one blade = one pyramid per root triangle, 6(S − 1) + 3 triangles",
    "billboard": "one unit = the 8 blades its tuft shows: N blades are ceil(N/8) units of n "
                 "crossed planes, 2n triangles each",
    "instanced": "one blade = one instance of the Bézier strip, 2·segments − 1 triangles; "
                 "tiles of 8 m culled on the CPU, the LOD strip beyond the LOD distance",
}


def _speed(gpu, effect: Grass, island: Island, counts, size, rounds: int,
           budget_s: float) -> list[dict]:
    target = gpu.target(OWNER, "speed", size)
    frame = FrameContext(size, CAMERA, time=2.0, terrain=island, wind=WIND, main_light=SUN)
    effect.update(frame, 0.0)
    rows = []
    try:
        for n in counts:
            effect.params.set("grass.blades", int(n))
            last = {}
            for m in gs.METHODS:  # build each method's buffers outside the timed rounds
                effect.params.set("grass.method", m)
                target.clear()
                effect.draw(frame, target)
                last[m] = dict(effect.last)

            def variant(m):
                def run():
                    effect.params.set("grass.method", m)
                    target.clear()
                    effect.draw(frame, target)
                return run

            variants = {m: variant(m) for m in gs.METHODS}
            variants["clear"] = target.clear
            # the building draws above are each method's untimed warm-up run
            timed = time_interleaved(gpu.ctx, variants, warmup=0, rounds=rounds,
                                     budget_s=budget_s, min_rounds=min(rounds, 3))
            clear_ms = timed.quartiles("clear")[1]
            for m in gs.METHODS:
                p25, med, p75 = timed.quartiles(m)
                net = max(med - clear_ms, 1e-3)
                rows.append({"method": m, "blades": int(n), "median_ms": med, "p25_ms": p25,
                             "p75_ms": p75, "clear_ms": clear_ms, "net_ms": net,
                             "blades_per_s": n / (net * 1e-3),
                             "triangles": int(last[m].get("triangles", 0)),
                             "drawn_blades": int(last[m].get("blades", 0)),
                             "rounds": timed.rounds})
    finally:
        gpu.free(target)
        effect.params.reset("grass.method")
        effect.params.reset("grass.blades")
    return rows


def _coverage(gpu, effect: Grass) -> dict:
    size = (240, 80)
    target = gpu.target(OWNER, "coverage", size)
    cam = Camera(position=(0.0, 0.25, 40.0), yaw=0.0, pitch=0.0, fov=1.3, near=1.0, far=100.0)
    units = gs.Units(np.array([[-0.6, 0.0, 0.0], [0.0, 0.0, 0.0], [0.6, 0.0, 0.0]]),
                     np.zeros(3), np.zeros(3), np.array([0.0, 1.0, 2.0]), np.ones((3, 3)))
    frame = FrameContext(size, cam, main_light=SUN)
    alphas = [gs.tuft_texture(k)[..., 3] for k in range(3)]
    out: dict = {"planes": [1, 2, 3, 4], "layouts": {}}
    try:
        for layout in gs.ANGLE_LAYOUTS:
            rendered, twin = [], []
            for n in (1, 2, 3, 4):
                for k, v in {"bb_planes": n, "billboard_y": "world", "bb_scale": 0.25,
                             "bb_angles": layout}.items():
                    effect.params.set(f"grass.{k}", v)
                target.clear()
                effect.draw_units(frame, target, units)
                rendered.append(float((target.read()[..., :3].max(axis=-1) > 0.0).mean()))
                twin.append(float(np.mean([gs.side_coverage(a, gs.plane_angles(n, layout))
                                           for a in alphas])))
            out["layouts"][layout] = {
                "rendered": rendered, "twin": twin,
                "change_3_to_4": rendered[3] / rendered[2] - 1.0 if rendered[2] else None,
                "angles": {n: [float(a) for a in gs.plane_angles(n, layout)]
                           for n in (1, 2, 3, 4)}}
    finally:
        gpu.free(target)
        for k in ("bb_planes", "billboard_y", "bb_scale", "bb_angles"):
            effect.params.reset(f"grass.{k}")
    return out


def speed_table(gpu, counts, size, rounds: int = 5, budget_s: float = 60.0) -> list[dict]:
    """The methods' speed at each blade count on the island's meadow (the speed section
    alone, for the GPU report)."""
    effect = Grass(gpu, ParamSet(Grass.declare(gpu.shaders)), owner=OWNER)
    try:
        return _speed(gpu, effect, Island(), counts, size, rounds=rounds, budget_s=budget_s)
    finally:
        effect.release()


def run(gpu, quick: bool = False) -> dict:
    """Both sections (the module docstring)."""
    import time

    start = time.perf_counter()
    effect = Grass(gpu, ParamSet(Grass.declare(gpu.shaders)), owner=OWNER)
    island = Island()
    size = (160, 90) if quick else (320, 180)
    counts = QUICK_COUNTS if quick else COUNTS
    try:
        speed = _speed(gpu, effect, island, counts, size, rounds=3 if quick else 5,
                       budget_s=4.0 if quick else 60.0)
        coverage = _coverage(gpu, effect)
        p = effect.params
        settings = {k: p[f"grass.{k}"] for k in ("gs_sections", "bb_planes", "segments",
                                                  "lod_segments", "lod_distance",
                                                  "draw_distance", "billboard_y")}
    finally:
        effect.release()
    return {"quick": quick, "size": list(size), "counts": list(counts),
            "renderer": gpu.ctx.info.get("GL_RENDERER", "?"),
            "camera": {"position": list(CAMERA.position), "yaw": CAMERA.yaw,
                       "pitch": CAMERA.pitch, "fov": CAMERA.fov},
            "wind_m_s": WIND.tolist(), "settings": settings, "definitions": DEFINITIONS,
            "speed": speed, "coverage": coverage,
            "seconds": round(time.perf_counter() - start, 2)}


def chart(section_report: dict, path, force: bool = False) -> None:
    """Left: net ms against blades per method (log–log); right: side-view coverage against
    the number of crossed planes, rendered and twin, both angle layouts."""
    plt = pyplot()

    r = section_report
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.4))
    for m, colour in zip(gs.METHODS, ("tab:red", "tab:green", "tab:blue")):
        rows = [x for x in r["speed"] if x["method"] == m]
        xs = [x["blades"] for x in rows]
        a.plot(xs, [x["net_ms"] for x in rows], "o-", color=colour, label=m)
        a.fill_between(xs, [max(x["p25_ms"] - x["clear_ms"], 1e-3) for x in rows],
                       [max(x["p75_ms"] - x["clear_ms"], 1e-3) for x in rows], color=colour,
                       alpha=0.15)
    a.set(xscale="log", yscale="log", xlabel="blades (equal for every method)",
          ylabel="ms per pass (clear subtracted; quartile band)")
    a.set_title(f"speed, {r['size'][0]}×{r['size'][1]}, {r['renderer'][:28]}", fontsize=9)
    a.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=8)
    cov = r["coverage"]
    for layout, style in zip(gs.ANGLE_LAYOUTS, ("-", "--")):
        c = cov["layouts"][layout]
        rel = [v / c["rendered"][0] for v in c["rendered"]]
        twin = [v / c["twin"][0] for v in c["twin"]]
        b.plot(cov["planes"], rel, "o" + style, color="tab:green",
               label=f"{layout} angles, rendered")
        b.plot(cov["planes"], twin, "x" + style, color="tab:gray",
               label=f"{layout} angles, numpy twin (orthographic)")
    doc = cov["layouts"]["document"]["change_3_to_4"]
    b.set_xticks(cov["planes"])
    b.set(xlabel="crossed planes per unit n", ylabel="side-view coverage ÷ one plane's")
    b.set_title(f"coverage of a row of units; n = 3 → 4: {100 * doc:+.1f} % (document)",
                fontsize=9)
    b.grid(True, alpha=0.3)
    b.legend(fontsize=7)
    write_chart(fig, path, force=force, title="Village grass (spec/003 §2.9): geometry-shader "
                "blades, crossed billboards, instanced blades")


def summary(section_report: dict) -> list[str]:
    r = section_report
    lines = []
    for n in r["counts"]:
        rows = {x["method"]: x for x in r["speed"] if x["blades"] == n}
        lines.append(f"{n:>9,} blades: " + ", ".join(
            f"{m} {rows[m]['net_ms']:.1f} ms ({rows[m]['blades_per_s'] / 1e6:.2f} M blades/s)"
            for m in gs.METHODS if m in rows))
    for layout in gs.ANGLE_LAYOUTS:
        c = r["coverage"]["layouts"][layout]
        lines.append(f"side coverage n = 1..4 ({layout} angles): "
                     + ", ".join(f"{v:.3f}" for v in c["rendered"])
                     + f"; n = 3 → 4 {100 * c['change_3_to_4']:+.1f} %")
    return lines
