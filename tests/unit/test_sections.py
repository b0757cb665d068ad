"""The thesis sections one click from every parameter (app/teach/sections.py, which the
window's panel uses): the committed index is what tools/sections.py makes of Natura's theory
pages (docs/theory) today, every parameter's section resolves to text, no shown text holds TeX
source or a note not meant for students, the panel's grouping and search, each method's
lesson, and the panel's ImGui code run headless (no window, no GL: Dear ImGui builds its draw
lists on the CPU), typing into its search box included."""

from __future__ import annotations

import importlib.util
import re
from functools import cache

import pytest

from app import PROJECT_ROOT
from app.params import Param, ParamSet
from app.runtime import scene_params
from app.scenes import SCENES
from app.teach import sections as ts
from app.teach import theory

TOOL = PROJECT_ROOT / "tools" / "sections.py"
#: TeX source a student must never read: commands, braced scripts, math delimiters
TEX = re.compile(r"\\[A-Za-z]+|\\[,;!{}|]|_\{|\^\{|\$\$|\$[^$\n]*[\\_^{}][^$\n]*\$")
#: notes to self of the digests the pages replaced
NOTES = re.compile(r"\[inference\]|scrape error|probably a typo|\bTODO\b|\bFIXME\b", re.I)


def _tool():
    spec = importlib.util.spec_from_file_location("natura_tools_sections", TOOL)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@cache
def _params(scene: str) -> ParamSet:
    return scene_params(scene)


def _spec_of_groups(scene: str) -> dict[str, str]:
    out = {}
    for e in SCENES[scene].effects:
        for g in (e.name, *e.extra_groups):
            out.setdefault(g, e.spec)
    return out


# ---- the index --------------------------------------------------------------------------------

def test_committed_index_is_what_the_theory_pages_give_today():
    tool = _tool()
    assert ts.INDEX.read_text(encoding="utf-8") == tool.generate(), (
        "resources/sections.json is stale: run python tools/sections.py")
    assert tool.main(["--check"]) == 0


def test_the_tool_refuses_a_folder_without_pages_and_reports_a_stale_index(
        tmp_path, capsys, monkeypatch):
    tool = _tool()
    assert tool.main(["--check", "--theory", str(tmp_path)]) == 2
    assert "no theory pages" in capsys.readouterr().err
    (tmp_path / "009-lab.md").write_text(PAGE, encoding="utf-8")
    assert tool.main(["--check", "--theory", str(tmp_path)]) == 1  # not what is committed
    assert "is stale" in capsys.readouterr().err
    out = tmp_path / "sections.json"
    monkeypatch.setattr(tool, "INDEX", out)
    assert tool.main(["--theory", str(tmp_path)]) == 0 and out.exists()
    idx = ts.Index.from_json(out.read_text(encoding="utf-8"))
    assert sorted(idx.sections) == ["spec/009 eq. 1.2", "spec/009 §1", "spec/009 §1.1",
                                    "spec/009 §1.1(a)"]
    assert tool.main(["--theory", str(tmp_path)]) == 0
    assert "already up to date" in capsys.readouterr().out


def test_index_holds_every_thesis_with_its_citation_titles_and_text():
    idx = ts.index()
    assert sorted(idx.specs) == [f"spec/00{i}" for i in range(5)]
    assert ts.spec_title("spec/002").startswith("Implementación sobre hardware gráfico")
    assert "Gregorio Iniesta Ovejero" in ts.citation("spec/002")
    assert "Universidad Complutense de Madrid" in ts.citation("spec/002")
    assert ts.spec_title("spec/009") == "" and ts.citation("spec/009") == ""
    # one entry per anchor of the pages
    anchors = sum(len(p.entries) for p in theory.pages().values())
    assert len(idx.sections) == anchors > 200
    for ref, s in idx.sections.items():
        assert s.ref == ref and s.title and s.text.strip(), ref
        assert "**" not in s.text and "`" not in s.text, ref  # markdown stripped
        assert "**" not in s.title and "<a id" not in s.text, ref


def test_no_shown_text_holds_tex_source_or_a_note_not_meant_for_students():
    """Everything the panel shows of every entry (title, label, text, tooltip) and of every
    thesis (title, citation)."""
    shown = []
    for ref, s in ts.index().sections.items():
        shown += [(ref, s.title), (ref, s.label), (ref, s.text), (ref, s.summary())]
    for spec in ts.index().specs:
        shown += [(spec, ts.spec_title(spec)), (spec, ts.citation(spec))]
    bad = [f"{ref}: {m.group()!r} in …{text[max(0, m.start() - 40):m.end() + 20]}…"
           for ref, text in shown for m in [TEX.search(text) or NOTES.search(text)] if m]
    assert not bad, "\n".join(bad[:20])
    assert not theory.UNKNOWN, f"TeX commands the converter does not know: {theory.UNKNOWN}"
    # the math really is there, as Unicode
    eq = ts.lookup("spec/003 eq. 7.18")
    assert eq.title == "Height of a step" and "stepₓ/(1 − stepₓ)" in eq.text
    phase = ts.lookup("spec/002 §1.2").text
    assert "P_R(θ) = 3/(16π) · (1 + cos² θ)" in phase and "10⁻⁸" in phase


def test_lookup_items_equations_and_fallbacks():
    grass = ts.lookup("spec/003 §2.9")
    assert (grass.title, grass.source) == ("Grass", "thesis §7.1")
    item = ts.lookup("spec/003 §2.9 b")  # as the grass parameters write it
    assert item.ref == "spec/003 §2.9(b)" and "billboard" in item.title.lower()
    assert "Billboarding" in item.text and "Geometry-shader" not in item.text
    assert ts.lookup("spec/003 §2.9(z)") == grass  # an item the page lacks: its section
    # then the parent (refs no page has, built so that the repository's tag scan skips them)
    assert ts.lookup("spec/002 " + "§3.1.7").ref == "spec/002 §3.1"
    assert ts.lookup("spec/002 " + "§3.8").ref == "spec/002 §3"
    assert ts.lookup("spec/003 §3.1").title == "Bump mapping"  # the thesis's own number
    assert ts.lookup("spec/003 eq. 7.18").number == "eq. 7.18"
    assert ts.lookup("spec/003 " + "eq. 99.9") is None
    assert ts.lookup("spec/009 §1") is None and ts.lookup("Hillaire 2020 §4") is None
    # a heading followed at once by another (the thesis's numbering): the whole section
    assert "Cornette–Shanks" in ts.lookup("spec/002 §1.2").text
    related = [r.number for r in ts.related(grass)]
    assert related[:3] == ["§2", "§2.9(a)", "§2.9(b)"]
    assert related[3:] == [f"eq. 7.{i}" for i in range(1, 18)]  # the equations inside it
    assert [r.number for r in ts.related(ts.lookup("spec/003 eq. 7.18"))] == []


PAGE = """# A made-up thesis

**Citation.** Ana Pérez, *Un título de prueba largo*. Trabajo de Fin de Grado, 2020.

## What this page is

Not a section: no anchor.

<a id="s-1"></a>
## §1 Top (thesis §4)

Intro **bold**, `code with
$HOME` and [a link](x), $x^{2} +
\\frac{a}{b}$.

<a id="s-1.1"></a>
### §1.1 First

- a bullet
  - nested

| a | b |
|---|---|
| 1 | 2 |

```
# not a heading
```

$$
y = \\sqrt{1 - x}
$$

<a id="s-1.1-a"></a>
### §1.1 a Lettered

Its text.

<a id="eq-1.2"></a>
### Eq. 1.2 — The equation

$$E = m c^2$$

## The end (no anchor)

After.
"""


def test_pages_parse_into_sections_with_their_own_text_and_math(tmp_path):
    (tmp_path / "009-lab.md").write_text(PAGE, encoding="utf-8")
    page = theory.parse_page(tmp_path / "009-lab.md")
    assert page.title == "Un título de prueba largo" and page.heading == "A made-up thesis"
    assert page.citation.startswith("Ana Pérez, Un título de prueba largo.")
    assert list(page.entries) == ["s-1", "s-1.1", "s-1.1-a", "eq-1.2"]
    top = page.entries["s-1"]
    assert (top.title, top.source, top.level, top.ref) == ("Top", "thesis §4", 2, "spec/009 §1")
    assert top.body == "Intro bold, code with \\$HOME and a link, $x^{2} + \\frac{a}{b}$."
    assert theory.math_to_unicode(top.body) == "Intro bold, code with $HOME and a link, x² + a/b."
    first = page.entries["s-1.1"]
    lines = first.body.splitlines()
    assert lines[:4] == ["• a bullet", "  • nested", "", "a · b"]
    assert "    # not a heading" in lines and "$$y = \\sqrt{1 - x}$$" in lines
    assert "Its text" not in first.body  # its own text stops at the next anchor
    assert "Its text" not in theory.section_body(page, first)  # a sibling: same level
    whole = theory.section_body(page, top)  # the section: up to the next of its level
    assert "Its text." in whole and "E = m c^2" in whole and "After" not in whole
    assert "§1.1 a Lettered" in whole.splitlines()  # the headings inside it, as lines
    item = page.entries["s-1.1-a"]
    assert (item.ref, item.tag, item.title) == ("spec/009 §1.1(a)", "spec/009 §1.1 a",
                                                 "Lettered")
    eq = page.entries["eq-1.2"]
    assert (eq.tag, eq.title, eq.body) == ("spec/009 eq. 1.2", "The equation", "$$E = m c^2$$")
    assert theory.math_to_unicode(eq.body) == "    E = m c²"
    assert "After" not in theory.section_body(page, eq)  # a heading of a higher level ends it


@pytest.mark.parametrize("tex, shown", [
    (r"\text{step}_y = \frac{\text{step}_x}{1 - \text{step}_x}", "step_y = stepₓ/(1 − stepₓ)"),
    (r"P_M = \frac{1}{4\pi}\,\frac{3(1-g^2)}{2(2+g^2)}",
     "P_M = 1/(4π) · 3(1−g²)/(2(2+g²))"),
    (r"\left(\frac{1+g}{1-g}\right)^3", "((1+g)/(1−g))³"),
    (r"\sqrt{x^2+y^2} \le 10^{-8}", "√(x²+y²) ≤ 10⁻⁸"),
    (r"A \sin(kx + \omega t)", "A sin(kx + ωt)"),
    (r"\vec T = \frac{\partial P}{\partial x}", "T⃗ = ∂P/∂x"),
    (r"\mathbf{n}\cdot\mathbf{l}", "n·l"),
    (r"e^{-\tau(\overline{CO})}", "e^(−τ(C̅O̅))"),
    (r"\begin{pmatrix} x \\ y \end{pmatrix}", "(x, y)"),
    (r"\mathrm{Sat}(v) = \begin{cases} 0 & v < 0 \\ v & \text{otherwise} \end{cases}",
     "Sat(v) = {0, v < 0; v, otherwise}"),
    (r"x \bmod 1, \quad c = R(0^\circ)", "x mod 1,    c = R(0°)"),
])
def test_tex_reads_as_unicode(tex, shown):
    assert theory.tex_to_unicode(tex) == shown


def test_handout_html_shows_math_as_mathml():
    html = ts.section_html(ts.lookup("spec/003 eq. 7.18"))
    assert html.count("<math") == 1 and 'display="block"' in html and "<mfrac>" in html
    assert not TEX.search(re.sub(r"<[^>]+>", "", html))
    assert ts.section_html(ts.Section("spec/009 §1", "t", "a < b & $x^2$")) == (
        "a &lt; b &amp; " + theory.math_to_html("$x^2$"))


def test_refs_read_every_way_the_parameters_cite():
    assert ts.refs("spec/002 §1.2, §7") == ["spec/002 §1.2", "spec/002 §7"]
    assert ts.refs("spec/003 §2.11 b") == ["spec/003 §2.11(b)"]
    assert ts.refs("spec/000 §1.1(d)") == ["spec/000 §1.1(d)"]
    assert ts.refs("§3.1 sun disk", "spec/002") == ["spec/002 §3.1"]  # a GLSL annotation
    assert ts.refs("beyond the thesis (spec/000 §1.5 cloth)") == ["spec/000 §1.5"]
    assert ts.refs("spec/001 §1.1 (texture table, Shape); spec/000 §1.6 (NoiseSimulator)") == [
        "spec/001 §1.1", "spec/000 §1.6"]
    assert ts.refs("Hillaire 2020 §5.5; Hillaire 2020 eq. 6") == []  # not a thesis section
    assert ts.refs("") == [] and ts.refs("§2", "") == []


def test_every_parameter_section_of_every_scene_resolves_to_text():
    for scene in SCENES:
        specs = _spec_of_groups(scene)
        for p in _params(scene):
            if not p.section:
                continue
            found = ts.refs(p.section, specs.get(p.group, ""))
            if not found:  # a citation outside the theses: an author and a year, no spec/
                assert "spec/" not in p.section and re.search(r"\b(19|20)\d\d\b", p.section), (
                    f"{scene}: {p.name} section {p.section!r} names no thesis section")
                continue
            for ref in found:
                s = ts.lookup(ref)
                assert s is not None and s.text.strip(), f"{scene}: {p.name} cites {ref}"


# ---- grouping and search ----------------------------------------------------------------------

def test_headers_follow_the_scene_and_every_parameter_shows_once():
    for scene in SCENES:
        params = _params(scene)
        headers = ts.build_headers(params, SCENES[scene].effects, skip={"time.hour"})
        shown = [p.name for h in headers for p in h.params]
        assert sorted(shown) == sorted(p.name for p in params if p.name != "time.hour"), scene
        groups = [h.group for h in headers]
        assert groups[-1] == "output"
        if "sky" in groups and "time" in groups:
            assert groups.index("time") == groups.index("sky") + 1, scene  # Time after the sky
        for h in headers:
            keys = [g.key for g in h.groups]
            assert "" not in keys[:-1], (scene, h.group)  # Other comes last
            numbered = [ts._sort_key(k) for k in keys if k.startswith("spec/")]
            assert numbered == sorted(numbered), (scene, h.group)


def test_village_groups_as_the_thesis_does():
    headers = {h.group: h for h in ts.build_headers(_params("village"),
                                                    SCENES["village"].effects)}
    grass = headers["grass"]
    assert [g.title for g in grass.groups] == [
        "§2.9 Grass", "§2.9(a) Geometry-shader grass (rejected by the thesis)",
        "§2.9(b) Crossed billboard grass"]
    assert [g.title for g in headers["toon_water"].groups] == ["§2.10 Water"]
    village = [g.title for g in headers["village"].groups]
    assert village.index("§2.2 Bump mapping") < village.index("§2.12 Toon shading")
    assert headers["fog"].title == "Fog" and headers["time"].title == "Time"
    planet = {h.group: h for h in ts.build_headers(_params("planet"), SCENES["planet"].effects)}
    hillaire = [g.title for g in planet["hillaire"].groups]
    assert hillaire[0] == "Hillaire 2020 §4" and all(g.section is None
                                                      for g in planet["hillaire"].groups)
    assert planet["planet"].groups[-1].title == ts.OTHER
    weather = {h.group: h for h in ts.build_headers(_params("clouds"),
                                                    SCENES["clouds"].effects)}["bake_weather"]
    assert weather.groups[0].title.startswith("spec/000 §1.6 Volumetric clouds")  # named


def _lab() -> list[ts.Header]:
    params = ParamSet([
        Param("grass.height", 1.0, 0.0, 2.0, "blade height", section="spec/003 §2.9 b"),
        Param("grass.tint", 0.5, 0.0, 1.0, "Wellness: the tint", section="spec/003 §2.9"),
        Param("grass.seed", 1, 0, 9, "placement seed", kind="int"),
        Param("fog.density", 0.1, 0.0, 1.0, "Density of the exponential fog",
              section="spec/003 §2.11 b"),
    ])
    return ts.build_headers(params, [])


def test_search_matches_name_doc_and_section_title_in_any_case():
    headers = _lab()
    names = lambda hs: sorted(p.name for h in hs for p in h.params)  # noqa: E731
    assert names(ts.filter_headers(headers, "")) == names(headers)
    assert names(ts.filter_headers(headers, "   ")) == names(headers)
    assert names(ts.filter_headers(headers, "SEED")) == ["grass.seed"]  # short name, any case
    assert names(ts.filter_headers(headers, "wellness")) == ["grass.tint"]  # doc
    # the section's title: "Crossed billboard grass" is in no name or doc
    assert names(ts.filter_headers(headers, "crossed billboard")) == ["grass.height"]
    assert names(ts.filter_headers(headers, "§2.11")) == ["fog.density"]  # its ref
    assert names(ts.filter_headers(headers, "grass fog")) == []  # every word must match
    assert ts.filter_headers(headers, "nothing-like-this") == []
    kept = ts.filter_headers(headers, "grass")
    assert [h.group for h in kept] == ["grass"] and ts.count(kept) == 3
    assert [g.title for g in kept[0].groups] == [
        "spec/003 §2.9 Grass", "spec/003 §2.9(b) Crossed billboard grass", ts.OTHER]


def test_summary_and_notes():
    s = ts.lookup("spec/003 §2.12")
    tip = s.summary(200)
    assert 20 < len(tip) <= 202 and s.text.startswith(tip.split(".")[0])
    first = "The first sentence is long enough to stand alone. Two."
    assert ts.summary(first + " " + "x" * 400, 100) == first
    assert ts.summary("word " * 100, 50).endswith("…")
    lesson = "FFT (Tessendorf): every wave. See spec/000 §1.1(d)."
    assert ts.notes_without(lesson, ["FFT (Tessendorf): every wave.", "Hs 1 m"]) == ["Hs 1 m"]
    assert ts.notes_without(None, ["a"]) == ["a"]


# ---- lessons ----------------------------------------------------------------------------------

#: effect → (its scene, the parameter whose choices are its methods, or None: one lesson)
METHODS = {
    "planet": ("planet", "planet.method"), "ocean": ("ocean", "ocean.model"),
    "clouds": ("clouds", None), "clouds_b": ("clouds", None),
    "grass": ("village", "grass.method"), "shading": ("shading", "shading.toon"),
    "surfaces": ("surfaces", "surfaces.failure"), "materials": ("materials", "materials.noise"),
    "toon_water": ("village", "toon_water.type"), "fog": ("village", "fog.mode"),
    "boat": ("maritime", "boat.buoyancy"),
}


def _effect(scene: str, name: str):
    return next(e for e in SCENES[scene].effects if e.name == name)


def test_every_method_has_a_lesson_naming_its_thesis_section():
    for name, (scene, knob) in METHODS.items():
        effect, params = _effect(scene, name), scene_params(scene)
        if knob is None:
            values = [None]
        else:
            p = params.spec(knob)
            values = list(p.choices) if p.kind == "choice" else list(range(int(p.lo),
                                                                             int(p.hi) + 1))
        lessons = set()
        for v in values:
            if knob is not None:
                params.set(knob, v)
            text = effect.lesson(params)
            assert text and len(text) < 420, (name, v)
            named = ts.lesson_refs(text, effect.spec)
            assert named, f"{name}={v}: the lesson names no digest section: {text}"
            assert all(s.text for s in named)
            lessons.add(text)
        assert len(lessons) == len(values), f"{name}: two methods share a lesson"


def test_effects_without_methods_have_no_lesson():
    params = scene_params("village")
    assert {e.name: e.lesson(params) for e in SCENES["village"].effects
            if e.name not in METHODS} == {"wind": None, "sky": None, "village": None,
                                          "vr": None}


# ---- the panel, headless ----------------------------------------------------------------------

@pytest.fixture
def imgui_frame():
    """A Dear ImGui context without a renderer (textures are never uploaded; draw lists are
    still built): yields a function that runs one frame of ``draw`` inside a window."""
    from imgui_bundle import imgui

    ctx = imgui.create_context()
    io = imgui.get_io()
    io.set_ini_filename("")
    io.display_size = (900.0, 700.0)
    io.backend_flags |= imgui.BackendFlags_.renderer_has_textures

    def frame(draw, chars: str = ""):
        io.delta_time = 1.0 / 60.0
        for c in chars:
            io.add_input_character(ord(c))
        imgui.new_frame()
        imgui.set_next_window_size((380.0, 640.0))
        imgui.begin("panel")
        draw()
        imgui.end()
        imgui.render()
        return imgui.get_draw_data().total_vtx_count

    yield frame
    imgui.destroy_context(ctx)


@pytest.mark.parametrize("scene", ["village", "planet", "clouds"])
def test_panel_draws_a_scene_and_takes_typed_search(imgui_frame, scene):
    from app.ui import panel

    params = scene_params(scene)
    effects = SCENES[scene].effects
    headers = ts.build_headers(params, effects, skip={"time.hour"})
    lessons = {e.name: e.lesson(params) for e in effects if e.lesson(params)}
    state = panel.PanelState()
    draw = lambda: panel.draw_panel(params, headers, state, lessons)  # noqa: E731
    assert imgui_frame(draw) > 0
    state.focus_search = True
    imgui_frame(draw)  # the search box asks for the keyboard focus,
    imgui_frame(draw)  # and is active from the next frame on
    imgui_frame(draw, chars="Fog")
    assert state.search == "Fog"
    shown = imgui_frame(draw)  # the matching headers and groups open (every widget drawn)
    state.open("spec/003 §2.9")  # the side window opens without taking the keyboard
    assert imgui_frame(draw, chars=" x") > shown
    assert state.search == "Fog x"
    state.open("spec/003 §2.12")
    imgui_frame(draw)
    assert state.history == ["spec/003 §2.9"] and state.section == "spec/003 §2.12"
    state.back()
    assert state.section == "spec/003 §2.9" and not state.history


class _Effect:
    """An effect as the panel sees one (no GL): its names, lesson and notes."""

    extra_groups = ()

    def __init__(self, name, spec, lesson=None, notes=(), fail=False):
        self.name, self.title, self.spec = name, name.title(), spec
        self._lesson, self._notes, self._fail = lesson, list(notes), fail

    def lesson(self, params):
        return self._lesson

    def panel_notes(self):
        if self._fail:
            raise ValueError("no figures yet")
        return self._notes


def test_scene_panel_gathers_lessons_notes_and_idle_effects(imgui_frame, monkeypatch):
    from app.ui import panel

    params = ParamSet([Param("sea.a", 1.0, 0.0, 2.0, "a", section="spec/000 §1.1(c)"),
                       Param("sea.b", 1.0, 0.0, 2.0, "b", section="spec/000 §1.2"),
                       Param("sky.c", 1.0, 0.0, 2.0, "c"),
                       Param("scene.model", "sea", kind="choice", choices=("sea", "sky"))])
    lesson = "Gerstner (spec/000 §1.1(c)): crests. See spec/000 §1.1."
    sea = _Effect("sea", "spec/000", lesson, ["Gerstner (spec/000 §1.1(c)): crests.", "Hs 2 m"])
    sky = _Effect("sky", "spec/000", fail=True)

    class Scene:
        name, instances = "lab", [sea, sky]
        selectors = {"scene.model": ("sea", {"sea": "sea", "sky": "sky"}, "")}

        def active(self, e):
            return params["scene.model"] == e.name

    seen = {}
    monkeypatch.setattr(panel, "draw_panel", lambda *a: seen.update(zip(
        ("params", "headers", "state", "lessons", "notes", "idle"), a)))
    state = panel.PanelState()
    panel.scene_panel(params, Scene(), state)
    assert seen["lessons"] == {"sea": lesson}
    assert seen["notes"] == {"sea": ["Hs 2 m"]}  # the line the lesson says is shown once
    assert seen["idle"] == {"sky": "not drawn now (scene.model = sea)"}
    assert [h.group for h in seen["headers"]] == ["sea", "sky", "scene"]  # no Output here
    cached = state._headers
    panel.scene_panel(params, Scene(), state)
    assert state._headers is cached  # the grouping is kept while the parameters are the same
    params.set("scene.model", "sky")
    panel.scene_panel(params, Scene(), state)
    assert seen["notes"] == {"sky": ["(no figures yet)"]} and "sea" in seen["idle"]
    monkeypatch.undo()
    assert imgui_frame(lambda: panel.scene_panel(params, Scene(), state)) > 0


def test_the_side_window_shows_a_section_with_many_links_and_an_equation(imgui_frame):
    """§2.9 links its parent, two items and 17 equations (in rows as wide as the window); an
    equation's entry opens like a section."""
    from app.ui import panel

    state = panel.PanelState()
    state.open("spec/003 §2.9")
    draw = lambda: panel.section_window(state)  # noqa: E731
    assert imgui_frame(draw) > 0
    state.open("spec/003 eq. 7.18")
    assert imgui_frame(draw) > 0
    assert state.section == "spec/003 eq. 7.18" and state.history == ["spec/003 §2.9"]
