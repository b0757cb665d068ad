"""ImGui widgets built from parameters: the scene's panel a student can navigate.

:func:`scene_panel` is the window's parameter panel, one a student can navigate: a search box on
top; one collapsing header per parameter group (an effect, its extra groups, Time, Output);
under an effect's header first the lesson of its current method (``Effect.lesson``) and its
live notes, then its parameters grouped by the thesis section they come from, in the
theory pages' order, each group with a "§" button that opens the section's text in a side
window (hovering it shows the title and the first sentences). The grouping and the search
are the pure functions of :mod:`app.teach.sections`, tested without a window.

Every widget writes through :meth:`ParamSet.set`, so the panel can never store a value the
CLI would reject. Hovering a widget shows its doc, unit, range and thesis section; its context
menu (right click) resets it or opens its section.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np
from imgui_bundle import imgui

from ..colour import linear_to_srgb, srgb_to_linear
from ..errors import ParamError, one_line
from ..params import Param, ParamSet
from ..scenes.base import AUTO_SCALE, MIN_SCALE, ScaleParam
from ..teach import sections as ts

ERROR_COLOUR = (1.0, 0.35, 0.3, 1.0)
LESSON_COLOUR = (0.55, 0.8, 1.0, 1.0)
#: the width of tooltips, in font heights (they wrap there)
TOOLTIP_EMS = 32.0
SEARCH_HINT = "search: name, doc or thesis section"


def next_event_id() -> int:
    """The number ImGui gives the next input event: every event queued so far is below it."""
    return int(imgui.get_current_context().input_events_next_event_id)


def queued_before(event_id: int) -> bool:
    """Whether ImGui still queues input events numbered below ``event_id``: keys pressed before
    it that a slow frame has not handed out yet (ImGui trickles them over the next frames). A
    focus change waits for them, so each key goes to the widget that had the keyboard when it
    was pressed."""
    return any(e.event_id < event_id for e in imgui.get_current_context().input_events_queue)


@dataclass
class PanelState:
    """What the panel keeps between frames (the window holds one): the search text, the thesis
    section shown in the side window (a ref, ``"spec/003 §2.9"``) and the ones before it."""

    search: str = ""
    section: str | None = None
    history: list[str] = field(default_factory=list)
    #: set to focus the search box on the next frame (a key binding may set it); with
    #: ``focus_after`` (an ImGui event number, Ctrl+F's) only once the keys pressed before it
    #: have gone where they were typed: the window sets ``focus_ready`` before a frame whose
    #: input holds none of them (:func:`queued_before`)
    focus_search: bool = False
    focus_after: int | None = None
    focus_ready: bool = False
    #: characters typed while the search box takes the keyboard (ImGui activates it a frame
    #: after the request and drops that frame's characters): held, then typed into it
    _carry: list = field(default_factory=list, repr=False, compare=False)
    _carry_frames: int = field(default=0, repr=False, compare=False)
    _search_active: bool = field(default=False, repr=False, compare=False)
    #: (key, headers): the grouping, rebuilt only when the parameters change
    _headers: tuple = field(default=(), repr=False, compare=False)

    def open(self, ref: str) -> None:
        """Show section ``ref`` in the side window (the one shown before goes to history)."""
        if self.section and self.section != ref:
            self.history.append(self.section)
            del self.history[:-20]
        self.section = ref

    def back(self) -> None:
        self.section = self.history.pop() if self.history else None

    def close(self) -> None:
        self.section = None
        self.history.clear()


def _wrapped_tooltip(lines: Sequence[str]) -> None:
    """A tooltip whose lines wrap at :data:`TOOLTIP_EMS` font heights."""
    if imgui.begin_tooltip():
        imgui.push_text_wrap_pos(imgui.get_font_size() * TOOLTIP_EMS)
        for line in lines:
            imgui.text_unformatted(line)
        imgui.pop_text_wrap_pos()
        imgui.end_tooltip()


def section_tooltip(section: ts.Section) -> None:
    """The section's ref and title, and its first sentences."""
    head = f"{section.ref} — {section.title}"
    thesis = ts.spec_title(section.spec)
    lines = [head] + ([f"({thesis})"] if thesis else []) + ["", section.summary(),
                                                             "", "click: the whole section"]
    _wrapped_tooltip(lines)


def _tooltip(p: Param, section: ts.Section | None = None) -> None:
    if imgui.is_item_hovered(imgui.HoveredFlags_.for_tooltip):
        unit = f" {p.unit}" if p.unit else ""
        lines = [p.name, p.doc, f"allowed: {p.allowed()}{unit}"]
        lines += [f"and: {j.text}" for j in p.joint]
        lines.append(f"default: {p.default}")
        if p.section:
            lines.append(f"thesis: {p.section}")
        if section is not None:
            lines += ["", f"{section.label}: {section.summary(180)}"]
        if p.source != "python":
            lines.append(f"declared in {p.source}")
        _wrapped_tooltip(lines)


#: parameter name → why its last change was refused (a rule it shares with others), shown under
#: its widget until a change of it is accepted
REFUSED: dict[str, str] = {}


def param_widget(params: ParamSet, p: Param, section: ts.Section | None = None,
                 state: PanelState | None = None) -> bool:
    """Draw one widget; returns True when the value changed. With ``section`` its tooltip
    quotes the thesis section, and with ``state`` its context menu opens it."""
    value = params[p.name]
    label = f"{p.short}##{p.name}"
    changed = False
    new = value
    if isinstance(p, ScaleParam):  # output.scale: "auto", or a slider over the pinned scales
        changed, auto = imgui.checkbox(f"auto##{p.name}", value == AUTO_SCALE)
        new = AUTO_SCALE if auto else (1.0 if changed else value)
        if not auto:
            imgui.same_line()
            moved, pinned = imgui.slider_float(label, float(new), MIN_SCALE, 1.0, "%.3g")
            if moved:
                changed, new = True, pinned
    elif p.kind == "bool":
        changed, new = imgui.checkbox(label, value)
    elif p.kind == "choice":
        idx = p.choices.index(value)
        changed, idx = imgui.combo(label, idx, list(p.choices))
        new = p.choices[idx]
    elif p.kind == "int":
        lo, hi = int(p.lo), int(p.hi)
        if hi - lo <= 4096:
            changed, new = imgui.slider_int(label, int(value), lo, hi)
        else:
            changed, new = imgui.drag_int(label, int(value), 1.0, lo, hi)
    elif p.kind == "float":
        fmt = "%.4g" + (f" {p.unit}" if p.unit else "").replace("%", "%%")
        changed, new = imgui.slider_float(label, float(value), float(p.lo), float(p.hi), fmt)
    elif p.kind == "color":
        # pickers show display (sRGB) values; linear parameters are converted both ways
        shown = [float(v) for v in (value if p.srgb else linear_to_srgb(np.asarray(value)))]
        changed, shown = imgui.color_edit3(label, shown)
        shown = np.clip(np.asarray(shown, dtype=np.float64), p.lo, p.hi)
        new = tuple(float(v) for v in (shown if p.srgb else srgb_to_linear(shown)))
    elif p.kind in ("vec3", "vec4"):
        drag = imgui.drag_float3 if p.kind == "vec3" else imgui.drag_float4
        changed, new = drag(label, list(value), float(p.step), float(p.lo), float(p.hi))
    _tooltip(p, section)
    if imgui.begin_popup_context_item(f"ctx##{p.name}"):
        if imgui.menu_item_simple("reset to default"):
            new, changed = p.default, True
        if section is not None and state is not None and imgui.menu_item_simple(
                f"thesis: {section.ref} {section.title}"):
            state.open(section.ref)
        imgui.end_popup()
    if p.joint:  # its rules with other parameters, beside its range
        _wrapped_in(imgui.get_style_color_vec4(imgui.Col_.text_disabled),
                    f"and: {p.joint_text()}")
    if changed:
        try:
            params.try_set(p.name, new)
        except ParamError as exc:  # it would break a rule it shares: say so, keep the value
            REFUSED[p.name] = str(exc)
            changed = False
        except Exception:  # a half-typed or out-of-range value: keep the last valid one
            return False
        else:
            REFUSED.pop(p.name, None)
    if p.name in REFUSED:
        _wrapped_in(imgui.ImVec4(1.0, 0.45, 0.35, 1.0), f"kept: {REFUSED[p.name]}")
    return changed


def _wrapped_in(colour, text: str) -> None:
    """A line of wrapped text in ``colour`` (under a widget: its rules, a refusal)."""
    imgui.push_style_color(imgui.Col_.text, colour)
    imgui.text_wrapped(text)
    imgui.pop_style_color()


def scene_panel(params: ParamSet, scene, state: PanelState,
                skip: set[str] | frozenset[str] = frozenset({"time.hour"})) -> None:
    """The window's parameter panel for ``scene`` (its effect instances give the lessons and
    the notes; an effect a selector has switched off says so); ``state`` is kept by the
    window between frames. Draws inside the current ImGui window, plus the thesis section's
    side window when one is open."""
    key = (getattr(scene, "name", ""), id(params),
           tuple((p.name, p.section, p.doc) for p in params))
    if not state._headers or state._headers[0] != key:
        state._headers = (key, ts.build_headers(params, scene.instances, skip))
    headers = state._headers[1]
    lessons: dict[str, str] = {}
    notes: dict[str, list[str]] = {}
    idle: dict[str, str] = {}
    for e in scene.instances:
        if not scene.active(e):
            idle[e.name] = _idle_reason(scene, e, params)
            continue
        try:
            lesson = e.lesson(params)
        except Exception as exc:  # a lesson that cannot be read must not close the panel
            lesson = f"({one_line(exc)})"
        if lesson:
            lessons[e.name] = lesson
        try:
            notes[e.name] = ts.notes_without(lesson, e.panel_notes())
        except Exception as exc:  # a figure that cannot be computed must not close the panel
            notes[e.name] = [f"({one_line(exc)})"]
        readers = slot_readers(scene, e)
        if readers:
            notes[e.name] = [*notes[e.name], readers]
    draw_panel(params, headers, state, lessons, notes, idle, main_group(scene, headers, idle))


def slot_readers(scene, effect) -> str | None:
    """What of ``effect``'s frame slots the scene's other drawn effects read, and who: effects
    meet through slots and never name each other, so the scene says who follows whom
    ("wind read here by Grass, Fog"). None when no other effect reads them."""
    produced = set(getattr(effect, "produces", ()))
    slots: set[str] = set()
    titles: list[str] = []
    for other in getattr(scene, "instances", ()):
        if other is effect or not scene.active(other):
            continue
        read = produced & set(getattr(other, "consumes", {}))
        if read:
            slots |= read
            titles.append(other.title or other.name)
    if not titles:
        return None
    return f"{', '.join(sorted(slots))} read here by {', '.join(titles)}"


def main_group(scene, headers: Sequence[ts.Header], idle: Mapping[str, str]) -> str | None:
    """The header the panel opens on: the scene's own (the group named as the scene — the
    ocean's ocean, maritime's own parameters), else its first effect's; one whose effect is not
    drawn now gives way to the first effect that is. None: no such header (all open)."""
    groups = [h.group for h in headers]
    name = getattr(scene, "name", "")
    if name in groups and name not in idle:
        return name
    drawn = [h.group for h in headers if h.effect and h.group == h.effect and h.effect not in idle]
    return drawn[0] if drawn else None


def _idle_reason(scene, effect, params: ParamSet) -> str:
    for name, (_, choices, _) in getattr(scene, "selectors", {}).items():
        if effect.name in choices.values() and name in params:
            return f"not drawn now ({name} = {params[name]})"
    return "not drawn now"


def draw_panel(params: ParamSet, headers: Sequence[ts.Header], state: PanelState,
               lessons: Mapping[str, str] | None = None,
               notes: Mapping[str, Sequence[str]] | None = None,
               idle: Mapping[str, str] | None = None, main: str | None = None) -> None:
    """The search box, then the headers that match it (:func:`scene_panel` gathers the
    lessons, notes and idle effects by parameter group; tests call this directly). The panel
    opens on ``main``'s header, drawn first (and its Time), the others closed; without
    ``main`` every effect's own header, Time and Output open, in the scene's order."""
    lessons, notes, idle = lessons or {}, notes or {}, idle or {}
    search_box(state)
    shown = ts.filter_headers(headers, state.search)
    if main is not None:  # the main section first, the others in the scene's order
        shown = sorted(shown, key=lambda h: h.group != main)
    searching = bool(state.search.split())
    if searching:
        n, total = ts.count(shown), ts.count(headers)
        imgui.text_disabled(f"{n} of {total} parameters match" if n else
                            "nothing matches: try a shorter word")
    for h in shown:
        if searching:
            imgui.set_next_item_open(True, imgui.Cond_.appearing)
            label = f"{h.title}##{h.group}/search"
            flags = 0
        else:
            label = f"{h.title}##{h.group}"
            if main is None:
                own = h.group == h.effect or h.group in ("time", "output")
            else:
                own = h.group == main or (h.group == "time" and h.effect == main)
            flags = imgui.TreeNodeFlags_.default_open if own else 0
        if imgui.collapsing_header(label, flags):
            imgui.push_id(h.group)
            header_body(params, h, state, lessons.get(h.group), notes.get(h.group, ()),
                        idle.get(h.group), searching)
            imgui.pop_id()
    section_window(state, headers)


def search_box(state: PanelState) -> None:
    """The search box over the whole width, with a button that clears it."""
    queue = imgui.get_io().input_queue_characters
    if state.focus_search and (state.focus_after is None or state.focus_ready):
        imgui.set_keyboard_focus_here()
        state.focus_search, state.focus_after, state.focus_ready = False, None, False
        state._carry_frames = 4
    if state._carry_frames > 0 and not state._search_active:  # not taking characters yet
        state._carry += list(queue)
        queue.clear()
        state._carry_frames -= 1
    elif state._carry:  # active since the last frame: what was typed meanwhile, in order
        for char in reversed(state._carry):
            queue.push_front(char)
        state._carry, state._carry_frames = [], 0
    clear = imgui.calc_text_size("clear").x + imgui.get_style().frame_padding.x * 4
    imgui.set_next_item_width(-clear if state.search else -1.0)
    _, state.search = imgui.input_text_with_hint("##natura-search", SEARCH_HINT, state.search)
    state._search_active = imgui.is_item_active()
    if state.search:
        imgui.same_line()
        if imgui.small_button("clear##natura-search"):
            state.search = ""


def section_button(section: ts.Section, state: PanelState, id_: str) -> None:
    """A small "§" button that opens ``section``; hovering it quotes the section."""
    if imgui.small_button(f"§##{id_}"):
        state.open(section.ref)
    if imgui.is_item_hovered(imgui.HoveredFlags_.for_tooltip):
        section_tooltip(section)


def header_body(params: ParamSet, h: ts.Header, state: PanelState, lesson: str | None,
                notes: Sequence[str], idle: str | None, searching: bool = False) -> None:
    """Under an effect's header: whether it is drawn, its lesson (with the § of the section
    it names), its notes, then its parameters by thesis section."""
    if idle:
        imgui.text_disabled(idle)
    if lesson:  # the § first: a button after wrapped text lands at the window's edge
        named = ts.lesson_refs(lesson, h.spec)
        if named:
            section_button(named[0], state, f"lesson-{h.group}")
            imgui.same_line()
        imgui.push_text_wrap_pos(0.0)
        imgui.text_colored(LESSON_COLOUR, lesson)
        imgui.pop_text_wrap_pos()
    for line in notes:
        imgui.text_wrapped(line)
    if len(h.groups) == 1:  # one section: its line, then the widgets (no click to open)
        g = h.groups[0]
        if g.key:
            _group_line(g, state, h.group)
        for p in g.params:
            param_widget(params, p, g.section, state)
        return
    pad = imgui.calc_text_size("§").x + imgui.get_style().frame_padding.x * 2.0
    for g in h.groups:
        if searching:
            imgui.set_next_item_open(True, imgui.Cond_.appearing)
        if g.section is not None:  # the § before the title, which may run past the edge
            section_button(g.section, state, f"{h.group}/{g.key}")
            imgui.same_line()
        else:  # the titles stay in one column
            imgui.dummy((pad, 1.0))
            imgui.same_line()
        node = f"{g.title} ({len(g.params)})##{g.key or 'other'}" + ("/search" if searching
                                                                       else "")
        opened = imgui.tree_node_ex(node, 0)
        _group_hover(g)
        if opened:
            for p in g.params:
                param_widget(params, p, g.section, state)
            imgui.tree_pop()


def _group_hover(g: ts.Group) -> None:
    if not imgui.is_item_hovered(imgui.HoveredFlags_.for_tooltip):
        return
    if g.section is not None:
        section_tooltip(g.section)
    elif g.key:
        _wrapped_tooltip([g.key, "a source beyond the five theses"])
    else:
        _wrapped_tooltip(["parameters of this implementation that no thesis section names"])


def _group_line(g: ts.Group, state: PanelState, group: str) -> None:
    if g.section is not None:
        section_button(g.section, state, f"{group}/{g.key}")
        imgui.same_line()
    imgui.text_disabled(g.title)
    _group_hover(g)


def section_window(state: PanelState, headers: Sequence[ts.Header] = ()) -> None:
    """The open thesis section in a window of its own beside the panel: the thesis, the
    section's title and the thesis's own number for it, its text (wrapped), the lettered items
    and subsections it has, and the scene's parameters that cite it."""
    if not state.section:
        return
    s = ts.lookup(state.section)
    pos, size = imgui.get_window_pos(), imgui.get_window_size()
    imgui.set_next_window_pos((pos.x + size.x + 8.0, pos.y), imgui.Cond_.appearing)
    imgui.set_next_window_size((440.0, 520.0), imgui.Cond_.first_use_ever)
    title = f"Thesis: {s.ref if s else state.section}###natura-thesis-section"
    expanded, keep = imgui.begin(title, True, imgui.WindowFlags_.no_focus_on_appearing)
    if expanded:
        if state.history:
            if imgui.small_button("< back"):
                state.back()
            imgui.same_line()
        if s is None:
            imgui.text_wrapped(f"{state.section}: not in resources/sections.json")
        else:
            section_text(s, state, headers)
    imgui.end()
    if not keep:
        state.close()


def section_text(s: ts.Section, state: PanelState, headers: Sequence[ts.Header] = ()) -> None:
    thesis = ts.spec_title(s.spec)
    imgui.text_disabled(f"{s.spec}: {thesis}" if thesis else s.spec)
    imgui.push_text_wrap_pos(0.0)
    imgui.text_colored(LESSON_COLOUR, f"{s.number} {s.title}")
    if s.source:
        imgui.text_disabled(f"({s.source})")
    imgui.pop_text_wrap_pos()
    related = ts.related(s)
    if related:
        width, used = imgui.get_content_region_avail().x, 0.0
        pad, gap = imgui.get_style().frame_padding.x * 2.0, imgui.get_style().item_spacing.x
        for i, r in enumerate(related):  # in rows as wide as the window (§2.9 has 20)
            w = imgui.calc_text_size(r.number).x + pad
            if i and used + gap + w <= width:
                imgui.same_line()
                used += gap + w
            else:
                used = w
            if imgui.small_button(f"{r.number}##rel-{r.ref}"):
                state.open(r.ref)
            if imgui.is_item_hovered(imgui.HoveredFlags_.for_tooltip):
                section_tooltip(r)
    cited = [p.name for h in headers for g in h.groups if g.section is not None
             and g.section.ref == s.ref for p in g.params]
    if cited:
        imgui.push_text_wrap_pos(0.0)
        imgui.text_disabled("parameters here: " + ", ".join(cited))
        imgui.pop_text_wrap_pos()
    imgui.separator()
    imgui.text_wrapped(s.text)


def keyframes_panel(keyframes) -> bool:
    """Colour stops and star factor of each sky keyframe; returns True when edited."""
    edited = False
    for k in keyframes.frames:
        if imgui.tree_node(f"{int(k.hour):02d}:00##kf{k.hour}"):
            for i, (pos, col) in enumerate(k.gradient):
                shown = [float(v) for v in linear_to_srgb(col)]
                ch, shown = imgui.color_edit3(f"elev {pos:.2f}##kf{k.hour}-{i}", shown)
                if ch:
                    k.gradient[i] = (pos, srgb_to_linear(np.clip(np.asarray(shown), 0.0, 1.0)))
                    edited = True
            ch, stars = imgui.slider_float(f"stars##kf{k.hour}", k.stars, 0.0, 1.0)
            if ch:
                k.stars = float(stars)
                edited = True
            imgui.tree_pop()
    if edited:
        keyframes.version += 1
    return edited


def error_list(errors) -> None:
    """Errors in red, each whole: wrapped at the panel's edge, never cut off."""
    imgui.push_text_wrap_pos(0.0)  # 0: wrap at the window's right edge
    try:
        for e in errors:
            imgui.text_colored(ERROR_COLOUR, str(e))
    finally:
        imgui.pop_text_wrap_pos()


def messages(lines) -> None:
    """The window's recent messages (saved files, reloads, what could not be saved), wrapped."""
    imgui.push_text_wrap_pos(0.0)
    try:
        for m in lines:
            imgui.text_disabled(m)
    finally:
        imgui.pop_text_wrap_pos()


def inspector_panel(params: ParamSet, inspector, register=None) -> None:
    """A material inspector (app.params.Inspector): a button per popup (its parameters' widgets
    inside) and the generated maps as thumbnails (``register(texture)`` makes a texture
    drawable by the window's renderer first)."""
    params = inspector.params if inspector.params is not None else params
    for i, (title, names) in enumerate(inspector.popups.items()):
        if i:
            imgui.same_line()
        popup = f"{title}##inspector-{inspector.title}"
        if imgui.button(f"{title}…##btn-{inspector.title}"):
            imgui.open_popup(popup)
        if imgui.begin_popup(popup):
            imgui.text(title)
            for name in names:
                if name in params:
                    param_widget(params, params.spec(name))
            imgui.end_popup()
    for label, tex in inspector.textures.items():
        if register is not None:
            register(tex)
        imgui.begin_group()
        imgui.image(imgui.ImTextureRef(tex.glo), (64.0, 64.0 if tex.height > 1 else 12.0))
        imgui.text_disabled(label)
        imgui.end_group()
        imgui.same_line()
    imgui.new_line()
