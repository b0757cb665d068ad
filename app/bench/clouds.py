"""Speed against accuracy for the volumetric clouds: ms per frame and error against a fine march.

* **Table 6.1 of the cloud thesis** (spec/001 §3): the three presets × 256², 512², 800² and
  1920×1080 (``--sizes`` scales it for slow renderers), ms per frame for the thesis's marcher
  (uniform 64 steps, 6 light samples, naive sum, no reprojection) and for the speed work
  (adaptive steps, energy-conserving steps, temporal reprojection in steady state — distance-
  dependent steps are measured alone: they cost more error than they save), with the speed-up,
  and which preset is slowest.
* **Time against error**: the cloud layer (premultiplied radiance and transmittance) against
  the same model at 512 steps without jitter or reprojection, for the view steps, the light
  samples, each speed option alone, and their combination; "equal error" compares the cheapest
  configuration whose error is at most the thesis marcher's with the thesis marcher. The app's
  default march (``DEFAULT_MARCH``: the parameters' defaults, reprojection off as in a single
  render) is measured uniform and adaptive at several step counts.
* **The error budget of the default** (``BUDGET_FACTOR``): the default march's mean error
  against the 512-step reference must stay within 1.5 × that of the uniform 64-step march with
  the default integration (the march the app shipped before adaptive steps became the default;
  the thesis's own marcher, naive sum, is several times worse still, so the budget is tighter
  than "as good as the thesis"). The factor bounds what a speed option may cost in accuracy:
  at most half again the uniform march's error, which at the default settings is far below a
  display step (the mean |Δ| is ~1e-3 of radiance values up to ~3). ``budget`` says whether
  the default meets it.
* **The amortised march** (``app/bench/amortise.py``): ms of the march pass against the error
  of the window's image, still and during a 30°/s pan, for each march resolution and refresh
  fraction, against the full-resolution march averaged over its jittered offsets.
* **Default before / after**: the uniform 64-step default against the adaptive one, timed in
  one interleaved run (``app.gpu.timing.time_interleaved``: per-round ratios, median and
  quartiles) with the error of each against the same reference.
"""

from __future__ import annotations

import numpy as np

from ..gpu.timing import time_call, time_interleaved
from ..teach.sweeps import THESIS_MARCH
from . import amortise, at_most, pyplot, ratio_text, write_chart

PRESETS = ("cumulus", "stratocumulus", "stratus")
DEFAULT_SIZES = ((256, 256), (512, 512), (800, 800), (1920, 1080))
#: the thesis's marcher (defined in app.teach.sweeps, which the quality picker reads)
THESIS = THESIS_MARCH
SPEED = {"clouds.adaptive_steps": True, "clouds.energy_conserving": True,
         "clouds.reprojection": "on"}
REFERENCE = {"clouds.steps": 512, "clouds.jitter": False, "clouds.reprojection": "off",
             "clouds.adaptive_steps": False, "clouds.distance_steps": False,
             "clouds.energy_conserving": True}
#: the parameters of the march that the speed options change (their defaults: ``default_march``)
MARCH_KEYS = ("clouds.steps", "clouds.light_steps", "clouds.energy_conserving",
              "clouds.adaptive_steps", "clouds.distance_steps", "clouds.jitter")
#: the default march's mean error may be at most this × the uniform 64-step march's (see above)
BUDGET_FACTOR = 1.5
BUDGET_BASIS = "default integration, uniform 64 steps"


def default_march(params) -> dict:
    """The app's default march: each of ``MARCH_KEYS`` at its default, reprojection off (a
    single render marches every pixel)."""
    return {**{k: params.spec(k).default for k in MARCH_KEYS}, "clouds.reprojection": "off"}


def _layer(session, size) -> np.ndarray:
    eff = session.scene.effect("clouds")
    w, h = size
    return np.frombuffer(eff._layer.color.read(), dtype="f4").reshape(h, w, 4).astype(np.float64)


def _steady_frame_ms(session, size, warmup: int, repeat: int) -> tuple[float, np.ndarray]:
    """ms per frame once reprojection (if on) has a full history; and the layer after it.
    Without reprojection the one frame before the history's place is the first of the
    ``warmup`` untimed runs (it builds what the configuration changed; the layer it leaves is
    the one every later frame leaves)."""
    gpu = session.gpu
    with gpu.scratch_target("bench", "clouds frame", size) as target:
        reprojecting = session.params["clouds.reprojection"] != "off"
        frame = session.scene.frame(size)
        for _ in range(17 if reprojecting else 1):
            session.scene.render(frame, target)  # fill the history (static camera, wind 0)
        ms = time_call(gpu.ctx, "frame", lambda: session.scene.render(frame, target),
                       warmup if reprojecting else max(0, warmup - 1), repeat).median_ms
        return ms, _layer(session, size)


def table(session, sizes=DEFAULT_SIZES, warmup: int = 1, repeat: int = 3) -> dict:
    p = session.params
    session.scene.interactive = True
    rows = []
    for preset in PRESETS:
        p.set("clouds.preset", preset)
        for size in sizes:
            p.set_many(THESIS)
            thesis_ms, _ = _steady_frame_ms(session, tuple(size), warmup, repeat)
            p.set_many(SPEED)
            fast_ms, _ = _steady_frame_ms(session, tuple(size), warmup, repeat)
            rows.append({"preset": preset, "size": list(size), "thesis_ms": thesis_ms,
                         "speed_work_ms": fast_ms, "speedup": thesis_ms / fast_ms})
    slowest = {}
    for size in sizes:
        cell = [r for r in rows if r["size"] == list(size)]
        slowest[f"{size[0]}x{size[1]}"] = {
            "thesis": max(cell, key=lambda r: r["thesis_ms"])["preset"],
            "speed_work": max(cell, key=lambda r: r["speed_work_ms"])["preset"],
        }
    return {"rows": rows, "slowest": slowest}


def accuracy(session, size=(160, 90), warmup: int = 1, repeat: int = 3,
             preset: str = "cumulus") -> dict:
    p = session.params
    session.scene.interactive = True
    p.set_many({"clouds.preset": preset, "clouds.wind_speed": 0.0})
    p.set_many(REFERENCE)
    _, ref = _steady_frame_ms(session, size, 0, 1)
    rows = []

    def measure(label, values, base=THESIS):
        p.set_many(base)
        p.set_many(values)
        ms, layer = _steady_frame_ms(session, size, warmup, repeat)
        d = np.abs(layer - ref).max(axis=-1)
        rows.append({"config": label, "ms": ms, "mean": float(d.mean()),
                     "p99": float(np.percentile(d, 99)),
                     **{k.split(".")[1]: v for k, v in values.items()}})

    for n in (16, 32, 64, 128, 256):
        measure(f"uniform {n} steps (thesis marcher)", {"clouds.steps": n})
    for n in (2, 4, 6, 10):
        measure(f"light samples {n}", {"clouds.light_steps": n})
    measure("energy-conserving", {"clouds.energy_conserving": True})
    measure("distance steps", {"clouds.distance_steps": True})
    measure("adaptive steps", {"clouds.adaptive_steps": True})
    measure("reprojection", {"clouds.reprojection": "on"})
    for n in (24, 32, 40, 48, 64, 96, 128):
        measure(f"all speed work, {n} steps", {**SPEED, "clouds.steps": n})
    default = default_march(p)
    for n in (32, 48, 64, 96, 128):
        for adaptive in (False, True):
            measure(f"default {'adaptive' if adaptive else 'uniform'} {n} steps",
                    {"clouds.steps": n, "clouds.adaptive_steps": adaptive}, base=default)
    thesis = next(r for r in rows if r["config"] == "uniform 64 steps (thesis marcher)")
    candidates = [r for r in rows
                  if r["config"].startswith("all speed work") and r["mean"] <= thesis["mean"]]
    best = min(candidates, key=lambda r: r["ms"]) if candidates else None
    return {"size": list(size), "preset": preset, "rows": rows,
            "equal_error": {"thesis": thesis["config"], "thesis_ms": thesis["ms"],
                            "thesis_mean": thesis["mean"],
                            "best": best["config"] if best else None,
                            "best_ms": best["ms"] if best else None,
                            "speedup": (thesis["ms"] / best["ms"]) if best else None},
            "budget": budget(rows, default)}


def budget(rows: list[dict], default: dict) -> dict:
    """The error budget (``BUDGET_FACTOR`` × the uniform 64-step march at the default
    integration) and whether the default march meets it."""
    by = {r["config"]: r for r in rows}
    basis = by["default uniform 64 steps"]
    chosen = by[f"default {'adaptive' if default['clouds.adaptive_steps'] else 'uniform'} "
                f"{default['clouds.steps']} steps"]
    bound = BUDGET_FACTOR * basis["mean"]
    return {"factor": BUDGET_FACTOR, "basis": BUDGET_BASIS, "basis_mean": basis["mean"],
            "mean_bound": bound, "default": chosen["config"], "default_mean": chosen["mean"],
            "default_p99": chosen["p99"], "within": bool(chosen["mean"] <= bound),
            "adaptive_default": bool(default["clouds.adaptive_steps"])}


def default_change(session, sizes=((160, 90), (320, 180)), warmup: int = 1, rounds: int = 9,
                   preset: str = "cumulus") -> dict:
    """The default march before (uniform) and after (adaptive steps) in one interleaved run
    per size: per-round time ratios after / before, and the mean error of each against the
    512-step reference."""
    p = session.params
    session.scene.interactive = True
    p.set_many({"clouds.preset": preset, "clouds.wind_speed": 0.0})
    gpu = session.gpu
    out = []
    for size in sizes:
        size = tuple(int(v) for v in size)
        p.set_many(REFERENCE)
        _, ref = _steady_frame_ms(session, size, 0, 1)
        with gpu.scratch_target("bench", "clouds default", size) as target:
            frame = session.scene.frame(size)
            variants = {}
            errors = {}
            for name, adaptive in (("before", False), ("after", True)):
                values = {**default_march(p), "clouds.adaptive_steps": adaptive}

                def run(values=values):
                    p.set_many(values)
                    session.scene.render(frame, target)

                variants[name] = run
                run()  # its error, and the first of its untimed runs
                d = np.abs(_layer(session, size) - ref).max(axis=-1)
                errors[name] = {"mean": float(d.mean()), "p99": float(np.percentile(d, 99))}
            timed = time_interleaved(gpu.ctx, variants, max(0, warmup - 1), rounds)
        out.append({"size": list(size), "rounds": timed.rounds,
                    "ratio": timed.ratio("after", "before"),
                    "before_ms": timed.quartiles("before")[1],
                    "after_ms": timed.quartiles("after")[1],
                    "before": errors["before"], "after": errors["after"]})
    return {"before": "default uniform 64 steps (adaptive steps off)",
            "after": "default adaptive 64 steps", "rows": out}


def sweep(session, size, warmup: int = 1, repeat: int = 3, sizes=None) -> dict:
    saved = session.params.values()
    try:
        change_sizes = tuple(dict.fromkeys(at_most(size, s) for s in ((160, 90), (320, 180))))
        out = {"accuracy": accuracy(session, size=at_most(size, (160, 90)), warmup=warmup,
                                    repeat=repeat),
               "default_change": default_change(session, sizes=change_sizes, warmup=warmup,
                                                rounds=max(5, 3 * repeat)),
               "table": table(session, sizes or DEFAULT_SIZES, warmup, repeat)}
        session.params.set_many(saved)
        out["amortised"] = amortise.sweep(session, "clouds", at_most(size, (320, 180)), warmup,
                                          repeat)
    finally:
        session.params.set_many(saved)
        session.scene.interactive = False
    return out


def _in_group(config: str, prefix: str) -> bool:
    """Whether a row's ``config`` is one of the chart's group ``prefix`` ("uniform" is not
    "default uniform")."""
    return config.startswith(prefix) and config[len(prefix):len(prefix) + 1] in (" ", ",")


def chart(report: dict, path, force: bool = False) -> None:
    plt = pyplot()

    s = report["sweep"]
    fig, axes = plt.subplots(1, 3 if "amortised" in s else 2,
                             figsize=(21 if "amortised" in s else 14, 5))
    ax = axes[0]
    groups = {"uniform": ("o-", "uniform (thesis marcher)"), "light samples": ("s-", None),
              "all speed work": ("D-", None),
              "default uniform": ("v-", "default integration, uniform"),
              "default adaptive": ("P-", "default integration, adaptive steps")}
    for prefix, (style, label) in groups.items():
        rows = [r for r in s["accuracy"]["rows"] if _in_group(r["config"], prefix)]
        ax.plot([r["ms"] for r in rows], [max(r["mean"], 1e-6) for r in rows], style,
                label=label or prefix)
        for r in rows:
            n = r.get("steps", r.get("light_steps", ""))
            ax.annotate(str(n), (r["ms"], max(r["mean"], 1e-6)), fontsize=7,
                        textcoords="offset points", xytext=(3, 3))
    bud = s["accuracy"].get("budget")
    if bud:
        ax.axhline(bud["mean_bound"], color="k", ls=":", lw=1,
                   label=f"error budget {bud['mean_bound']:.2e} "
                         f"({bud['factor']:g} × {bud['basis']})")
        d = next(r for r in s["accuracy"]["rows"] if r["config"] == bud["default"])
        ax.plot([d["ms"]], [max(d["mean"], 1e-6)], "*", ms=14, mfc="none", mec="r",
                label=f"the default: {bud['default']}")
    for r in s["accuracy"]["rows"]:
        if not any(_in_group(r["config"], p) for p in groups):
            ax.plot([r["ms"]], [max(r["mean"], 1e-6)], "^", label=r["config"])
    ax.set(yscale="log",
           xlabel=f"ms per frame at {s['accuracy']['size'][0]}×{s['accuracy']['size'][1]}",
           ylabel="mean |layer − 512-step reference|")
    eq = s["accuracy"]["equal_error"]
    title = (f"time against error (equal-error speed-up ×{eq['speedup']:.1f})"
             if eq["speedup"] else "time against error")
    ch = s.get("default_change")
    if ch and ch["rows"]:
        q = ch["rows"][0]["ratio"]
        title += (f"\nadaptive default: time ×{q['median']:.2f} [{q['p25']:.2f}–{q['p75']:.2f}] "
                  f"at {ch['rows'][0]['size'][0]}×{ch['rows'][0]['size'][1]}")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=6)
    ax = axes[1]
    rows = s["table"]["rows"]
    labels = [f"{r['preset']}\n{r['size'][0]}×{r['size'][1]}" for r in rows]
    x = np.arange(len(rows))
    ax.bar(x - 0.2, [r["thesis_ms"] for r in rows], 0.4, label="thesis marcher (64 uniform steps)")
    ax.bar(x + 0.2, [r["speed_work_ms"] for r in rows], 0.4, label="speed work")
    ax.set_xticks(x, labels, fontsize=6, rotation=60)
    ax.set(ylabel="ms per frame", yscale="log", title="the cloud thesis's Table 6.1 layout")
    ax.legend(fontsize=8)
    if "amortised" in s:
        amortise.plot(axes[2], s["amortised"])
    write_chart(fig, path, force, title=f"natura bench clouds — {report['renderer']}")


def summary(report: dict) -> str:
    s = report["sweep"]
    lines = ["preset         size        thesis ms   speed-work ms   speed-up"]
    for r in s["table"]["rows"]:
        lines.append(f"{r['preset']:14s} {r['size'][0]}x{r['size'][1]:<7d} {r['thesis_ms']:9.1f} "
                     f"{r['speed_work_ms']:14.1f}   ×{r['speedup']:.2f}")
    for size, who in s["table"]["slowest"].items():
        lines.append(f"slowest at {size}: {who['thesis']} (thesis marcher), "
                     f"{who['speed_work']} (speed work)")
    lines.append("config                                   ms     error mean / p99")
    for r in s["accuracy"]["rows"]:
        lines.append(f"{r['config']:38s} {r['ms']:8.2f}   {r['mean']:.2e} / {r['p99']:.2e}")
    eq = s["accuracy"]["equal_error"]
    lines.append(f"equal error: {eq['thesis']} {eq['thesis_ms']:.2f} ms "
                 f"(mean {eq['thesis_mean']:.2e}) vs "
                 f"{eq['best']} "
                 f"{eq['best_ms'] if eq['best_ms'] is None else round(eq['best_ms'], 2)} ms → "
                 f"speed-up {eq['speedup'] if eq['speedup'] is None else round(eq['speedup'], 2)}")
    bud = s["accuracy"].get("budget")
    if bud:
        lines.append(f"error budget: mean ≤ {bud['factor']:g} × {bud['basis']} "
                     f"({bud['basis_mean']:.2e}) = {bud['mean_bound']:.2e}; the default "
                     f"({bud['default']}) {bud['default_mean']:.2e} → "
                     f"{'within' if bud['within'] else 'OVER'} the budget")
    ch = s.get("default_change")
    if ch:
        lines.append(f"default before → after: {ch['before']} → {ch['after']} "
                     "(one interleaved run)")
        for r in ch["rows"]:
            q = r["ratio"]
            lines.append(f"  {r['size'][0]}x{r['size'][1]}: time {ratio_text(q)} "
                         f"({r['before_ms']:.1f} → {r['after_ms']:.1f} ms); error mean "
                         f"{r['before']['mean']:.2e} → {r['after']['mean']:.2e}, p99 "
                         f"{r['before']['p99']:.2e} → {r['after']['p99']:.2e}")
    if "amortised" in s:
        lines += amortise.summary(s["amortised"])
    return "\n".join(lines)
