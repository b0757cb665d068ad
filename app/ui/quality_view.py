"""The panel's "Quality: time against error" section (ImPlot): for each knob family the benches
measured for this scene (app/teach/quality.py), its points of ms against error, the current
setting (square) and — with ``--quality auto`` — the chosen one (ringed) and the budget lines,
with the picker's line saying why."""

from __future__ import annotations

from typing import Any

import numpy as np
from imgui_bundle import imgui, implot

from ..teach import quality

CURRENT = (1.0, 1.0, 1.0, 1.0)
CHOSEN = (1.0, 0.35, 0.2, 1.0)
BUDGET = (1.0, 0.8, 0.2, 0.9)


class QualityView:
    """Families are read once per scene (they come from JSON files, not from the frame)."""

    def __init__(self, picks=None):
        self.picks = picks
        self._families: dict[str, list] = {}
        self.problem: str | None = None
        self.plots_drawn = 0  # charts drawn in the last frame (the window test reads it)

    def families(self, scene_name: str) -> list:
        if scene_name not in self._families:
            try:
                self._families[scene_name] = quality.families(scene_name)
            except Exception as exc:  # noqa: BLE001 - no sweeps: one line, not a crash
                self.problem = f"no measured sweeps: {exc}"
                self._families[scene_name] = []
        return self._families[scene_name]

    def _choices(self, scene_name: str) -> list[tuple[Any, Any]]:
        if self.picks:
            return [(c.family, c) for c in self.picks]
        return [(f, None) for f in self.families(scene_name)]

    def draw(self, scene_name: str, params, size) -> None:
        self.plots_drawn = 0
        pairs = self._choices(scene_name)
        if not pairs:
            imgui.text_wrapped(self.problem or "No measured sweeps for this scene: run "
                               f"`natura bench {scene_name}` (then --sweeps FILE).")
            return
        if self.picks is not None:
            imgui.text_wrapped(f"--quality auto, from {self.picks.source}")
        shown = 0
        for i, (family, choice) in enumerate(pairs):
            if choice is not None and choice.status == "skipped":
                imgui.push_style_color(imgui.Col_.text, imgui.get_style_color_vec4(
                    imgui.Col_.text_disabled))
                imgui.text_wrapped(choice.line())
                imgui.pop_style_color()
                continue
            a = quality.plot_arrays(family, choice, params=params, size=size)
            shown += 1
            if not imgui.tree_node_ex(f"{a['title']}##q{i}",
                                      imgui.TreeNodeFlags_.default_open if shown <= 2 else 0):
                continue
            self._plot(a, i)
            if choice is not None:
                imgui.push_text_wrap_pos(0.0)
                imgui.text_wrapped(choice.line())
                imgui.pop_text_wrap_pos()
            imgui.tree_pop()

    def _plot(self, a: dict, i: int) -> None:
        if not implot.begin_plot(f"##quality{i}", (-1, 200)):
            return
        try:
            implot.setup_axes(a["x_title"], "error")
            if a["log_error"]:
                implot.setup_axis_scale(implot.ImAxis_.y1, implot.Scale_.log10)
            ms = np.ascontiguousarray(a["ms"], dtype=np.float64)
            err = np.ascontiguousarray(a["error"], dtype=np.float64)
            spec = implot.Spec()
            spec.marker = implot.Marker_.circle
            implot.plot_line("measured", ms, err, spec)
            for key, colour, marker, label in (("current", CURRENT, implot.Marker_.square,
                                                "current"),
                                               ("chosen", CHOSEN, implot.Marker_.circle,
                                                "chosen")):
                j = a[key]
                if j < 0:
                    continue
                s = implot.Spec()
                s.marker = marker
                s.marker_size = 7.0
                s.marker_fill_color = (0.0, 0.0, 0.0, 0.0)
                s.marker_line_color = colour
                s.line_weight = 2.0
                implot.plot_scatter(label, ms[j:j + 1], err[j:j + 1], s)
            for key, horizontal in (("error_budget", True), ("ms_budget", False)):
                value = a[key]
                if value is None:
                    continue
                s = implot.Spec()
                s.line_color = BUDGET
                if horizontal:
                    s.flags = implot.InfLinesFlags_.horizontal
                implot.plot_inf_lines(key.replace("_", " "),
                                      np.array([float(value)], dtype=np.float64), s)
            self.plots_drawn += 1
        finally:
            implot.end_plot()
