"""The maritime thesis's HUD (spec/000 §2), drawn with ImGui for a scene that has a ``hud()``
method (the window duck-types on it and names no scene): the ship panel (fig. 4.1), the weather
and time panel (fig. 4.2) and the pause menu, as docs/commands.md ("Window controls",
maritime) describes them. The wind dial's true-wind arrow is the scene's ``wind_relative``
(wind direction − heading, criterion 36).

The figures come from the scene's ``HudState`` (plain numbers); the geometry of the dial is
:func:`dial_point` / :func:`dial_arrow`, tested without a window.
"""

from __future__ import annotations

import math

from imgui_bundle import imgui

from ..params import ParamSet
from ..sim.daynight import hour_label

#: the parameters the HUD's widgets write (a widget whose parameter the scene lacks is left out)
HELM, SAILS, THROTTLE = "boat.helm", "boat.sails", "boat.throttle"
HOUR, PLAYING = "time.hour", "time.playing"
WEATHER = "maritime.weather"
WIND_SPEED, WIND_DIRECTION = "wind.speed", "wind.direction"

MARGIN = 10.0
WIDTH = 290.0
LABEL_WIDTH = 74.0  # room right of the sliders for their labels
DIAL_RADIUS = 46.0
#: a window smaller than this (either side) gets the compact HUD: narrower, a smaller dial, the
#: weather and time panel folded (its title bar unfolds it), so the view stays mostly visible
COMPACT_BELOW = (1280, 720)
COMPACT_WIDTH = 220.0
COMPACT_DIAL_RADIUS = 28.0
KNOTS_PER_MS = 3600.0 / 1852.0

SHIP_WINDOW = "Ship###natura-hud-ship"
WEATHER_WINDOW = "Weather and time###natura-hud-weather"
PAUSE_WINDOW = "Paused###natura-pause"

_RING = (0.85, 0.88, 0.92, 0.9)
_BOAT = (0.95, 0.95, 0.95, 1.0)
_TRUE_WIND = (0.35, 0.75, 1.0, 1.0)
_APPARENT_WIND = (1.0, 0.75, 0.3, 1.0)


def dial_point(centre: tuple[float, float], radius: float,
               angle: float) -> tuple[float, float]:
    """The point ``radius`` from ``centre`` at ``angle`` degrees clockwise from up (the bow), in
    screen coordinates (y grows downward)."""
    a = math.radians(angle)
    return centre[0] + radius * math.sin(a), centre[1] - radius * math.cos(a)


def dial_arrow(centre: tuple[float, float], radius: float,
               toward: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """(tail, head) of a wind arrow across the dial: it comes in from the rim on the windward
    side and points at ``toward`` degrees off the bow (clockwise), where the wind blows."""
    return dial_point(centre, radius, toward + 180.0), dial_point(centre, radius, toward)


def _side(angle: float) -> str:
    """Port or starboard for an angle off the bow in (−180, 180]."""
    if abs(angle) < 0.5 or abs(abs(angle) - 180.0) < 0.5:
        return ""
    return " starboard" if angle > 0 else " port"


def mode_line(ui_mode: bool, paused: bool = False) -> str:
    """The HUD's first line: which mode is on, and how to switch."""
    if paused:
        return "Paused — Resume, or Esc again: quit"
    return ("UI mode: click the panels — Space: free navigation" if ui_mode else
            "Free navigation (mouse look) — Space: UI mode")


def _u32(colour) -> int:
    return imgui.get_color_u32(imgui.ImVec4(*colour))


def _slider(params: ParamSet, name: str, label: str, fmt: str = "%.2f") -> None:
    if name not in params:
        return
    spec = params.spec(name)
    lo = -1.0 if spec.lo is None else float(spec.lo)
    hi = 1.0 if spec.hi is None else float(spec.hi)
    changed, value = imgui.slider_float(label, float(params[name]), lo, hi, fmt)
    if changed:
        params.set(name, value)
    if imgui.is_item_hovered() and spec.doc:
        imgui.set_tooltip(f"{name}: {spec.doc}")


def compact(size: tuple[int, int]) -> bool:
    """Whether a window of ``size`` pixels gets the compact HUD."""
    return size[0] < COMPACT_BELOW[0] or size[1] < COMPACT_BELOW[1]


def _wind_dial(state, radius: float = DIAL_RADIUS) -> None:
    """The dial: a ring, the boat with its bow up, the true wind (blue, toward
    ``state.wind_relative``) and the apparent wind (orange, from ``state.apparent_angle``)."""
    draw = imgui.get_window_draw_list()
    origin = imgui.get_cursor_screen_pos()
    width = max(imgui.get_content_region_avail().x, 2.0 * radius + 8.0)
    r = radius
    c = (origin.x + width * 0.5, origin.y + r + 6.0)
    draw.add_circle(imgui.ImVec2(*c), r, _u32(_RING), 48, 2.0)
    for tick in range(0, 360, 45):
        a, b = dial_point(c, r - 5.0, tick), dial_point(c, r, tick)
        draw.add_line(imgui.ImVec2(*a), imgui.ImVec2(*b), _u32(_RING), 1.0)
    bow, port, starboard = (dial_point(c, 0.42 * r, 0.0), dial_point(c, 0.3 * r, 200.0),
                            dial_point(c, 0.3 * r, 160.0))
    draw.add_triangle_filled(imgui.ImVec2(*bow), imgui.ImVec2(*starboard), imgui.ImVec2(*port),
                             _u32(_BOAT))
    head_size = 9.0 * r / DIAL_RADIUS
    arrows = [(state.wind_relative, _TRUE_WIND, 3.0)]
    if state.apparent_angle is not None:
        arrows.append((state.apparent_angle + 180.0, _APPARENT_WIND, 1.5))
    for toward, colour, thickness in arrows:
        tail, head = dial_arrow(c, r - 2.0, toward)
        col = _u32(colour)
        draw.add_line(imgui.ImVec2(*tail), imgui.ImVec2(*head), col, thickness)
        left, right = (dial_point(head, head_size, toward + 180.0 - 25.0),
                       dial_point(head, head_size, toward + 180.0 + 25.0))
        draw.add_triangle_filled(imgui.ImVec2(*head), imgui.ImVec2(*left), imgui.ImVec2(*right),
                                 col)
    imgui.dummy(imgui.ImVec2(width, 2.0 * r + 12.0))


def _flags(interactive: bool) -> int:
    """Fixed, auto-sized windows that fold at their title bar's arrow (the view behind)."""
    f = imgui.WindowFlags_
    flags = (f.always_auto_resize | f.no_saved_settings | f.no_move | f.no_focus_on_appearing)
    if not interactive:
        flags |= f.no_inputs
    return flags


def draw_hud(state, params: ParamSet, size: tuple[int, int], *, ui_mode: bool = True,
             paused: bool = False, keys_help=(), error: str | None = None) -> dict:
    """Draw the ship panel and the weather and time panel at the top right of a window of
    ``size`` (pixels); below :data:`COMPACT_BELOW` they are compact (narrower, a smaller dial,
    the weather panel folded at first). ``state`` is the scene's ``HudState`` (None when it
    could not be computed: ``error`` says why). Returns the screen rectangles (x0, y0, x1, y1)
    of the windows drawn, by name. The panels take the mouse only in the UI mode, and not while
    the pause menu is open; each folds at its title bar."""
    interactive = ui_mode and not paused
    small = compact(size)
    width = COMPACT_WIDTH if small else WIDTH
    rects: dict = {}
    alpha = 0.75 if interactive else 0.4
    imgui.set_next_window_pos(imgui.ImVec2(size[0] - MARGIN, MARGIN), imgui.Cond_.always,
                              imgui.ImVec2(1.0, 0.0))
    imgui.set_next_window_size_constraints(imgui.ImVec2(width, 0), imgui.ImVec2(width, 10000))
    imgui.set_next_window_bg_alpha(alpha)
    imgui.begin(SHIP_WINDOW, None, _flags(interactive))
    imgui.push_item_width(-LABEL_WIDTH)
    imgui.text_wrapped(mode_line(ui_mode, paused))
    imgui.separator()
    if state is None:
        imgui.text_wrapped(f"HUD unavailable: {error or 'no figures'}")
    else:
        imgui.text(f"heading {state.heading:5.1f}°" + ("\n" if small else "   ")
                   + f"speed {state.speed:4.1f} m/s ({state.speed * KNOTS_PER_MS:4.1f} kn)")
        _slider(params, HELM, "helm##hud", "%+.2f")
        _slider(params, SAILS, "sails##hud", "%+.2f")
        _slider(params, THROTTLE, "throttle##hud", "%+.2f")
        if not imgui.is_window_collapsed():  # the dial draws straight into the window
            _wind_dial(state, COMPACT_DIAL_RADIUS if small else DIAL_RADIUS)
        imgui.text_wrapped(f"true wind {state.wind_speed:4.1f} m/s toward "
                           f"{state.wind_relative:+.0f}°{_side(state.wind_relative)}")
        if state.apparent_angle is not None:
            imgui.text_wrapped(f"apparent wind from {abs(state.apparent_angle):.0f}°"
                               f"{_side(state.apparent_angle)}")
        if keys_help and imgui.collapsing_header("Keys##hud"):
            for keys, what in keys_help:
                imgui.text(f"{keys:14s} {what}")
    imgui.pop_item_width()
    rects["ship"] = _window_rect()
    ship_bottom = rects["ship"][3]
    imgui.end()

    imgui.set_next_window_pos(imgui.ImVec2(size[0] - MARGIN, ship_bottom + MARGIN),
                              imgui.Cond_.always, imgui.ImVec2(1.0, 0.0))
    imgui.set_next_window_size_constraints(imgui.ImVec2(width, 0), imgui.ImVec2(width, 10000))
    if small:
        imgui.set_next_window_collapsed(True, imgui.Cond_.first_use_ever)
    imgui.set_next_window_bg_alpha(alpha)
    imgui.begin(WEATHER_WINDOW, None, _flags(interactive))
    imgui.push_item_width(-LABEL_WIDTH)
    if state is not None:
        playing = bool(state.playing)
        imgui.text(f"time {hour_label(state.hour)}   {'playing' if playing else 'paused'}")
        if PLAYING in params:
            imgui.same_line()
            if imgui.button(("Pause" if playing else "Play") + "##hud-time"):
                params.set(PLAYING, not playing)
        if HOUR in params:
            changed, hour = imgui.slider_float("hour##hud", float(params[HOUR]), 0.0, 24.0,
                                               "%.2f h")
            if changed:
                params.set(HOUR, hour % 24.0)
        if WEATHER in params:
            imgui.text(f"weather: {state.weather}")
            for i, choice in enumerate(c for c in params.spec(WEATHER).choices
                                       if c != "custom"):
                if i % 2:
                    imgui.same_line(110.0)
                if imgui.radio_button(f"{choice}##hud-weather", state.weather == choice):
                    params.set(WEATHER, choice)
        _slider(params, WIND_SPEED, "wind##hud", "%.1f m/s")
        _slider(params, WIND_DIRECTION, "wind dir##hud", "toward %.0f°")
    imgui.pop_item_width()
    rects["weather"] = _window_rect()
    imgui.end()
    return rects


def _window_rect() -> tuple[float, float, float, float]:
    pos, sz = imgui.get_window_pos(), imgui.get_window_size()
    return (float(pos.x), float(pos.y), float(pos.x + sz.x), float(pos.y + sz.y))


def _item_rect() -> tuple[float, float, float, float]:
    a, b = imgui.get_item_rect_min(), imgui.get_item_rect_max()
    return (float(a.x), float(a.y), float(b.x), float(b.y))


def pause_menu(size: tuple[int, int], rects: dict | None = None) -> str | None:
    """The pause menu, centred: "resume" or "quit" when its button was clicked, else None.
    ``rects`` (when given) receives the buttons' screen rectangles."""
    f = imgui.WindowFlags_
    imgui.set_next_window_pos(imgui.ImVec2(size[0] * 0.5, size[1] * 0.5), imgui.Cond_.always,
                              imgui.ImVec2(0.5, 0.5))
    imgui.set_next_window_focus()
    imgui.begin(PAUSE_WINDOW, None, f.no_collapse | f.always_auto_resize | f.no_saved_settings
                | f.no_move)
    choice = None
    imgui.text("Esc again: quit")
    if imgui.button("Resume", imgui.ImVec2(120, 0)):
        choice = "resume"
    if rects is not None:
        rects["Resume"] = _item_rect()
    imgui.same_line()
    if imgui.button("Quit", imgui.ImVec2(120, 0)):
        choice = "quit"
    if rects is not None:
        rects["Quit"] = _item_rect()
    imgui.end()
    return choice
