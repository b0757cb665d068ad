"""``natura report SCENE --out DIR``: a handout a teacher can hand out.

What the page shows is in docs/commands.md ("Handouts"); ``DIR/report.json`` holds the same
figures for scripts.

The images are inline (``data:`` URIs), not files beside the page: the page alone is the
handout — it can be mailed, uploaded to a course site or moved without its images breaking,
and it loads offline. Its Content-Security-Policy allows nothing but inline styles and
``data:`` images, so nothing external can creep in unnoticed (a browser refuses it, and says
so on its console). The page has no script.

The renders and timings come from :mod:`app.teach.compare`, the charts from
:mod:`app.teach.quality`, the digests from :mod:`app.teach.sections`, the methods from
:mod:`app.teach.methods`. The folder is written atomically: a new folder is assembled under a
temporary name beside it and renamed into place; an existing empty folder (or, with ``force``,
a non-empty one) gets its two files written atomically, and nothing else in it is touched.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import io
import json
import os
import re
import shlex
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

import numpy as np

from .. import __version__, imageio
from ..errors import UsageError, quote
from ..gpu import context as gl_context
from ..imageio import (
    _LIVE,
    _can_create_in,
    _remove,
    check_new_folder,
    check_output_path,
    expand,
    next_free_path,
    refuse_overwrite,
    signals_deferred,
    temp_name_in,
)
from ..runtime import scene_params
from ..scenes import get_scene
from . import quality, sections
from .compare import compare, encode_png
from .methods import Method, axis_of

PAGE = "index.html"
DATA = "report.json"
DEFAULT_SIZE = (320, 180)
DEFAULT_ROUNDS = 5


@dataclass
class Shot:
    """One method's image and figures."""

    method: Method
    png: np.ndarray                       # (H, W, 3) uint8, as `natura render` writes it
    ms: float
    ms_quartiles: tuple[float, float]
    error: float | None
    command: str                          # the `natura render` line that reproduces `png`
    ratio: float | None = None            # median per-round ms over the first method's
    ratio_quartiles: tuple[float, float] | None = None
    reference: str | None = None          # this image's reference (None: none applies)
    heat: np.ndarray | None = None        # (H, W, 3) uint8 heat map of this − first
    gain: float | None = None


@dataclass
class Chart:
    """A time-against-error chart of one knob family (PNG bytes from quality.chart_png)."""

    effect: str
    knob: str
    metric: str
    source: str
    png: bytes
    points: int
    requires: str = ""                    # the settings it was measured with ("" any)


@dataclass
class ParamRow:
    name: str
    value: str
    default: str
    allowed: str
    unit: str
    doc: str
    section: str
    varies: bool = False                  # the parameter the methods switch


@dataclass
class SectionGroup:
    """The parameters of one thesis section, with its title and digest paragraph."""

    ref: str                              # "spec/002 §2", or a heading for the others
    title: str
    text: str
    thesis: str
    rows: list[ParamRow] = field(default_factory=list)
    html: str = ""                        # the text as HTML, math as MathML ("": escape text)


@dataclass
class Handout:
    scene: str
    scene_title: str
    description: str
    theses: list[tuple[str, str]]         # (spec ref, thesis title)
    renderer: str
    date: str
    size: tuple[int, int]
    rounds: int
    param: str | None                     # the method parameter (None: one method)
    lesson: str
    reference: str | None                 # what the errors are measured against
    shots: list[Shot]
    charts: list[Chart]
    chart_note: str                       # why there are no charts, when there are none
    groups: list[SectionGroup]
    command: str                          # the `natura report` line that made the page


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", text).strip("-") or "default"


def _scene_words(preset: str | None, hour: float | None,
                 camera: str | None, sets: Iterable[str]) -> list[str]:
    """The scene options both commands share, in ``natura render``'s order."""
    words: list[str] = []
    if preset is not None:
        words += ["--preset", preset]
    if hour is not None:
        words += ["--time", f"{hour:g}"]
    if camera is not None:
        words += ["--camera", camera]
    for s in sets:
        words += ["--set", s]
    return words


def _shaders_words(shaders: str | None) -> list[str]:
    return ["--shaders", str(shaders)] if shaders is not None else []


def render_command(scene: str, sets: Iterable[str], size: tuple[int, int], out: str,
                   preset: str | None = None, camera: str | None = None,
                   hour: float | None = None, shaders: str | None = None) -> str:
    """The ``natura render`` line that makes the same image (each word shell-quoted): from the
    scene's defaults, so ``--view none`` where the scene opens on a view of its own."""
    plain = ["--view", "none"] if get_scene(scene).default_view is not None else []
    words = ["natura", "render", scene, *_shaders_words(shaders), *plain,
             *_scene_words(preset, hour, camera, sets),
             "--size", f"{size[0]}x{size[1]}", "--out", out]
    return " ".join(shlex.quote(w) for w in words)


def report_command(scene: str, out: str, size: tuple[int, int], rounds: int,
                   methods: list[Method] | None, base_sets: Iterable[str],
                   preset: str | None, camera: str | None, hour: float | None,
                   shaders: str | None = None) -> str:
    words = ["natura", "report", scene, *_shaders_words(shaders)]
    if methods is not None and axis_of(scene) is not None:
        words += ["--methods", ",".join(m.label for m in methods)]
    words += [*_scene_words(preset, hour, camera, base_sets),
              "--size", f"{size[0]}x{size[1]}", "--rounds", str(rounds), "--out", out]
    return " ".join(shlex.quote(w) for w in words)


def param_groups(params, varies: str | None = None, spec: str = "") -> list[SectionGroup]:
    """Every parameter under the thesis section it comes from, as the window's panel groups
    them (:func:`sections.group_params`: the digests' order, citations outside the theses
    next, those without a section last), with the section's title, thesis and digest."""
    out = []
    for g in sections.group_params(list(params), spec):
        sec, page = g.section, ""
        if sec is not None:
            text, thesis = sec.text, sections.spec_title(sec.spec)
            page = sections.section_html(sec)
        elif not g.key:
            text, thesis = "Parameters without a thesis section.", ""
        elif g.key.startswith("spec/"):
            text, thesis = "", sections.spec_title(g.key.split()[0])
        else:
            text, thesis = f"From a source outside the theses: {g.key}.", ""
        group = SectionGroup(sec.ref if sec is not None else (g.key or sections.OTHER),
                             g.title, text, thesis, html=page)
        for p in g.params:
            group.rows.append(ParamRow(p.name, _show(params[p.name]), _show(p.default),
                                       p.allowed(), p.unit, p.doc, p.section,
                                       varies=p.name == varies))
        out.append(group)
    return out


def _show(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, (tuple, list)):
        return ", ".join(_show(v) for v in value)
    return str(value)


def _say(text: str) -> None:
    print(f"report: {text}", file=sys.stderr, flush=True)


def collect(scene_name: str, methods: list[Method], *, size: tuple[int, int] = DEFAULT_SIZE,
            rounds: int = DEFAULT_ROUNDS, base_sets: Iterable[str] = (),
            preset: str | None = None, camera: str | None = None, hour: float | None = None,
            shader_root=None, out_name: str = "report",
            progress: Callable[[str], None] = _say) -> Handout:
    """Render and time every method against the first (one :func:`compare.compare` per other
    method, sharing one GL context), make the charts, look up the sections."""
    base_sets = list(base_sets)
    cls = get_scene(scene_name)
    axis = axis_of(scene_name)
    ctx = gl_context.create_headless_context()
    try:
        renderer = gl_context.caps_of(ctx).describe()
        first = methods[0]
        others = methods[1:] or [first]  # one method: compared with itself, for its timing
        comparisons = []
        references: dict = {}  # the first method's reference, rendered once for them all
        for i, other in enumerate(others, 1):
            what = (f"{first.label} against {other.label}" if other is not first
                    else first.label)
            progress(f"rendering {scene_name}: {what} at {size[0]}x{size[1]}, {rounds} rounds "
                     f"({i}/{len(others)})")
            comparisons.append(compare(
                scene_name, list(first.sets), list(other.sets), size=size,
                base_sets=base_sets, preset=preset, camera=camera, hour=hour, rounds=rounds,
                shader_root=shader_root, ctx=ctx, progress=lambda t: progress(f"  {t}"),
                reference_cache=references))
    finally:
        ctx.release()

    def command(m: Method) -> str:
        return render_command(scene_name, [*base_sets, *m.sets], size,
                              f"{scene_name}-{_slug(m.label)}.png", preset, camera, hour,
                              shader_root)

    a = comparisons[0].a
    shots = [Shot(first, a.png, a.ms, _pair(a.ms_quartiles), a.error, command(first),
                  reference=a.reference)]
    if len(methods) > 1:
        for m, cmp in zip(methods[1:], comparisons):
            b, r = cmp.b, cmp.ratio
            shots.append(Shot(m, b.png, b.ms, _pair(b.ms_quartiles), b.error, command(m),
                              ratio=r.get("median"),
                              ratio_quartiles=(r["p25"], r["p75"]) if "p25" in r else None,
                              reference=b.reference, heat=cmp.heat, gain=cmp.gain))
    charts, chart_note = _charts(scene_name, progress)
    params = scene_params(scene_name, shader_root, base_sets, preset)
    if hour is not None and "time.hour" in params:
        params.set("time.hour", hour % 24.0)
    if camera is not None:  # as the renders: a camera of the user's may switch a mode
        cls.on_user_camera(params)
    theses = [(s, sections.spec_title(s))
              for s in dict.fromkeys(re.findall(r"spec/\d{3}", cls.description))]
    groups = param_groups(params, axis.param if axis else None)
    return Handout(
        scene=scene_name, scene_title=cls.title, description=cls.description,
        theses=theses, renderer=renderer,
        date=_dt.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z").strip(),
        size=size, rounds=rounds, param=axis.param if axis and len(methods) > 1 else None,
        lesson=axis.lesson if axis and len(methods) > 1 else "",
        reference=comparisons[0].reference, shots=shots, charts=charts, chart_note=chart_note,
        groups=groups,
        command=report_command(scene_name, out_name, size, rounds,
                               methods if axis else None, base_sets, preset, camera, hour,
                               shader_root))


def _pair(q) -> tuple[float, float]:
    return (float(q[0]), float(q[1]))


def _charts(scene_name: str, progress: Callable[[str], None]) -> tuple[list[Chart], str]:
    """The scene's time-against-error charts, one per knob family (made in a scratch folder
    and read back: the page holds them inline), and a sentence on where the sweeps came from
    (or why there are none)."""
    found = quality.load_sweeps(scene_name)
    families = quality.families(scene_name)
    if not families:
        why = found.problem or f"no time-against-error families in {found.source}"
        return [], why[:1].upper() + why[1:] + "."
    progress(f"charting {len(families)} time-against-error famil"
             f"{'y' if len(families) == 1 else 'ies'}")
    charts = []
    with tempfile.TemporaryDirectory(prefix="natura-report-") as scratch:
        for i, fam in enumerate(families):
            path = Path(scratch) / f"chart-{i}.png"
            quality.chart_png(fam, None, path)
            requires = getattr(fam, "requires", {}) or {}
            charts.append(Chart(fam.effect, fam.knob, fam.metric, fam.source,
                                path.read_bytes(), len(fam.points),
                                " ".join(f"{k}={v}" for k, v in requires.items())))
    return charts, f"Measured by {found.source}{found.about}."


def _data_uri(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _e(text: Any) -> str:
    return html.escape(str(text), quote=True)


def _ms(x: float) -> str:
    return f"{x:.3g}" if x < 100 else f"{x:.0f}"


_CSS = """
:root { --ink: #1d2126; --muted: #5b6570; --rule: #d7dce1; --panel: #f4f6f8; --accent: #2459a8; }
* { box-sizing: border-box; }
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; color: var(--ink);
       margin: 0 auto; max-width: 1200px; padding: 1.5rem; }
h1 { margin: 0 0 .2rem; font-size: 1.7rem; }
h2 { margin: 2rem 0 .6rem; font-size: 1.25rem; border-bottom: 1px solid var(--rule); }
h3 { margin: 1.2rem 0 .4rem; font-size: 1.05rem; }
.thesis { margin: 0; font-style: italic; }
.meta, .note, figcaption .sets, footer { color: var(--muted); font-size: .9rem; }
.lesson { background: var(--panel); border-left: 4px solid var(--accent); padding: .5rem .8rem; }
.grid { display: grid; gap: 1rem;
        grid-template-columns: repeat(auto-fill, minmax(var(--col), 1fr)); }
figure { margin: 0; background: var(--panel); border: 1px solid var(--rule); padding: .5rem; }
figure img { display: block; width: 100%; height: auto; background: #000; }
img.small { image-rendering: pixelated; }
figcaption { margin-top: .4rem; }
figcaption b { display: block; }
dl.figures { display: grid; grid-template-columns: auto 1fr; gap: 0 .6rem; margin: .3rem 0; }
dl.figures dt { color: var(--muted); }
dl.figures dd { margin: 0; font-variant-numeric: tabular-nums; }
pre, code { font: .82rem/1.35 ui-monospace, "DejaVu Sans Mono", monospace; }
pre { white-space: pre-wrap; overflow-wrap: anywhere; background: #fff;
      border: 1px solid var(--rule); padding: .3rem .4rem; margin: .3rem 0 0; }
details { border: 1px solid var(--rule); margin: .5rem 0; padding: .3rem .6rem; }
summary { cursor: pointer; font-weight: 600; }
summary .spec { color: var(--muted); font-weight: normal; }
.digest { white-space: pre-wrap; margin: .4rem 0 .6rem; }
table { border-collapse: collapse; width: 100%; font-size: .85rem; }
th, td { text-align: left; vertical-align: top; padding: .2rem .4rem;
         border-top: 1px solid var(--rule); }
td.name, td.value { white-space: nowrap; font-family: ui-monospace, "DejaVu Sans Mono", monospace; }
tr.varies td { background: #fff6d6; }
footer { margin-top: 2.5rem; border-top: 1px solid var(--rule); padding-top: .6rem; }
@media print { body { max-width: none; padding: 0; } details { break-inside: avoid; }
               figure { break-inside: avoid; } }
"""

#: nothing but inline styles and data: images — no script, no fetch, no external font
_CSP = ("default-src 'none'; img-src data:; style-src 'unsafe-inline'; base-uri 'none'; "
        "form-action 'none'")


def _img(png: bytes, size: tuple[int, int], alt: str) -> str:
    w, h = size
    small = ' class="small"' if w < 320 else ""
    return (f'<img src="{_data_uri(png)}" width="{w}" height="{h}" alt="{_e(alt)}"'
            f'{small}>')


def _shot_html(h: Handout, shot: Shot, first: bool) -> str:
    m = shot.method
    p25, p75 = shot.ms_quartiles
    rows = [("time", f"{_ms(shot.ms)} ms median [{_ms(p25)}–{_ms(p75)}]")]
    if shot.ratio is not None:
        spread = (f" [{shot.ratio_quartiles[0]:.2f}–{shot.ratio_quartiles[1]:.2f}]"
                  if shot.ratio_quartiles else "")
        rows.append(("vs first", f"×{shot.ratio:.2f}{spread} per round"))
    elif first and len(h.shots) > 1:
        rows.append(("vs first", "the base of the comparison"))
    if shot.error is not None:
        rows.append(("error", f"{100.0 * shot.error:.3g} % of the reference's luminance"))
    else:
        rows.append(("error", "no reference for this method" if h.reference
                     else "no reference"))
    dl = "".join(f"<dt>{_e(k)}</dt><dd>{_e(v)}</dd>" for k, v in rows)
    sets = " ".join(m.sets) or "the defaults"
    return (f"<figure>{_img(encode_png(shot.png, optimize=True), h.size, m.title)}<figcaption>"
            f"<b>{_e(m.title)}</b><span class=\"sets\">{_e(sets)}</span>"
            f"<dl class=\"figures\">{dl}</dl><pre>{_e(shot.command)}</pre>"
            "</figcaption></figure>")


def _heat_html(h: Handout, shot: Shot) -> str:
    assert shot.heat is not None
    first = h.shots[0].method
    gain = f", magnified ×{shot.gain:.3g}" if shot.gain is not None else ""
    alt = f"{shot.method.label} − {first.label}"
    return (f"<figure>{_img(encode_png(shot.heat, optimize=True), h.size, alt)}<figcaption>"
            f"<b>{_e(shot.method.title)} − {_e(first.title)}</b>"
            f"<span class=\"sets\">signed luminance difference{_e(gain)}</span>"
            "</figcaption></figure>")


def _group_html(g: SectionGroup, open_: bool) -> str:
    thesis = f' <span class="spec">— {_e(g.thesis)}</span>' if g.thesis else ""
    text = (f'<p class="digest">{g.html}</p>' if g.html
            else f'<p class="digest">{_e(g.text)}</p>' if g.text
            else '<p class="note">The theory page has no text for this section.</p>')
    rows = "".join(
        f'<tr{" class=varies" if r.varies else ""}><td class="name">{_e(r.name)}</td>'
        f'<td class="value">{_e("by method" if r.varies else r.value)}'
        f'{(" " + _e(r.unit)) if r.unit and not r.varies else ""}</td>'
        f"<td>{_e(r.allowed)}</td><td>{_e(r.doc)}"
        f'{"" if r.section in ("", g.ref) else f" <i>({_e(r.section)})</i>"}</td></tr>'
        for r in g.rows)
    return (f"<details{' open' if open_ else ''}><summary>{_e(g.title)}{thesis} "
            f'<span class="spec">({len(g.rows)})</span></summary>{text}'
            "<table><thead><tr><th>parameter</th><th>value</th><th>allowed</th>"
            f"<th>what it does</th></tr></thead><tbody>{rows}</tbody></table></details>")


def render_html(h: Handout) -> str:
    """The page, every text HTML-escaped, every image inline."""
    col = max(280, min(h.size[0], 420))
    theses = " · ".join(f"{_e(title)} ({_e(ref)})" for ref, title in h.theses)
    n = len(h.shots)
    if n > 1:
        intro = (f"{n} methods, switched by <code>{_e(h.param)}</code>. Each was timed in "
                 f"{_rounds(h.rounds)} interleaved with the first, so machine load moves both "
                 "sides of a ratio together; the times are medians with their quartiles.")
    else:
        intro = f"This scene has one method: its default image, timed over {_rounds(h.rounds)}."
    ref = (" Error: the mean absolute luminance difference from the reference over the "
           f"reference's mean luminance; the reference is {_e(h.reference)}." if h.reference
           else " This scene has no reference image: no error is given.")
    shots = "".join(_shot_html(h, s, i == 0) for i, s in enumerate(h.shots))
    diffs = ""
    heats = "".join(_heat_html(h, s) for s in h.shots[1:] if s.heat is not None)
    if heats:
        diffs = (f"<h3>Differences against {_e(h.shots[0].method.title)}</h3>"
                 '<p class="note">Red: brighter than the first method, blue: darker; the '
                 f'magnification is in each caption.</p><div class="grid">{heats}</div>')
    if h.charts:
        charts = "".join(
            f"<figure>{_chart_img(c)}<figcaption><b>{_e(c.effect)}: {_e(c.knob)}</b>"
            f'<span class="sets">{_e(c.metric)} · {c.points} points'
            f'{" · with " + _e(c.requires) if c.requires else ""}</span>'
            "</figcaption></figure>" for c in h.charts)
        charts = f'<div class="grid charts">{charts}</div>'
    else:
        charts = f'<p class="note">{_e(h.chart_note)}</p>'
    varies_group = next((g.ref for g in h.groups for r in g.rows if r.varies), None)
    groups = "".join(_group_html(g, g.ref == varies_group) for g in h.groups)
    lesson = f'<p class="lesson">{_e(h.lesson[:1].upper() + h.lesson[1:])}.</p>' if h.lesson else ""
    return f"""<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="{_CSP}">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="natura {_e(__version__)}">
<title>{_e(h.scene_title)} — natura handout</title>
<style>{_CSS}.grid {{ --col: {col}px; }} .grid.charts {{ --col: 420px; }}</style>
</head>
<body>
<header>
<h1>{_e(h.scene_title)}</h1>
<p class="thesis">{theses}</p>
<p class="meta">{_e(h.description)}</p>
<p class="meta">Rendered by natura {_e(__version__)} on {_e(h.renderer)}, {_e(h.date)},
{h.size[0]}×{h.size[1]} pixels.</p>
{lesson}
</header>
<main>
<section id="methods">
<h2>{"Methods side by side" if n > 1 else "The image"}</h2>
<p class="note">{intro}{ref}</p>
<div class="grid">{shots}</div>
{diffs}
</section>
<section id="charts">
<h2>Time against error</h2>
<p class="note">From the scene's speed/accuracy sweeps (<code>natura bench {_e(h.scene)}</code>):
each point a setting of one knob, its time against its error in that sweep's own metric, at the
size the sweep timed (not this page's). {_e(h.chart_note) if h.charts else ""}</p>
{charts}
</section>
<section id="parameters">
<h2>Parameters by thesis section</h2>
<p class="note">Every parameter of the scene with the value used here, grouped under the thesis
section it comes from, with that section's text from Natura's theory pages.
<code>natura params {_e(h.scene)}</code> lists the same.</p>
{groups}
</section>
</main>
<footer>
<p>Made with <code>{_e(h.command)}</code>. Absolute times on a software renderer mean little:
compare methods within one page. Each image is reproduced by the command under it.</p>
</footer>
</body>
</html>
"""


def _rounds(n: int) -> str:
    return f"{n} round" if n == 1 else f"{n} rounds"


def _chart_img(c: Chart) -> str:
    try:
        from PIL import Image

        with Image.open(io.BytesIO(c.png)) as im:
            size = im.size
    except Exception:  # noqa: BLE001 — an unreadable chart still gets its <img>
        size = (640, 400)
    return (f'<img src="{_data_uri(c.png)}" width="{size[0]}" height="{size[1]}" '
            f'alt="{_e(c.effect)}: {_e(c.knob)}">')


def report_data(h: Handout) -> dict:
    """The page's figures for scripts (report.json)."""
    return {
        "scene": h.scene, "size": list(h.size), "rounds": h.rounds, "renderer": h.renderer,
        "date": h.date, "natura": __version__, "param": h.param, "reference": h.reference,
        "command": h.command,
        "methods": [{
            "label": s.method.label, "title": s.method.title, "sets": list(s.method.sets),
            "ms": s.ms, "ms_p25": s.ms_quartiles[0], "ms_p75": s.ms_quartiles[1],
            "ratio_to_first": s.ratio, "ratio_quartiles": s.ratio_quartiles,
            "error": s.error, "reference": s.reference, "gain": s.gain,
            "command": s.command} for s in h.shots],
        "charts": [{"effect": c.effect, "knob": c.knob, "metric": c.metric,
                    "source": c.source, "points": c.points, "requires": c.requires}
                   for c in h.charts],
        "charts_note": h.chart_note,
        "sections": [{"ref": g.ref, "title": g.title, "parameters": [r.name for r in g.rows]}
                     for g in h.groups],
    }


def default_out(scene_name: str) -> Path:
    """``SCENE-report-NNNN`` here, the first number not taken."""
    return next_free_path(Path("."), f"{scene_name}-report", "")


def check_out_dir(out: str | os.PathLike, force: bool = False) -> Path:
    """Validate ``--out DIR`` before any work: a new folder in an existing writable one, an
    empty folder, or (with ``force``) a folder whose index.html and report.json may be
    replaced (nothing else in it is touched)."""
    path = expand(out, "--out")
    shown = quote(str(path))
    allowed = "allowed a new or empty folder, or an existing one with --force"
    if os.path.lexists(path):
        if not path.is_dir():
            raise UsageError(f"--out {shown} exists and is not a folder: {allowed}")
        try:
            entries = os.listdir(path)
        except OSError as exc:
            raise UsageError(f"--out {shown} cannot be read ({exc.strerror}): {allowed}"
                             ) from None
        if entries and not force:
            raise UsageError(f"--out {shown} is not empty: {allowed} (it replaces {PAGE} "
                             f"and {DATA} only)")
        if not _can_create_in(path):
            raise UsageError(f"--out {shown} is not writable: {allowed}")
        for name, suffix in ((PAGE, ".html"), (DATA, ".json")):
            check_output_path(path / name, force=True, suffixes=(suffix,), probe_folder=False)
        return path
    check_new_folder(path, shown, allowed, "--out ")
    return path


def write_handout(h: Handout, out: Path, force: bool = False) -> Path:
    """Write index.html and report.json: into a new folder under a temporary name renamed at
    the end (an error or Ctrl-C leaves nothing), or atomically file by file into an existing
    one. Returns the page's path."""
    files = {PAGE: render_html(h), DATA: json.dumps(report_data(h), indent=2) + "\n"}
    if out.is_dir():
        for name, text in files.items():
            imageio.write_text_atomic(out / name, text, force=force)
        return out / PAGE
    parent = out.parent
    tmp = temp_name_in(parent)
    with signals_deferred():
        tmp.mkdir()  # the umask's permissions, as a plain mkdir
        _LIVE.add(tmp)
    try:
        for name, text in files.items():
            imageio.write_text_atomic(tmp / name, text)
        try:
            os.rename(tmp, out)  # onto nothing, or onto a folder made empty meanwhile
        except OSError as exc:
            if os.path.lexists(out):
                raise refuse_overwrite(out) from None
            raise UsageError(f"cannot create {quote(str(out))} ({exc.strerror}): allowed a "
                             "writable folder with free space; nothing was left behind"
                             ) from None
        _LIVE.discard(tmp)
    finally:
        if tmp in _LIVE:
            _remove(tmp)
    return out / PAGE
