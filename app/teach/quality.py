"""Quality by budget ("model no more than a scene needs"): ``--quality auto`` with
``--error-budget E`` and/or ``--ms-budget MS`` picks, per effect and per knob, the cheapest
setting whose *measured* error stays within the budget — from the sweeps the benches already
measure (``natura bench SCENE`` writes them into its JSON report), not from a model of cost.

**Families.** A family is one knob of one effect measured by one sweep (the extractors below:
:data:`EXTRACT`), each point a setting with its ms and its error against that sweep's reference.
A family applies only when the scene runs the method it was measured with (``planet.method``,
``ocean.model``...); the others are skipped, each with its reason.

**Units.** Each family's error is its sweep's own metric (printed with it: radiance for the
planet and the clouds, a relative spectrum figure for the ocean, texels for parallax, a share
of points for shadows...). ``--error-budget E`` is in that metric, so one number means
different things to different families; ``--error-budget Nx`` is the relative form: at most N
times the error of the setting the scene has now (a family whose current setting was not
measured is skipped with that reason). The ms are each family's measured time (the frame's,
or the pass the sweep timed: printed), scaled by pixel count from the size the sweep timed to
the render's size (as ``natura bench --budget`` does; parts that do not depend on the pixel
count, such as the ocean's spectrum simulation, are not scaled).

**The rules of the pick** (per family, among its measured points):

* error budget only — the cheapest point (lowest ms; ties: lower error) whose error ≤ the
  budget; none within it → nothing is chosen (the setting stays) and the most accurate point
  is named;
* ms budget only — the most accurate point (lowest error; ties: lower ms) whose ms ≤ the
  budget; none fits → nothing is chosen and the fastest point is named;
* both — the cheapest point within the error budget that also fits the ms budget; else the
  constraint that fails is said and the most accurate point that fits the ms budget is kept
  (its error is then over the error budget, and the line says so); nothing fits the ms budget
  → nothing is chosen.

A tighter error budget therefore never chooses a cheaper point, and a looser ms budget never a
less accurate one (tests/unit/test_quality.py checks both). The values given with ``--set``
win over the picker: a family whose knob the user set is left as set, and its line says what
the picker would have chosen. Each family's error was measured with the other knobs at the
sweep's settings: the errors of two families' picks do not simply add. Where the sweeps come
from: :func:`load_sweeps`. No GL here.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import statistics
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

from .. import PROJECT_ROOT
from ..errors import UsageError, quote
from ..imageio import check_output_path, save_figure
from ..runtime import scene_params
from . import sweeps
from .sweeps import Point, _finite, _size, format_value, hillaire_scaled, ocean_rows, same

#: the shipped measured runs (llvmpipe): docs/ (bench-planet.json and the like)
SHIPPED = PROJECT_ROOT / "docs"
#: the folder ``natura bench SCENE`` writes its reports to (relative to the current folder)
RESULTS = Path("bench-results")
#: the largest report read (a bench report is tens of kB)
MAX_REPORT_BYTES = 64 * 2**20
#: a pick that saves less than this share of the current setting's ms is flagged as within
#: timing noise
NOISE_SHARE = 0.05

MODES = ("fixed", "auto")


@dataclass
class Family:
    """One knob family of one effect, e.g. planet / "N_STEPS (method 3, LUT + shadows)"."""

    scene: str
    effect: str
    knob: str
    metric: str
    points: list[Point]
    source: str
    #: the settings the sweep measured with, which the scene must have for the family to
    #: apply: name → value, or a tuple of allowed values (planet.pc_rule and
    #: clouds.reprojection are compared as they take effect: see :func:`effective_value`)
    requires: dict[str, Any] = field(default_factory=dict)
    #: what the ms time ("the frame", "the wall's shading pass", ...)
    timed: str = "the frame"
    notes: list[str] = field(default_factory=list)

    @property
    def title(self) -> str:
        return f"{self.effect} · {self.knob}"

    @property
    def names(self) -> list[str]:
        """The parameters the family's points set."""
        return list(dict.fromkeys(k for p in self.points for k in p.sets))

    def current(self, params) -> Point | None:
        """The point whose settings the scene has now (None: not measured)."""
        for p in self.points:
            if all(same(_get(params, k), v) for k, v in p.sets.items()):
                return p
        return None

    def applies(self, params, interactive: bool = False) -> str | None:
        """None when the scene runs what the family was measured with, else why not."""
        for name, want in self.requires.items():
            have = effective_value(params, name, interactive)
            allowed = want if isinstance(want, tuple) else (want,)
            if not any(same(have, w) for w in allowed):
                shown = " or ".join(format_value(w) for w in allowed)
                how = " (as it takes effect)" if name in _DERIVED else ""
                return (f"measured with {name}={shown}; yours is "
                        f"{format_value(have) if have is not _MISSING else 'unset'}{how}")
        return None


@dataclass
class Choice:
    """The picker's answer for one family: ``point`` None when nothing is chosen (the family
    was skipped, nothing meets the budget, or the user's --set wins)."""

    family: Family
    point: Point | None
    reason: str
    #: chosen (within every budget) · over (the most accurate that fits the ms budget, over
    #: the error budget) · none (nothing meets the budget) · skipped · yours (--set wins)
    status: str = "chosen"
    current: Point | None = None
    error_budget: float | None = None     # absolute, in the family's metric
    ms_budget: float | None = None
    size: tuple[int, int] | None = None   # the size the ms are scaled to (None: as measured)
    would: Point | None = None            # status "yours": what the picker would choose

    def ms(self, point: Point) -> float:
        return point.ms_at(self.size)

    def line(self) -> str:
        """One line: the chosen setting, its ms and error, and why."""
        head = self.family.title
        if self.status == "skipped":
            return f"{head}: skipped — {self.reason}"
        if self.status == "yours":
            would = (f" (the picker would choose {self._figures(self.would)})"
                     if self.would is not None else "")
            return f"{head}: {self.reason}{would}"
        if self.point is None:
            kept = f"; kept {self.current.label}" if self.current is not None else ""
            return f"{head}: nothing chosen — {self.reason}{kept}"
        now = ""
        if self.current is self.point:
            now = "; already the current setting"
        elif self.current is not None:
            now = f"; now {self._figures(self.current)}"
        return f"{head}: {self._figures(self.point, budget=True)} ({self.reason}{now})"

    def _figures(self, p: Point, budget: bool = False) -> str:
        text = f"{p.label}: {_ms(self.ms(p))} ms, error {p.error:.3g}"
        if budget and self.error_budget is not None:
            text += f" {'≤' if p.error <= self.error_budget else '>'} {self.error_budget:.3g}"
        return text


class Picks(list):
    """:func:`pick`'s list of :class:`Choice`, with where the sweeps came from and the lines to
    print."""

    def __init__(self, choices: Iterable[Choice] = (), *, scene: str = "", source: str = "",
                 problem: str | None = None, notes: Iterable[str] = (),
                 error_budget: float | Relative | None = None, ms_budget: float | None = None,
                 size: tuple[int, int] | None = None, about: str = ""):
        super().__init__(choices)
        self.scene, self.source, self.problem = scene, source, problem
        self.notes = list(notes)
        self.error_budget, self.ms_budget, self.size, self.about = (error_budget, ms_budget,
                                                                     size, about)

    @property
    def sets(self) -> dict[str, Any]:
        """The parameter values the picks set (the chosen and the kept-within-ms points)."""
        out: dict[str, Any] = {}
        for c in self:
            if c.point is not None and c.status in ("chosen", "over"):
                out.update(c.point.sets)
        return out

    def changes(self, params) -> dict[str, Any]:
        """:attr:`sets` less the values ``params`` already has."""
        return {k: v for k, v in self.sets.items() if not same(_get(params, k), v)}

    def apply(self, params) -> dict[str, Any]:
        """Set the picks on ``params``; returns what changed."""
        changed = self.changes(params)
        for k, v in changed.items():
            params.set(k, v)
        return changed

    def lines(self, params=None) -> list[str]:
        """What ``--quality auto`` prints: the budgets and the source, each family's metric,
        one line per family, notes, and the picks as --set (against ``params``)."""
        if self.problem is not None:
            return [f"quality auto: {self.problem}: keeping the settings as they are"]
        budget = []
        e = self.error_budget
        if e is not None:
            budget.append(f"error ≤ {e.factor:g} × each family's current error"
                          if isinstance(e, Relative)
                          else f"error ≤ {e:g} (each family's own metric)")
        if self.ms_budget is not None:
            budget.append(f"ms ≤ {self.ms_budget:g}")
        where = f" at {self.size[0]}x{self.size[1]}" if self.size else ""
        out = [f"quality auto for {self.scene}{where}: {', '.join(budget)}",
               f"  sweeps: {self.source}{self.about}"]
        if self.size:
            out.append(f"  ms scaled by pixel count from each sweep's size to "
                       f"{self.size[0]}x{self.size[1]} (fixed costs, e.g. a simulation, not "
                       "scaled)")
        metrics: dict[tuple[str, str], list[str]] = {}
        for c in self:
            if c.status != "skipped":
                metrics.setdefault((c.family.metric, c.family.timed), []).append(c.family.knob)
        for (metric, timed), knobs in metrics.items():
            out.append(f"  {', '.join(knobs)}: error = {metric}; ms of {timed}")
        out += [c.line() for c in self]
        out += [f"note: {n}" for n in self.notes]
        for c in self:
            if c.status not in ("skipped",):
                out += [f"note ({c.family.knob}): {n}" for n in c.family.notes]
        if params is not None:
            changed = self.changes(params)
            if changed:
                out.append("as --set: " + " ".join(f"{k}={format_value(v)}"
                                                   for k, v in changed.items()))
            else:
                status = {c.status for c in self}
                why = ("the settings already are what the budget picks"
                       if status & {"chosen", "over"} else
                       "nothing measured meets the budget" if "none" in status else
                       "no family applies to these settings" if status <= {"skipped"} else
                       "the families left apply to what you set")
                yours = "; your --set values stay" if "yours" in status else ""
                out.append(f"no change: {why}{yours}")
        return out


@dataclass(frozen=True)
class Relative:
    """``--error-budget Nx``: at most ``factor`` × the current setting's error."""

    factor: float


def _ms(value: float) -> str:
    return f"{value:.3g}" if value < 1000 else f"{value:.0f}"


_MISSING = object()
#: the requirements compared as the setting takes effect, not as it is written
_DERIVED = ("planet.pc_rule", "clouds.reprojection")


def _get(params, name: str) -> Any:
    try:
        return params[name]
    except Exception:  # noqa: BLE001 - a ParamError or a KeyError: the scene has no such name
        return _MISSING


def effective_value(params, name: str, interactive: bool = False) -> Any:
    """The value of ``name`` as it takes effect: planet.pc_rule ``by_method`` is resolved for
    the method (app.effects.planet.effect.resolve_pc_rule); clouds.reprojection ``window`` is
    on in the interactive window only."""
    if name == "planet.pc_rule":
        rule, method = _get(params, name), _get(params, "planet.method")
        if rule is _MISSING or method is _MISSING:
            return _MISSING
        from ..effects.planet.effect import resolve_pc_rule

        return resolve_pc_rule(rule, method)
    if name == "clouds.reprojection":
        mode = _get(params, name)
        if mode is _MISSING:
            return mode
        return "on" if mode == "on" or (mode == "window" and interactive) else "off"
    return _get(params, name)


def parse_error_budget(text: str | float) -> float | Relative:
    """``--error-budget``: a finite number ≥ 0 in the families' own metrics, or ``Nx`` (N > 0)
    for N times each family's current error; anything else is one :class:`UsageError` line."""
    allowed = ("allowed a number ≥ 0 in each family's own error metric, or Nx for N times the "
               "current setting's error (e.g. 0.01 or 2x)")
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        raw = str(text)
    elif isinstance(text, str):
        raw = text
    else:
        raise UsageError(f"--error-budget {quote(str(text))}: {allowed}")
    t = raw.strip().lower()
    relative = t.endswith(("x", "×"))
    number = t[:-1].strip() if relative else t
    try:
        value = float(number)
    except ValueError:
        raise UsageError(f"--error-budget {quote(raw)} is not a number: {allowed}") from None
    if not math.isfinite(value):
        raise UsageError(f"--error-budget {quote(raw)} is not finite: {allowed}")
    if value < 0 or (relative and value == 0):
        raise UsageError(f"--error-budget {quote(raw)} is out of range: {allowed}")
    return Relative(value) if relative else value


@dataclass
class Sweeps:
    """A bench report with sweeps and where it came from; ``report`` None with ``problem``."""

    report: dict | None
    source: str
    problem: str | None = None
    #: the user named it (--sweeps FILE): a layout that cannot be read is refused, not noted
    given: bool = False

    @property
    def about(self) -> str:
        """", llvmpipe (…), 2025-…" from the report's renderer and date."""
        if not self.report:
            return ""
        parts = [str(self.report["renderer"])] if self.report.get("renderer") else []
        if self.report.get("when"):
            parts.append(str(self.report["when"])[:10])
        return f": {', '.join(parts)}" if parts else ""


def _read_report(path: Path) -> dict:
    """The JSON object in ``path``, or ValueError/OSError."""
    if path.stat().st_size > MAX_REPORT_BYTES:
        raise ValueError(f"larger than {MAX_REPORT_BYTES // 2**20} MB")
    with open(path, "rb") as f:
        data = json.loads(f.read(MAX_REPORT_BYTES + 1).decode("utf-8"))
    if not isinstance(data, dict):
        raise ValueError("not a JSON object")
    return data


def _shown(path: Path) -> str:
    try:
        return str(path.resolve().relative_to(PROJECT_ROOT))
    except ValueError:
        return str(path)


def load_sweeps(scene_name: str, sweeps: str | os.PathLike | dict | None = None) -> Sweeps:
    """The report to pick from: ``sweeps`` (a path, refused in one line when it is not a
    ``natura bench SCENE_NAME`` report with sweeps, or a report dict), else the newest run of
    ours in ./bench-results with sweeps, else the shipped docs/ (bench-planet.json and the like)."""
    if isinstance(sweeps, dict):
        if sweeps.get("scene") not in (None, scene_name):
            raise UsageError(f"the sweeps given are a bench of {sweeps.get('scene')!r}: allowed "
                             f"a report of natura bench {scene_name}")
        return Sweeps(sweeps, "the report given")
    if sweeps is not None:
        allowed = f"allowed a report of natura bench {scene_name} (JSON, with its sweeps)"
        name = quote(str(sweeps))
        path = Path(os.fspath(sweeps)).expanduser()
        if not path.is_file():
            what = "does not exist" if not os.path.lexists(path) else "is not a file"
            raise UsageError(f"--sweeps {name} {what}: {allowed}")
        try:
            report = _read_report(path)
        except (OSError, ValueError) as exc:
            why = exc.strerror if isinstance(exc, OSError) and exc.strerror else (
                "not JSON" if isinstance(exc, json.JSONDecodeError) else str(exc)[:60])
            raise UsageError(f"--sweeps {name} cannot be read ({why}): {allowed}") from None
        if report.get("scene") != scene_name:
            raise UsageError(f"--sweeps {name} is a bench of {quote(str(report.get('scene')))}"
                             f": {allowed}")
        if not report.get("sweep"):
            raise UsageError(f"--sweeps {name} has no sweeps (run without --no-sweep): "
                             f"{allowed}")
        return Sweeps(report, str(path), given=True)
    pattern = re.compile(rf"{re.escape(scene_name)}-(\d+)\.json")
    try:
        runs = sorted(((int(m.group(1)), p) for p in RESULTS.iterdir()
                       if (m := pattern.fullmatch(p.name))), reverse=True)
    except OSError:
        runs = []
    for _, path in runs:
        try:
            report = _read_report(path)
        except (OSError, ValueError):
            continue
        if report.get("scene") == scene_name and report.get("sweep"):
            return Sweeps(report, f"{path} (your run; --sweeps FILE for another)")
    shipped = SHIPPED / f"bench-{scene_name}.json"
    with contextlib.suppress(OSError, ValueError):
        report = _read_report(shipped)
        if report.get("scene") == scene_name and report.get("sweep"):
            return Sweeps(report, f"{_shown(shipped)} (shipped)")
    return Sweeps(None, "", f"no measured sweeps for {scene_name} (none shipped in "
                  f"docs/bench-{scene_name}.json, none of yours in {RESULTS}/; natura bench "
                  f"{scene_name} measures them where its bench has sweeps, or --sweeps FILE)")


def _planet(report: dict, source: str) -> tuple[list[Family], list[str]]:
    from ..effects.planet.effect import resolve_pc_rule

    acc = report["sweep"]["accuracy"]
    size = _size(acc.get("time_size", acc["size"]))
    w, h = _size(acc["size"])
    ref = acc.get("reference_steps")
    metric = (f"mean |in-scatter − float64 reference| (largest channel, ground view, {w}x{h}"
              + (f", {ref}-step reference" if ref else "") + ")")
    rows = [r for r in acc.get("rows", []) if _finite(r.get("ms"), r.get("in_mean"))]
    bench = report.get("parameters", {})
    rule = bench.get("planet.pc_rule", "by_method")
    names = {"brute_force": "method 1, brute force", "lut": "method 2, optical-depth LUT",
             "shadowed": "method 3, LUT + shadows", "hillaire": "method 4, Hillaire"}
    timed = f"the frame ({size[0]}x{size[1]}, ground view)"
    fams: list[Family] = []

    def family(knob, method, points, requires, metric=metric, notes=()):
        if points:
            fams.append(Family("planet", "planet", f"{knob} ({names.get(method, method)})",
                               metric, points, source, {"planet.method": method, **requires},
                               timed, list(notes)))

    for method in ("brute_force", "lut", "shadowed"):
        pts = [Point(f"N_STEPS={r['value']}",
                     {"planet.n_steps": int(r["value"]),
                      **({"planet.inner_steps": int(r["value"])}
                         if method == "brute_force" else {})},
                     r["ms"], r["in_mean"], size)
               for r in rows if r["method"] == method and r["knob"] == "n_steps"]
        family("N_STEPS", method, pts, {"planet.pc_rule": resolve_pc_rule(rule, method)},
               notes=["method 1's inner (sun) steps follow N_STEPS, as measured"]
               if method == "brute_force" else ())
    pts = [Point(f"N_STEPS={r['value']}", {"planet.n_steps": int(r["value"])}, r["ms"],
                 r["in_mean"], size)
           for r in rows if r["method"] == "lut" and r["knob"].startswith("n_steps, thesis")]
    family("N_STEPS, thesis τ(PC) rule", "lut", pts, {"planet.pc_rule": "thesis"})
    steps = bench.get("planet.n_steps")
    at = [f"measured at N_STEPS={steps}"] if steps is not None else []
    pts = [Point(f"LUT {r['value']}×{r['value']}", {"planet.lut_height": int(r["value"]),
                                                   "planet.lut_angle": int(r["value"])},
                 r["ms"], r["in_mean"], size)
           for r in rows if r["method"] == "lut" and r["knob"] == "lut_size"]
    family("optical-depth LUT size", "lut", pts,
           {"planet.pc_rule": resolve_pc_rule(rule, "lut")}, notes=at)
    pts = [Point(f"shadow map {r['value']}²", {"planet.shadow_map_size": int(r["value"])},
                 r["ms"], r["in_mean"], size)
           for r in rows if r["method"] == "shadowed" and r["knob"].startswith("shadow_map_size")]
    family("shadow-map size", "shadowed", pts, {},
           metric=f"mean |in-scatter − the same with an 8192² shadow map| (ground view, "
           f"{w}x{h})", notes=at)
    pts = []
    scratch = None
    for r in rows:
        if r["method"] == "hillaire" and r["knob"] == "lut scale":
            try:
                if scratch is None:
                    scratch = scene_params("planet")
                pts.append(Point(f"LUT scale {float(r['value']):g}",
                                 hillaire_scaled(float(r["value"]), scratch), r["ms"],
                                 r["in_mean"], size))
            except Exception:  # noqa: BLE001 - the sizes cannot be rebuilt: leave it out
                continue
    family("LUT sizes (× the defaults)", "hillaire", pts, {},
           metric=metric + ", counting Hillaire's multiple scattering",
           notes=["the reference is single scattering: most of this error is Hillaire's "
                  "multiple scattering, which no LUT size removes"])
    notes = []
    if any(r["knob"] == "single scattering only" for r in rows):
        notes.append("hillaire's 'single scattering only' row is a model switch, not a quality "
                     "knob (it meets the single-scattering reference by leaving light out): "
                     "not picked; natura compare shows it")
    return fams, notes


_CLOUD_ROW = re.compile(r"(?:uniform (?P<uniform>\d+) steps \(thesis marcher\)"
                        r"|light samples (?P<light>\d+)"
                        r"|all speed work, (?P<speed>\d+) steps"
                        r"|default (?P<march>uniform|adaptive) (?P<default>\d+) steps)")


def _clouds(report: dict, source: str) -> tuple[list[Family], list[str]]:
    acc = report["sweep"]["accuracy"]
    size = _size(acc["size"])
    preset = acc.get("preset", "?")
    metric = ("mean |cloud layer − 512-step reference| (premultiplied radiance and "
              f"transmittance, largest channel; {preset}, no wind, {size[0]}x{size[1]})")
    defaults = scene_params("clouds")
    thesis = {"clouds.energy_conserving": False, "clouds.adaptive_steps": False,
              "clouds.distance_steps": False, "clouds.reprojection": "off",
              "clouds.jitter": True}
    speed = {"clouds.energy_conserving": True, "clouds.adaptive_steps": True,
             "clouds.distance_steps": False, "clouds.reprojection": "on", "clouds.jitter": True}
    march = {k: defaults.spec(k).default for k in ("clouds.energy_conserving",
                                                   "clouds.distance_steps", "clouds.jitter")}
    groups: dict[str, tuple[dict, list[Point]]] = {
        "view steps (the thesis's marcher: uniform, naive sum)": (thesis, []),
        "light samples (the thesis's marcher, 64 view steps)": (thesis, []),
        "view steps (adaptive, energy-conserving, reprojected)": (speed, []),
        "view steps (the default march, uniform)": (
            {**march, "clouds.adaptive_steps": False, "clouds.reprojection": "off"}, []),
        "view steps (the default march, adaptive)": (
            {**march, "clouds.adaptive_steps": True, "clouds.reprojection": "off"}, []),
    }
    keys = list(groups)
    switches = []
    for r in acc.get("rows", []):
        if not _finite(r.get("ms"), r.get("mean")):
            continue
        m = _CLOUD_ROW.fullmatch(str(r.get("config", "")))
        if m is None:
            switches.append(str(r.get("config")))
            continue
        if m["uniform"]:
            key, n, name = keys[0], int(m["uniform"]), "clouds.steps"
        elif m["light"]:
            key, n, name = keys[1], int(m["light"]), "clouds.light_steps"
        elif m["speed"]:
            key, n, name = keys[2], int(m["speed"]), "clouds.steps"
        else:
            key = keys[3] if m["march"] == "uniform" else keys[4]
            n, name = int(m["default"]), "clouds.steps"
        label = f"{n} light samples" if name == "clouds.light_steps" else f"{n} steps"
        groups[key][1].append(Point(label, {name: n}, r["ms"], r["mean"], size))
    fams = [Family("clouds", "clouds", knob, metric, pts, source, req,
                   f"the frame ({size[0]}x{size[1]}, steady state)")
            for knob, (req, pts) in groups.items() if pts]
    notes = []
    if switches:
        notes.append("the sweep's single switches (" + ", ".join(switches) + ") are methods, "
                     "not knobs: natura compare shows them side by side")
    return fams, notes


def _ocean(report: dict, source: str) -> tuple[list[Family], list[str]]:
    sweep = report["sweep"]
    size = _size(sweep.get("view_size", (640, 360)))
    metric = ("the worst of |mean-square-slope deficit|, |Hs error| and the directional-shape "
              "distance against the spectrum (relative)")
    fft_metric = ("the worst of |mean-square-slope deficit| and |Hs error| against the spectrum "
                  "(relative)")
    where = [f"measured at wind {sweep.get('wind', '?')} m/s, {sweep.get('spectrum', '?')} "
             "spectrum; the simulation's ms are not scaled by pixel count"]
    fft, gerstner, shapes = [], [], []
    for r, _ in ocean_rows(sweep, "fft"):
        err = max(abs(r["mss_deficit"]), abs(r["hs_error"]))
        shapes.append(r["shape_distance"])
        n, c = int(r["fft_size"]), int(r["cascades"])
        sim = r.get("ms_sim")
        fixed = sim if _finite(sim) and 0 <= sim <= r["ms_frame"] else 0.0
        fft.append(Point(f"FFT {n}² × {c} cascade{'s' if c != 1 else ''}",
                         {"ocean.fft_size": str(n), "ocean.cascades": c}, r["ms_frame"], err,
                         size, fixed))
    for r, err in ocean_rows(sweep, "gerstner"):
        gerstner.append(Point(f"{int(r['waves'])} waves",
                              {"ocean.gerstner_waves": int(r["waves"])}, r["ms_frame"], err,
                              size))
    timed = f"the frame ({size[0]}x{size[1]})"
    fams = []
    if fft:
        shape = (f"the directional-shape distance ({min(shapes):.3g}–{max(shapes):.3g} at every "
                 "FFT setting: the spectrum's spreading, which no FFT knob changes) is left out "
                 "of this family's error")
        fams.append(Family("ocean", "ocean", "FFT size × cascades", fft_metric, fft, source,
                           {"ocean.model": "fft"}, timed, [*where, shape]))
    if gerstner:
        fams.append(Family("ocean", "ocean", "Gerstner wave count", metric, gerstner, source,
                           {"ocean.model": "gerstner"}, timed, where[:1]))
    return fams, []


def _materials(report: dict, source: str) -> tuple[list[Family], list[str]]:
    # the same ring-edge rows as natura bench --budget reads
    pts = sweeps.EXTRACT["materials"](report["sweep"], {}).options
    fams = []
    if pts:
        s = pts[0].size
        fams.append(Family("materials", "materials", "ring edges",
                           "mean |display − 8×8 supersampled| of fine wood rings", pts, source,
                           {"materials.material": "wood"},
                           f"a {s[0]}x{s[1]} wood slice seen from above, not the whole frame"))
    return fams, ["the materials' octave and bake sweeps measure no scene parameter with an "
                  "error: nothing to pick there"]


def _shading(report: dict, source: str) -> tuple[list[Family], list[str]]:
    par = report["sweep"]["parallax"][0]
    size = _size(par["size"])
    metric = ("mean UV offset error in texels of the 256² brick map (the numpy twin), the worst "
              "of the views at " + ", ".join(f"{a:g}°" for a in
                                             sorted({r["angle"] for r in par["rows"]})) + ")")
    fams = []
    for method, mode in (("steep", 2), ("occlusion", 3)):
        by: dict[int, list[dict]] = {}
        for r in par["rows"]:
            if r.get("method") == method and r.get("layers") and _finite(r.get("median_ms"),
                                                                        r.get("mean_px")):
                by.setdefault(int(r["layers"]), []).append(r)
        pts = [Point(f"{n} layers", {"shading.parallax_layers": n},
                     statistics.median(r["median_ms"] for r in rs),
                     max(r["mean_px"] for r in rs), size)
               for n, rs in sorted(by.items())]
        if pts:
            fams.append(Family("shading", "shading", f"parallax layers ({method})", metric, pts,
                               source, {"shading.parallax_mode": mode},
                               f"the wall's shading pass ({size[0]}x{size[1]}, median of the "
                               "views)"))
    return fams, []


def _surfaces(report: dict, source: str) -> tuple[list[Family], list[str]]:
    sweep = report["sweep"]
    fams = []
    sh = sweep.get("shadows") or {}
    groups: dict[tuple[str, int], list[Point]] = {}
    for r in sh.get("rows", []):
        if not str(r.get("bias", "")).startswith("thesis") or not _finite(r.get("ms"),
                                                                          r.get("mismatch")):
            continue
        groups.setdefault((r["filter"], int(r.get("cascades", 0))), []).append(
            Point(f"{int(r['size'])}² map", {"surfaces.shadow_map_size": int(r["size"])},
                  r["ms"], r["mismatch"], (1, 1), fixed_ms=r["ms"]))
    for (filt, cascades), pts in groups.items():
        fams.append(Family(
            "surfaces", "surfaces", f"shadow-map size ({filt} filter, "
            f"{f'{cascades} cascades' if cascades else 'one map'})",
            "share of floor points whose shadow differs from the ray-cast visibility", pts,
            source, {"surfaces.shadow_filter": filt, "surfaces.shadow_cascades": str(cascades),
                     "surfaces.shadow_normal_bias": 0.3, "surfaces.shadow_linear_bias": 0.01},
            "a map render and a receiver pass over the floor grid (not scaled by pixels)"))
    tr = sweep.get("transparency") or {}
    layers = {"peeled_1": 1, "peeled_2": 2, "peeled_reference": 64}
    by: dict[str, list[dict]] = {}
    for r in tr.get("rows", []):
        if r.get("method") in layers and _finite(r.get("ms"), r.get("rms")):
            by.setdefault(r["method"], []).append(r)
    if by and tr.get("size"):
        size = _size(tr["size"])
        pts = [Point(f"{layers[m]} layer{'s' if layers[m] != 1 else ''}",
                     {"surfaces.peel_layers": layers[m]},
                     statistics.fmean(r["ms"] for r in rs), max(r["rms"] for r in rs), size)
               for m, rs in sorted(by.items(), key=lambda kv: layers[kv[0]])]
        fams.append(Family("surfaces", "surfaces", "depth-peeling layers",
                           "RMS error of the linear image against depth peeling with every "
                           "layer, the worst view", pts, source,
                           {"surfaces.transparency": "peeled"},
                           f"the transparent quads ({size[0]}x{size[1]}, mean of the views)"))
    return fams, []


EXTRACT = {"planet": _planet, "clouds": _clouds, "ocean": _ocean, "materials": _materials,
           "shading": _shading, "surfaces": _surfaces}


def _valid(fams: list[Family], scene_name: str) -> tuple[list[Family], list[str]]:
    """Drop the points whose settings this version's parameters refuse (a renamed knob, a
    value out of range), saying so."""
    params = scene_params(scene_name)
    out, notes = [], []
    for fam in fams:
        kept = []
        for p in fam.points:
            try:
                p.sets = {params.resolve(k): params.spec(k).validate(v)
                          for k, v in p.sets.items()}
                kept.append(p)
            except Exception as exc:  # noqa: BLE001 - a ParamError or a KeyError
                notes.append(f"{fam.knob}: {p.label} left out ({str(exc)[:80]})")
        for name in list(fam.requires):
            if name not in params:
                notes.append(f"{fam.knob}: needs {name}, which this version lacks: left out")
                kept = []
        if kept:
            fam.points = kept
            out.append(fam)
    return out, notes


def _layout_problem(exc: BaseException) -> str:
    """What a report's layout got wrong, in words (no exception name or repr)."""
    if isinstance(exc, KeyError) and exc.args:
        return f"an entry has no {quote(str(exc.args[0]), 30)}"
    if isinstance(exc, ValueError):
        m = re.search(r"invalid literal for (\w+)\(\).*?: (.*)$", str(exc))
        if m:
            kind = "an integer" if m.group(1) == "int" else "a number"
            return f"the value {quote(m.group(2).strip(chr(39)), 30)} is not {kind}"
        return "a value is not a number"
    if isinstance(exc, IndexError):
        return "a list is shorter than expected"
    return "an entry is of the wrong type"


def _families(scene_name: str, found: Sweeps) -> tuple[list[Family], list[str]]:
    if found.report is None:
        return [], []
    extract = EXTRACT.get(scene_name)
    if extract is None:
        return [], [f"no extractor for {scene_name}: its sweeps compare methods, which "
                    "natura compare shows side by side"]
    try:
        fams, notes = extract(found.report, found.source)
    except (KeyError, TypeError, ValueError, IndexError, AttributeError) as exc:
        problem = f"its sweeps are not laid out as natura bench {scene_name} writes them " \
                  f"({_layout_problem(exc)})"
        if found.given:
            raise UsageError(f"--sweeps {quote(found.source)}: {problem}: allowed a report of "
                             f"natura bench {scene_name} (JSON, with its sweeps)") from None
        return [], [problem]
    fams, dropped = _valid(fams, scene_name)
    return fams, notes + dropped


def families(scene_name: str, sweeps=None) -> list[Family]:
    """The knob families measured for ``scene_name`` (see the module's docstring for where the
    sweeps come from); [] where there are none."""
    return _families(scene_name, load_sweeps(scene_name, sweeps))[0]


def choose(family: Family, error_budget: float | None = None, ms_budget: float | None = None,
           size: tuple[int, int] | None = None, current: Point | None = None) -> Choice:
    """The pick of one family under absolute budgets (the module's rules); no applicability or
    --set checks here (:func:`pick` does those)."""
    if error_budget is None and ms_budget is None:
        raise ValueError("choose needs an error budget or an ms budget")
    c = Choice(family, None, "", "none", current, error_budget, ms_budget, size)
    pts = family.points
    if not pts:
        c.reason = "no measured point"
        return c
    def cheap(p: Point):
        return (c.ms(p), p.error)

    def accurate(p: Point):
        return (p.error, c.ms(p))

    within = [p for p in pts if error_budget is None or p.error <= error_budget]
    fits = [p for p in pts if ms_budget is None or c.ms(p) <= ms_budget]
    if ms_budget is not None and not fits:
        fast = min(pts, key=cheap)
        c.reason = (f"no measured setting fits {ms_budget:g} ms (the fastest: {fast.label}, "
                    f"{_ms(c.ms(fast))} ms)")
        return c
    if ms_budget is None:
        if not within:
            best = min(pts, key=accurate)
            c.reason = (f"no measured setting has error ≤ {error_budget:.3g} (the most "
                        f"accurate: {best.label}, error {best.error:.3g}, {_ms(c.ms(best))} ms)")
            return c
        c.point, c.status = min(within, key=cheap), "chosen"
        c.reason = "cheapest within the error budget"
    elif error_budget is None:
        c.point, c.status = min(fits, key=accurate), "chosen"
        c.reason = f"most accurate within {ms_budget:g} ms"
    else:
        fitting = {id(p) for p in fits}
        both = [p for p in within if id(p) in fitting]
        if both:
            c.point, c.status = min(both, key=cheap), "chosen"
            c.reason = f"cheapest within the error budget that fits {ms_budget:g} ms"
        else:
            c.point, c.status = min(fits, key=accurate), "over"
            if within:
                need = min(within, key=cheap)
                c.reason = (f"error ≤ {error_budget:.3g} needs {need.label} at "
                            f"{_ms(c.ms(need))} ms > {ms_budget:g} ms: kept the most accurate "
                            f"that fits {ms_budget:g} ms")
            else:
                best = min(pts, key=accurate)
                c.reason = (f"no measured setting has error ≤ {error_budget:.3g} (the most "
                            f"accurate: {best.label}, {best.error:.3g}): kept the most accurate "
                            f"that fits {ms_budget:g} ms")
    if (c.point is not None and current is not None and c.point is not current
            and c.ms(current) > 0 and c.ms(c.point) < c.ms(current)
            and c.ms(current) - c.ms(c.point) < NOISE_SHARE * c.ms(current)):
        c.reason += f"; saves < {NOISE_SHARE:.0%}: within timing noise"
    return c


def pick(scene_name: str, error_budget=None, ms_budget=None, sweeps=None, *, params=None,
         size: tuple[int, int] | None = None, interactive: bool = False,
         explicit: Iterable[str] = ()) -> Picks:
    """Per family of ``scene_name``: the setting the budgets pick (the module's rules).

    ``error_budget``: a number in each family's metric, ``Relative(N)`` or its text ("2x");
    ``ms_budget``: ms at ``size`` (None: as measured); ``params``: the scene's parameters as
    the user set them (default: the scene's defaults) — which families apply, and what is
    current; ``explicit``: the names the user gave with --set (their families are left as
    set); ``interactive``: the window (clouds.reprojection ``window`` is then on)."""
    if error_budget is not None and not isinstance(error_budget, Relative):
        error_budget = parse_error_budget(error_budget)
    if error_budget is None and ms_budget is None:
        raise UsageError("--quality auto needs a budget: allowed --error-budget E and/or "
                         "--ms-budget MS")
    if params is None:
        params = scene_params(scene_name)
    found = load_sweeps(scene_name, sweeps)
    fams, notes = _families(scene_name, found)
    picks = Picks(scene=scene_name, source=found.source, problem=found.problem, notes=notes,
                  error_budget=error_budget, ms_budget=ms_budget, size=size, about=found.about)
    if found.problem is None and not fams:
        picks.problem = (f"the {scene_name} sweeps in {found.source} hold no quality knob with "
                         "a time and an error" + (f" ({notes[0]})" if notes else ""))
        return picks
    mine = set()
    for name in explicit:
        try:
            mine.add(params.resolve(name))
        except Exception:  # noqa: BLE001 - not a ParamSet, or an unknown name
            mine.add(name)
    taken: dict[str, str] = {}
    for fam in fams:
        current = fam.current(params)
        why = fam.applies(params, interactive)
        if why is not None:
            picks.append(Choice(fam, None, why, "skipped", current, size=size))
            continue
        eb = error_budget
        if isinstance(eb, Relative):
            if current is None:
                now = ", ".join(f"{k}={format_value(_get(params, k))}" for k in fam.names)
                picks.append(Choice(fam, None, f"a relative budget needs the current "
                                    f"setting's error, and {now} was not measured: give an "
                                    f"absolute one ({fam.metric})", "skipped", None, size=size))
                continue
            eb = eb.factor * current.error
        c = choose(fam, eb, ms_budget, size, current)
        given = [k for k in fam.names if k in mine]
        if given:
            c = Choice(fam, None, "your --set " + ", ".join(given) + " wins", "yours", current,
                       eb, ms_budget, size, would=c.point)
        elif c.point is not None:
            clash = [k for k in c.point.sets if k in taken]
            if clash:
                c = Choice(fam, None, f"{clash[0]} is already chosen by {taken[clash[0]]}",
                           "skipped", current, eb, ms_budget, size)
            else:
                taken.update({k: fam.knob for k in c.point.sets})
        picks.append(c)
    return picks


def plot_arrays(family: Family, choice: Choice | None = None, params=None,
                size: tuple[int, int] | None = None) -> dict[str, Any]:
    """Plain arrays for the window's ImPlot time-against-error chart: ``ms`` and ``error``
    (float64, in the family's point order), ``labels``, the indices of the ``chosen`` and the
    ``current`` point (-1: none), the budgets (None: not given), ``log_error`` (whether the
    errors span more than 20× and are all positive) and the axis titles. Without a ``choice``
    (no --quality auto), ``params`` marks the current point and ``size`` scales the ms."""
    import numpy as np

    if choice is not None:
        size = choice.size
    elif params is not None:
        choice = Choice(family, None, "", "none", family.current(params), size=size)
    ms = np.array([p.ms_at(size) for p in family.points], dtype=np.float64)
    err = np.array([p.error for p in family.points], dtype=np.float64)
    pts = family.points

    def index(p):
        return next((i for i, q in enumerate(pts) if q is p), -1) if p is not None else -1

    positive = err[err > 0]
    return {
        "ms": ms, "error": err, "labels": [p.label for p in pts],
        "chosen": index(choice.point if choice is not None else None),
        "current": index(choice.current if choice is not None else None),
        "error_budget": choice.error_budget if choice is not None else None,
        "ms_budget": choice.ms_budget if choice is not None else None,
        "log_error": bool(len(positive) == len(err) and len(err) > 1
                          and positive.max() > 20 * positive.min()),
        "x_title": "ms" + (f" at {size[0]}x{size[1]}" if size else "") + f" ({family.timed})",
        "y_title": f"error: {family.metric}",
        "title": (family.title if family.effect == family.scene
                  else f"{family.scene}: {family.title}"),
    }


def chart_png(family: Family, choice: Choice | None, path, force: bool = False) -> None:
    """The family's time against error (matplotlib, Agg) with the chosen point ringed, the
    current one marked and the budget lines drawn; written atomically, never over an existing
    file without ``force``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = check_output_path(path, force=force, suffixes=(".png",))
    a = plot_arrays(family, choice)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    try:
        ax.plot(a["ms"], a["error"], "o-", color="#4477aa", ms=5, lw=1, label="measured")
        for x, y, label in zip(a["ms"], a["error"], a["labels"]):
            ax.annotate(label, (x, y), fontsize=7, textcoords="offset points", xytext=(4, 3))
        if a["current"] >= 0:
            i = a["current"]
            ax.plot([a["ms"][i]], [a["error"][i]], "s", mfc="none", mec="#222222", ms=11,
                    label="current")
        if a["chosen"] >= 0:
            i = a["chosen"]
            ax.plot([a["ms"][i]], [a["error"][i]], "o", mfc="none", mec="#cc3311", mew=2.5,
                    ms=15, label="chosen")
        if a["error_budget"] is not None:
            ax.axhline(a["error_budget"], color="#cc3311", ls="--", lw=1,
                       label=f"error budget {a['error_budget']:.3g}")
        if a["ms_budget"] is not None:
            ax.axvline(a["ms_budget"], color="#228833", ls="--", lw=1,
                       label=f"ms budget {a['ms_budget']:g}")
        if a["log_error"]:
            ax.set_yscale("log")
        ax.set_xlabel(a["x_title"], fontsize=8)
        ax.set_ylabel("error", fontsize=8)
        ax.set_title(a["title"], fontsize=9)
        ax.legend(fontsize=7)
        fig.text(0.01, 0.005, _wrap(a["y_title"], 120), fontsize=6, va="bottom")
        fig.tight_layout(rect=(0, 0.05, 1, 1))
        save_figure(fig, path, force=force)
    finally:
        plt.close(fig)


def _wrap(text: str, width: int) -> str:
    return "\n".join(textwrap.wrap(text, width))
