"""The benches' sweeps read back from a bench report (``report["sweep"]``) as the measured
:class:`Point` s of ``natura bench SCENE --budget MS`` (app/bench/budget.py says what they
are); the quality picker (app/teach/quality.py) shares the points and the helpers. The
settings the benches measure with live here too (:data:`THESIS_MARCH`,
:data:`HILLAIRE_SIZES`): app.bench imports them from here, as app.teach may not import
app.bench. No GL, no session.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

from ..runtime import scene_params

#: the thesis's cloud marcher (spec/001 §3): uniform 64 steps, 6 light samples, the naive sum,
#: no reprojection — the base of the cloud sweep's "uniform N steps" and "light samples" rows
THESIS_MARCH = {"clouds.steps": 64, "clouds.light_steps": 6, "clouds.energy_conserving": False,
                "clouds.adaptive_steps": False, "clouds.distance_steps": False,
                "clouds.reprojection": "off", "clouds.jitter": True}

#: Hillaire LUT resolutions scaled together by the planet sweep's "lut scale" knob
#: (defaults × scale)
HILLAIRE_SIZES = ("hillaire.transmittance_width", "hillaire.transmittance_height",
                  "hillaire.ms_size", "hillaire.skyview_width", "hillaire.skyview_height",
                  "hillaire.ap_size", "hillaire.ap_slices")


def scale_hillaire(params, scale: float) -> None:
    """Set each of :data:`HILLAIRE_SIZES` to its default × ``scale`` (within its range; the
    sky-view height kept even)."""
    for name in HILLAIRE_SIZES:
        q = params.spec(name)
        value = int(min(q.hi, max(q.lo, round(q.default * scale))))
        if name == "hillaire.skyview_height":
            value += value % 2
        params.set(name, value)


@dataclass
class Point:
    """One measured setting of a sweep: the parameters it sets, its ms at ``size`` (the size
    the sweep timed it at) and its error against the sweep's reference."""

    label: str
    sets: dict[str, Any]
    ms: float
    error: float
    size: tuple[int, int]
    #: the part of ``ms`` that does not grow with the pixel count (not scaled by ms_at)
    fixed_ms: float = 0.0

    def ms_at(self, size: tuple[int, int] | None = None) -> float:
        """ms at ``size``: the per-pixel part scaled by pixel count from the sweep's size."""
        if size is None or tuple(size) == tuple(self.size):
            return self.ms
        scale = (size[0] * size[1]) / (self.size[0] * self.size[1])
        return self.fixed_ms + (self.ms - self.fixed_ms) * scale


@dataclass
class SceneOptions:
    """A scene's options (``natura bench --budget``) and what their error means."""

    metric: str
    options: list[Point]
    notes: list[str] = field(default_factory=list)


def _size(value) -> tuple[int, int]:
    return int(value[0]), int(value[1])


def _finite(*values) -> bool:
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
               for v in values)


def format_value(value: Any) -> str:
    """A parameter value as ``--set`` takes it back: true/false, comma-separated vectors."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return ",".join(format_value(v) for v in value)
    if isinstance(value, float):
        return repr(int(value)) if value.is_integer() and abs(value) < 1e15 else repr(value)
    return str(value)


def same(a: Any, b: Any) -> bool:
    """Whether two parameter values are the same setting (numbers within rounding, sequences
    item by item, anything else by its text: "256" is 256)."""
    if isinstance(a, (list, tuple)) or isinstance(b, (list, tuple)):
        return isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)) and len(a) == len(
            b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, bool) or isinstance(b, bool):
        return a is b or a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)
    return str(a) == str(b)


def _clouds(sweep: dict) -> SceneOptions:
    acc = sweep["accuracy"]
    base = dict(THESIS_MARCH)
    known = {"config", "ms", "mean", "p99"}
    opts = []
    for row in acc.get("rows", []):
        if not _finite(row.get("ms"), row.get("mean")):
            continue
        knobs = {f"clouds.{k}": v for k, v in row.items() if k not in known}
        # "default …" rows start from the scene's default march, the others from the thesis's
        start = {} if row["config"].startswith("default ") else base
        opts.append(Point(row["config"], {**start, **knobs}, row["ms"], row["mean"],
                          _size(acc["size"])))
    return SceneOptions(f"mean |cloud layer − 512-step reference| ({acc.get('preset', '?')}, "
                        "no wind)", opts)


def hillaire_scaled(scale: float, params=None) -> dict[str, Any]:
    """The Hillaire LUT sizes the planet sweep's "lut scale" knob set (defaults × scale);
    ``params``: a planet ParamSet to work on (its sizes are overwritten)."""
    if params is None:
        params = scene_params("planet")
    scale_hillaire(params, scale)
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
                sets.update(hillaire_scaled(float(v)))
            except Exception:  # noqa: BLE001 - the sizes cannot be rebuilt: leave it out
                continue
        elif knob == "single scattering only":
            sets["hillaire.multiple_scattering"] = False
        else:
            continue
        opts.append(Point(label, sets, r["ms"], error, size))
    if any(o.label.startswith("hillaire") for o in opts):
        notes.append("hillaire's error counts its multiple scattering (the reference is single "
                     "scattering)")
    return SceneOptions(f"mean |in-scatter − float64 reference| (ground view, "
                        f"{acc['size'][0]}x{acc['size'][1]})", opts, notes)


def ocean_rows(sweep: dict, model: str) -> list[tuple[dict, float]]:
    """The rows of the ocean sweep's ``model`` table ("fft" or "gerstner") with a frame time
    and an error, each with its error: the worst of |mean-square-slope deficit|, |Hs error| and
    the directional-shape distance (all relative, against the spectrum)."""
    out = []
    for r in sweep.get(model, {}).get("rows", []):
        parts = [r.get("mss_deficit"), r.get("hs_error"), r.get("shape_distance")]
        if (model == "fft" or r.get("model") == model) and _finite(r.get("ms_frame"), *parts):
            out.append((r, max(abs(p) for p in parts)))
    return out


def _ocean(sweep: dict) -> SceneOptions:
    size = _size(sweep.get("view_size", (640, 360)))
    opts = []
    for r, err in ocean_rows(sweep, "fft"):
        opts.append(Point(f"fft {r['fft_size']}² × {r['cascades']} cascades",
                          {"ocean.model": "fft", "ocean.fft_size": str(r["fft_size"]),
                           "ocean.cascades": int(r["cascades"])}, r["ms_frame"], err, size))
    for r, err in ocean_rows(sweep, "gerstner"):
        opts.append(Point(f"{r['waves']} Gerstner waves",
                          {"ocean.model": "gerstner", "ocean.gerstner_waves": int(r["waves"])},
                          r["ms_frame"], err, size))
    return SceneOptions("the worst of |mean-square-slope deficit|, |Hs error| and the "
                        "directional-shape distance against the spectrum", opts)


def _materials(sweep: dict) -> SceneOptions:
    rings = sweep.get("ring_edges", {})
    opts = []
    for key, value in (("hard", False), ("filtered", True)):
        r = rings.get(key)
        if r and _finite(r.get("median_ms"), r.get("mean_error")):
            opts.append(Point(f"{key} ring edges", {"materials.filter_rings": value},
                              r["median_ms"], r["mean_error"], _size(rings["size"])))
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
