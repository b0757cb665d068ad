"""``natura bench SCENE --budget MS``: which passes blow a frame budget, and which measured
parameter changes bring the frame under it at the least error.

The options are the measured points of the scene's sweeps (``report["sweep"]``, written by
``app/bench/<scene>.py``, read back by app/teach/sweeps.py: settings, ms, error). Options whose
time, scaled to the bench's frame (see :func:`budget_view`), fits the budget are listed lowest
error first, each as a ready ``--set name=value`` string (only the values that differ from the
bench's parameters).

Everything here reads the report dict only: no GL, no session.
"""

from __future__ import annotations

from typing import Any

# the sweeps' extraction lives in app.teach.sweeps (the quality picker reads it too)
from ..teach.sweeps import _finite, _size, format_value, same, scene_options

#: passes that are references, not parts of the frame
REFERENCES = ("reference.fullscreen", "reference.clear")
#: how many fitting options are printed
TOP = 5


def set_string(sets: dict[str, Any], current: dict[str, Any]) -> str:
    """``--set name=value`` for each value that differs from ``current``."""
    changed = [f"--set {k}={format_value(v)}" for k, v in sets.items()
               if k not in current or not same(current[k], v)]
    return " ".join(changed) if changed else "(the bench's own settings)"


def over_budget(report: dict, budget_ms: float) -> list[tuple[str, float]]:
    return [(name, p["median_ms"]) for name, p in report.get("passes", {}).items()
            if name not in REFERENCES and _finite(p.get("median_ms"))
            and p["median_ms"] > budget_ms]


def budget_view(report: dict, budget_ms: float, top: int = TOP) -> list[str]:
    """The lines ``natura bench SCENE --budget MS`` prints."""
    size = _size(report["size"])
    where = f"{size[0]}x{size[1]}"
    lines = []
    frame = report.get("passes", {}).get("frame", {}).get("median_ms")
    if _finite(frame):
        verdict = "over" if frame > budget_ms else "within"
        lines.append(f"budget {budget_ms:g} ms at {where}: the frame takes {frame:.3f} ms, "
                     f"{verdict} the budget")
    over = over_budget(report, budget_ms)
    if over:
        lines.append("over budget: " + ", ".join(f"{n} {ms:.3f} ms" for n, ms in over))
    else:
        lines.append(f"no pass is over {budget_ms:g} ms")
    found = scene_options(report)
    if found is None:
        return lines
    lines += [f"note: {n}" for n in found.notes]
    opts = found.options
    if not opts:
        lines.append("the sweeps hold no option with a time and an error")
        return lines
    current = report.get("parameters", {})
    # The frame's cost under each option: the measured frame times the option's time ratio to
    # the current settings' in the same sweep (the sweep may time a slice or another size: the
    # ratio carries over, its absolute time does not); without a current-settings row, the
    # option's own time scaled by pixel count.
    base = next((o for o in opts
                 if all(k in current and same(current[k], v) for k, v in o.sets.items())), None)
    if base is not None and _finite(frame) and base.ms > 0:
        estimate = {id(o): frame * o.ms / base.ms for o in opts}
        lines.append("each option's frame time = the measured frame × its time ratio to the "
                     f"current settings' in the sweep ({base.label})")
    else:
        estimate = {id(o): o.ms_at(size) for o in opts}
        scaled = sorted({o.size for o in opts if o.size != size})
        if scaled:
            lines.append("times scaled by pixel count from the sweep's "
                         + ", ".join(f"{w}x{h}" for w, h in scaled) + f" to {where} "
                         "(assumes cost ∝ pixels: fixed costs do not scale)")
    fits = sorted((o for o in opts if estimate[id(o)] <= budget_ms),
                  key=lambda o: (o.error, estimate[id(o)]))
    if not fits:
        fastest = min(opts, key=lambda o: estimate[id(o)])
        lines.append(f"no measured option fits {budget_ms:g} ms; the fastest: "
                     f"{set_string(fastest.sets, current)}  ≈{estimate[id(fastest)]:.3f} ms, "
                     f"error {fastest.error:.3g} ({fastest.label})")
        return lines
    lines.append(f"options that fit, lowest error first (error: {found.metric}):")
    for o in fits[:max(1, top)]:
        measured = "" if o.size == size else f", {o.ms:.3f} ms at {o.size[0]}x{o.size[1]}"
        lines.append(f"  {set_string(o.sets, current)}  ≈{estimate[id(o)]:.3f} ms{measured}, "
                     f"error {o.error:.3g} ({o.label})")
    if len(fits) > top:
        lines.append(f"  … and {len(fits) - top} more that fit with more error")
    return lines
