"""ImGui widgets built from parameters, grouped per effect (one collapsing header per group).

Every widget writes through :meth:`ParamSet.set`, so the panel can never store a value the
CLI would reject. Hovering a widget shows its doc, unit, range and thesis section.
"""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui

from ..colour import linear_to_srgb, srgb_to_linear
from ..params import Param, ParamSet

ERROR_COLOUR = (1.0, 0.35, 0.3, 1.0)


def _tooltip(p: Param) -> None:
    if imgui.is_item_hovered():
        unit = f" {p.unit}" if p.unit else ""
        lines = [p.name, p.doc, f"allowed: {p.allowed()}{unit}", f"default: {p.default}"]
        if p.section:
            lines.append(f"thesis: {p.section}")
        if p.source != "python":
            lines.append(f"declared in {p.source}")
        imgui.set_tooltip("\n".join(lines))


def param_widget(params: ParamSet, p: Param) -> bool:
    """Draw one widget; returns True when the value changed."""
    value = params[p.name]
    label = f"{p.short}##{p.name}"
    changed = False
    new = value
    if p.kind == "bool":
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
        fmt = "%.4g" + (f" {p.unit}" if p.unit else "")
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
    _tooltip(p)
    if imgui.begin_popup_context_item(f"ctx##{p.name}"):
        if imgui.menu_item_simple("reset to default"):
            new, changed = p.default, True
        imgui.end_popup()
    if changed:
        try:
            params.set(p.name, new)
        except Exception:  # a half-typed or out-of-range value: keep the last valid one
            return False
    return changed


def params_panel(params: ParamSet, titles: dict[str, str], skip: set[str] = frozenset(),
                 open_groups: set[str] = frozenset(),
                 notes: dict[str, list[str]] | None = None) -> None:
    """One collapsing header per group, the groups in ``open_groups`` open at first; groups
    with a title (the scene's effects, Time, Output) come first. ``notes`` are lines an effect
    shows above its widgets (live figures, what the current method teaches)."""
    groups = params.groups()
    order = [g for g in titles if g in groups] + [g for g in groups if g not in titles]
    for group in order:
        shown = [p for p in groups[group] if p.name not in skip]
        if not shown:
            continue
        title = titles.get(group, group)
        flags = imgui.TreeNodeFlags_.default_open if group in open_groups else 0
        if imgui.collapsing_header(f"{title}##{group}", flags):
            for line in (notes or {}).get(group, ()):
                imgui.text_wrapped(line)
            for p in shown:
                param_widget(params, p)


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
        imgui.image(tex.glo, (64.0, 64.0 if tex.height > 1 else 12.0))
        imgui.text_disabled(label)
        imgui.end_group()
        imgui.same_line()
    imgui.new_line()
