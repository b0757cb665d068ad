"""What a lab's default frame costs against its reference, and what the picture gives up for it
(the labs at interactive speed without a GPU). Each variant is a set of
parameters — the reference (the full-cost methods, as the lab drew before it chose from the
context), each speed knob alone, and the defaults — rendered at the bench's size:

* **speed** — the frame's per-frame passes (those not cached between frames: for the surfaces
  lab the opaque and the transparent passes; the shadow maps and the probe are re-rendered only
  when what they show changes) timed in interleaved rounds: each round runs every variant once
  in a shuffled order, the variant's parameters applied and its cached work (shadow maps, probe,
  programs) brought up to date outside the timed span, ``ctx.finish()`` on both sides of it. A
  variant's ratio to the reference is taken round by round, so machine load moves both sides;
* **picture** — the variant's frame against the reference's in 8-bit display values (the
  scene's exposure and tone map, :func:`app.colour.to_srgb8`): the largest channel's |Δ| per
  pixel, its mean, 99th percentile and maximum in 8-bit levels, and the share of pixels more than
  two levels off.

The surfaces lab's variants (:data:`SURFACES`): ``reference`` (4× MSAA, the full 5 × 5 PCF
taps, the generic surface program), ``specialised`` (the same but the specialised programs:
the same image), ``taps fast`` (the 3 × 3 PCF alone), ``no MSAA`` (MSAA off alone) and
``default`` (``surfaces.msaa=auto``, ``surfaces.shadow_taps=auto``: what this renderer gets).
The shading lab's (:data:`SHADING`, used by app/bench/shading.py): ``reference`` (full taps:
PCSS's 7 × 7 blocker search), ``taps fast`` and ``default``.

API: ``run(session, size, variants, passes, warmup, rounds, budget_s) -> dict``,
``chart_axes(ax, report)``, ``chart(report, path, force=False)``, ``summary(report) ->
list[str]``.
"""

from __future__ import annotations

import random
import statistics
import time
from pathlib import Path

import numpy as np

from ..colour import to_srgb8

#: surfaces: name → the parameters it sets over the scene's (the reference first)
SURFACES: dict[str, dict] = {
    "reference": {"surfaces.msaa": "4", "surfaces.shadow_taps": "full",
                  "surfaces.specialise": False},
    "specialised": {"surfaces.msaa": "4", "surfaces.shadow_taps": "full",
                    "surfaces.specialise": True},
    "taps fast": {"surfaces.msaa": "4", "surfaces.shadow_taps": "fast",
                  "surfaces.specialise": True},
    "no MSAA": {"surfaces.msaa": "0", "surfaces.shadow_taps": "full",
                "surfaces.specialise": True},
    "default": {},
}
SURFACES_PASSES = ("surfaces.opaque", "surfaces.transparent")
#: shading: the same, for the shading lab's PCSS ground and objects
SHADING: dict[str, dict] = {
    "reference": {"shading.shadow_taps": "full"},
    "taps fast": {"shading.shadow_taps": "fast"},
    "default": {},
}
SHADING_PASSES = ("shading",)
#: a pixel this many 8-bit levels off counts as visibly changed
VISIBLE_LEVELS = 2


def _apply(params, saved: dict, sets: dict) -> None:
    for name, value in saved.items():
        if params[name] != value:
            params.set(name, value)
    params.set_many(sets)


def _display(session, image: np.ndarray) -> np.ndarray:
    mode = session.params["output.tonemap"] if "output.tonemap" in session.params else "aces"
    return to_srgb8(image[..., :3], session.scene.exposure(), mode).astype(np.int64)


def picture_error(a: np.ndarray, b: np.ndarray) -> dict:
    """8-bit display images ``a`` against ``b``: the largest channel's |Δ| per pixel — its mean,
    99th percentile and maximum in levels, and the share over :data:`VISIBLE_LEVELS`."""
    d = np.abs(a - b).max(axis=-1)
    return {"mean_levels": float(d.mean()), "p99_levels": float(np.percentile(d, 99)),
            "max_levels": float(d.max()), "share_visible": float((d > VISIBLE_LEVELS).mean())}


def chosen(session) -> dict:
    """What the context made of the lab's ``auto`` settings: the surfaces lab's MSAA samples
    and either lab's shadow taps (``full`` or ``fast``)."""
    from ..render.shadows import ShadowSettings

    names = [e.name for e in session.scene.instances]
    out: dict = {}
    for group in ("surfaces", "shading"):
        if group in names:
            effect = session.scene.effect(group)
            if hasattr(effect, "samples"):
                out["msaa"] = effect.samples()
            settings = (effect.shadow_settings() if hasattr(effect, "shadow_settings")
                        else ShadowSettings.from_params(session.params, group))
            out["taps"] = settings.resolved_taps(session.gpu.caps.software)
    return out


def run(session, size, variants: dict[str, dict], passes: tuple[str, ...], warmup: int = 1,
        rounds: int = 5, budget_s: float | None = 30.0, seed: int = 0) -> dict:
    """The module's docstring for ``variants`` (the first is the reference) at ``size``; the
    timed passes are ``passes`` (by name, of ``session.scene.passes``). Each row records the
    parameters it ran with (``resolved``: the reference's keys) and what the context made of
    them (``chosen``). The session's parameters are as they were afterwards."""
    gpu = session.gpu
    ctx = gpu.ctx
    params = session.params
    saved = params.values()
    size = (int(size[0]), int(size[1]))
    target = gpu.target("bench", "speed against the picture", size)
    names = list(variants)
    times: dict[str, dict[str, list[float]]] = {n: {p: [] for p in passes} for n in names}
    totals: dict[str, list[float]] = {n: [] for n in names}
    images: dict[str, np.ndarray] = {}
    resolved: dict[str, dict] = {}
    choices: dict[str, dict] = {}
    try:
        frame = session.scene.frame(size, 0.0)

        def prepare(name: str) -> dict:
            """Apply the variant, run the passes it does not time (cached work), return the
            timed ones."""
            _apply(params, saved, variants[name])
            by_name = {p.name: p for p in session.scene.passes(frame, target)}
            missing = [p for p in passes if p not in by_name]
            if missing:
                raise ValueError(f"speed variant {name!r}: no pass {missing[0]!r}: allowed "
                                 f"{', '.join(by_name)}")
            target.clear()
            for p in by_name.values():
                if p.name not in passes:
                    p.run()
            ctx.finish()
            return by_name

        for name in names:
            _apply(params, saved, variants[name])
            for _ in range(1 + max(0, warmup)):  # caches, programs, then the image
                session.scene.render(frame, target)
            images[name] = _display(session, target.read())
            resolved[name] = {k: params[k] for k in variants[names[0]]}
            choices[name] = chosen(session)
        rng = random.Random(seed)
        start = time.perf_counter()
        done = 0
        for _ in range(max(1, rounds)):
            if budget_s is not None and done >= 2 and time.perf_counter() - start > budget_s:
                break
            done += 1
            order = names[:]
            rng.shuffle(order)
            for name in order:
                by_name = prepare(name)
                total = 0.0
                for p in passes:  # in the frame's order: each from where the last left off
                    t0 = time.perf_counter()
                    by_name[p].run()
                    ctx.finish()
                    ms = (time.perf_counter() - t0) * 1e3
                    times[name][p].append(ms)
                    total += ms
                totals[name].append(total)
    finally:
        _apply(params, saved, {})
        gpu.free(target)
    ref = names[0]
    rows = []
    for name in names:
        ratios = [a / b for a, b in zip(totals[name], totals[ref]) if b > 0]
        rows.append({"variant": name, "sets": dict(variants[name]),
                     "resolved": resolved[name], "chosen": choices[name],
                     "ms": statistics.median(totals[name]),
                     "pass_ms": {p: statistics.median(v) for p, v in times[name].items()},
                     "ratio": statistics.median(ratios) if ratios else float("nan"),
                     **picture_error(images[name], images[ref])})
    return {"size": list(size), "rounds": done, "passes": list(passes), "reference": ref,
            "rows": rows}


def chart_axes(ax, report: dict, title: str) -> None:
    """ms of the timed passes against the picture's error (mean and p99 in 8-bit levels)."""
    for key, marker in (("mean_levels", "o"), ("p99_levels", "^")):
        xs = [r["ms"] for r in report["rows"]]
        ys = [r[key] for r in report["rows"]]
        ax.scatter(xs, ys, marker=marker, s=24, label=key.replace("_levels", " |Δ|"))
    for r in report["rows"]:
        ax.annotate(r["variant"], (r["ms"], r["p99_levels"]), fontsize=7, xytext=(3, 3),
                    textcoords="offset points")
    ax.set(xlabel=f"ms of {' + '.join(report['passes'])} ({report['rounds']} rounds)",
           ylabel=f"8-bit levels off the {report['reference']}")
    ax.set_yscale("symlog", linthresh=1.0)
    ax.legend(fontsize=7)
    ax.set_title(title, fontsize=9)


def chart(report: dict, path, force: bool = False, title: str = "the lab's frame") -> None:
    from . import pyplot, write_chart

    plt = pyplot()

    fig, ax = plt.subplots(figsize=(6, 4))
    chart_axes(ax, report, f"{title} at {report['size'][0]}×{report['size'][1]}: speed "
                           "against the picture")
    write_chart(fig, Path(path), force=force)


def summary(report: dict, label: str) -> list[str]:
    lines = [f"{label} at {report['size'][0]}x{report['size'][1]} ({report['rounds']} rounds; "
             f"ms of {' + '.join(report['passes'])}, ratio to the {report['reference']}, "
             "8-bit |Δ| mean/p99/max and share over 2 levels):"]
    for r in report["rows"]:
        settings = ", ".join([f"{k.split('.', 1)[1]}={v}" for k, v in r["resolved"].items()]
                             + [f"→ {k} {v}" for k, v in r.get("chosen", {}).items()])
        lines.append(f"  {r['variant']:12s} {r['ms']:9.2f} ms  ×{r['ratio']:.2f}  "
                     f"{r['mean_levels']:.3f}/{r['p99_levels']:.0f}/{r['max_levels']:.0f}  "
                     f"{100 * r['share_visible']:.2f} %  ({settings})")
    return lines
