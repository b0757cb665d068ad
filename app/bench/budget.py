"""``natura bench SCENE --budget MS``: which passes blow a frame budget, and which measured
parameter changes bring the frame under it at the least error.

The options come from the sweeps of the scene's bench module (``report["sweep"]``, written by
``app/bench/<scene>.py``): each measured variant becomes an :class:`Option` — the parameter
assignment the sweep set, its ms per frame at the size the sweep timed it, and its error
against the sweep's reference. Options whose time, scaled by pixel count from the sweep's
size to the bench size, fits the budget are listed lowest error first, each as a ready
``--set name=value`` string (only the values that differ from the bench's parameters).

Everything here reads the report dict only: no GL, no session.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

#: passes that are references, not parts of the frame
REFERENCES = ("reference.fullscreen", "reference.clear")
#: how many fitting options are printed
TOP = 5


@dataclass
class Option:
    """One measured variant of a scene's sweep."""

    label: str
    sets: dict[str, Any]
    ms: float                      # ms per frame as measured by the sweep
    size: tuple[int, int]          # the size the sweep timed it at
    error: float
    notes: list[str] = field(default_factory=list)

    def scaled_ms(self, size: tuple[int, int]) -> float:
        """ms at ``size``, scaled by pixel count from the size the sweep timed it at."""
        return self.ms * (size[0] * size[1]) / (self.size[0] * self.size[1])


@dataclass
class SceneOptions:
    """A scene's options and what their error means."""

    metric: str
    options: list[Option]
    notes: list[str] = field(default_factory=list)


def _size(value) -> tuple[int, int]:
    return int(value[0]), int(value[1])


def _finite(*values) -> bool:
    return all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)


# ---- per-scene extraction ---------------------------------------------------------------------

def _clouds(sweep: dict) -> SceneOptions:
    acc = sweep["accuracy"]
    try:
        from .clouds import THESIS
        base = dict(THESIS)
    except ImportError:  # the sweep's base settings moved: the rows' own knobs only
        base = {}
    known = {"config", "ms", "mean", "p99"}
    opts = []
    for row in acc.get("rows", []):
        if not _finite(row.get("ms"), row.get("mean")):
            continue
        knobs = {f"clouds.{k}": v for k, v in row.items() if k not in known}
        # "default …" rows start from the scene's default march, the others from the thesis's
        start = {} if row["config"].startswith("default ") else base
        opts.append(Option(row["config"], {**start, **knobs}, row["ms"], _size(acc["size"]),
                           row["mean"]))
    return SceneOptions(f"mean |cloud layer − 512-step reference| ({acc.get('preset', '?')}, "
                        "no wind)", opts)


def _hillaire_scaled(scale: float) -> dict[str, Any]:
    """The Hillaire LUT sizes the planet sweep's "lut scale" knob set (defaults × scale)."""
    if scale == 1.0:
        from ..runtime import scene_params
        from .planet import HILLAIRE_SIZES

        params = scene_params("planet", None, [], None)
        return {name: params.spec(name).default for name in HILLAIRE_SIZES}
    from ..runtime import scene_params
    from .planet import HILLAIRE_SIZES, _scale_hillaire

    params = scene_params("planet", None, [], None)
    _scale_hillaire(params, scale)
    return {name: params[name] for name in HILLAIRE_SIZES}


def _planet(sweep: dict, current: dict) -> SceneOptions:
    acc = sweep["accuracy"]
    size = _size(acc.get("time_size", acc["size"]))
    rows = [r for r in acc.get("rows", []) if _finite(r.get("ms"), r.get("in_mean"))]
    max_steps = max((r["value"] for r in rows if r["knob"] == "n_steps"), default=None)
    notes = []
    opts = []
    for r in rows:
        method, knob, v = r["method"], r["knob"], r["value"]
        sets: dict[str, Any] = {"planet.method": method}
        error = r["in_mean"]
        label = f"{method} {knob} {v}"
        if knob == "n_steps":
            sets.update({"planet.n_steps": v, "planet.inner_steps": v})
        elif knob.startswith("n_steps, thesis"):
            sets.update({"planet.pc_rule": "thesis", "planet.n_steps": v})
            if max_steps is not None:  # the sweep left inner_steps at its last n_steps
                sets["planet.inner_steps"] = max_steps
        elif knob == "lut_size":
            sets.update({"planet.lut_height": v, "planet.lut_angle": v})
        elif knob.startswith("shadow_map_size"):
            # its error is against an 8192² map: add the same method's error at the current
            # step count against the reference (the triangle inequality: an upper bound)
            n = current.get("planet.n_steps")
            base = next((b for b in rows if b["method"] == "shadowed"
                         and b["knob"] == "n_steps" and b["value"] == n), None)
            if base is None:
                continue
            sets["planet.shadow_map_size"] = v
            error = base["in_mean"] + r["in_mean"]
        elif knob == "lut scale":
            try:
                sets.update(_hillaire_scaled(float(v)))
            except Exception:  # noqa: BLE001 - the sizes cannot be rebuilt: leave it out
                continue
        elif knob == "single scattering only":
            sets["hillaire.multiple_scattering"] = False
        else:
            continue
        opts.append(Option(label, sets, r["ms"], size, error))
    if any(o.label.startswith("hillaire") for o in opts):
        notes.append("hillaire's error counts its multiple scattering (the reference is single "
                     "scattering)")
    return SceneOptions(f"mean |in-scatter − float64 reference| (ground view, "
                        f"{acc['size'][0]}x{acc['size'][1]})", opts, notes)


def _ocean_error(row: dict) -> float | None:
    parts = [row.get("mss_deficit"), row.get("hs_error"), row.get("shape_distance")]
    if not all(_finite(p) for p in parts):
        return None
    return max(abs(p) for p in parts)  # type: ignore[arg-type]


def _ocean(sweep: dict) -> SceneOptions:
    size = _size(sweep.get("view_size", (640, 360)))
    opts = []
    for r in sweep.get("fft", {}).get("rows", []):
        err = _ocean_error(r)
        if err is None or not _finite(r.get("ms_frame")):
            continue
        opts.append(Option(f"fft {r['fft_size']}² × {r['cascades']} cascades",
                           {"ocean.model": "fft", "ocean.fft_size": str(r["fft_size"]),
                            "ocean.cascades": int(r["cascades"])}, r["ms_frame"], size, err))
    for r in sweep.get("gerstner", {}).get("rows", []):
        err = _ocean_error(r)
        if r.get("model") != "gerstner" or err is None or not _finite(r.get("ms_frame")):
            continue
        opts.append(Option(f"{r['waves']} Gerstner waves",
                           {"ocean.model": "gerstner", "ocean.gerstner_waves": int(r["waves"])},
                           r["ms_frame"], size, err))
    return SceneOptions("the worst of |mean-square-slope deficit|, |Hs error| and the "
                        "directional-shape distance against the spectrum", opts)


def _materials(sweep: dict) -> SceneOptions:
    rings = sweep.get("ring_edges", {})
    opts = []
    for key, value in (("hard", False), ("filtered", True)):
        r = rings.get(key)
        if r and _finite(r.get("median_ms"), r.get("mean_error")):
            opts.append(Option(f"{key} ring edges", {"materials.filter_rings": value},
                               r["median_ms"], _size(rings["size"]), r["mean_error"]))
    notes = ["materials' timed sweep is a wood slice seen from above, not the whole frame; "
             "its octave and bake sweeps have no parameter with an error"]
    return SceneOptions("mean |display − 8×8 supersampled| of fine wood rings", opts, notes)


EXTRACT: dict[str, Callable[[dict, dict], SceneOptions]] = {
    "clouds": lambda sweep, current: _clouds(sweep),
    "planet": _planet,
    "ocean": lambda sweep, current: _ocean(sweep),
    "materials": lambda sweep, current: _materials(sweep),
}


def scene_options(report: dict) -> SceneOptions | None:
    """The options in ``report``'s sweeps; None where the report has none (or its scene has
    no extractor here: adding a scene is adding one to :data:`EXTRACT`)."""
    sweep = report.get("sweep")
    extract = EXTRACT.get(report.get("scene", ""))
    if not sweep or extract is None:
        return None
    try:
        return extract(sweep, report.get("parameters", {}))
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        return SceneOptions("?", [], [f"the sweep's layout is not the one expected ({exc!r})"])


# ---- the view ---------------------------------------------------------------------------------

def format_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return ",".join(format_value(v) for v in value)
    if isinstance(value, float):
        return repr(int(value)) if value.is_integer() and abs(value) < 1e15 else repr(value)
    return str(value)


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, (list, tuple)) or isinstance(b, (list, tuple)):
        return isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)) and len(a) == len(
            b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b or a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
    return str(a) == str(b)


def set_string(sets: dict[str, Any], current: dict[str, Any]) -> str:
    """``--set name=value`` for each value that differs from ``current``."""
    changed = [f"--set {k}={format_value(v)}" for k, v in sets.items()
               if k not in current or not _same(current[k], v)]
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
                 if all(k in current and _same(current[k], v) for k, v in o.sets.items())), None)
    estimate: dict[int, float] = {}
    if base is not None and _finite(frame) and base.ms > 0:
        for o in opts:
            estimate[id(o)] = frame * o.ms / base.ms
        lines.append("each option's frame time = the measured frame × its time ratio to the "
                     f"current settings' in the sweep ({base.label})")
    else:
        for o in opts:
            estimate[id(o)] = o.scaled_ms(size)
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
