"""The window's A/B comparison (F3, or the panel's "Compare A/B" button): docs/commands.md
("Teaching tools") says what it shows. The sides are typed as ``NAME=VALUE`` lines or picked
from the scene's methods (app/teach/methods.py) and rendered by app/teach/compare.py on the
window's GL context; the live scene is not touched.
"""

from __future__ import annotations

import shlex
from pathlib import Path
from typing import Callable

import moderngl
import numpy as np
from imgui_bundle import imgui

from ..errors import NaturaError
from ..imageio import next_free_path
from ..teach import compare as cmp_logic
from ..teach import methods as methods_logic
from . import panel

SIZES = ((160, 90), (320, 180), (480, 270), (640, 360))


def parse_sets(text: str) -> list[str]:
    """``planet.method=lut planet.n_steps=16`` (spaces or commas between) → the sets."""
    return [s for part in shlex.split(text.replace(",", " ")) if (s := part.strip())]


class ComparePane:
    def __init__(self, say: Callable[[str], None], fail: Callable[[str], None],
                 software: bool = False):
        self.say, self.fail = say, fail
        self.shown = False
        self.a_text = ""
        self.b_text = ""
        self.size_index = 0 if software else 1  # a software renderer starts at 160x90
        self.rounds = 3
        self.reference = True
        self.layout = 0  # 0: side by side, 1: wipe
        self.wipe = 0.5
        self.result: cmp_logic.Comparison | None = None
        self.problem: str | None = None
        self.textures: dict[str, moderngl.Texture] = {}
        self._scene: str | None = None
        self.saved: list[Path] = []
        self.requested = False  # run before the next ImGui frame (it draws progress frames)
        self.button_rect = (0.0, 0.0, 0.0, 0.0)  # where "Compare" was drawn (x0, y0, x1, y1)

    def preset_for(self, scene_name: str) -> None:
        """Start with the scene's first two methods (planet: brute force against the LUT)."""
        if self._scene == scene_name:
            return
        self._scene = scene_name
        axis = methods_logic.axis_of(scene_name)
        if axis is not None and len(axis.choices) >= 2:
            self.a_text = f"{axis.param}={axis.choices[1][0]}"
            self.b_text = f"{axis.param}={axis.choices[-1][0]}"

    def run(self, session, register, progress=None) -> bool:
        """Compare now (blocking: seconds on a software renderer)."""
        try:
            a, b = parse_sets(self.a_text), parse_sets(self.b_text)
        except ValueError as exc:
            self.problem = f"cannot read the sets: {exc}"
            return False
        say = progress or (lambda text: None)
        try:
            result = cmp_logic.compare(None, a, b, session=session, size=SIZES[self.size_index],
                                       rounds=int(self.rounds), reference=self.reference,
                                       progress=say)
        except NaturaError as exc:
            self.problem = str(exc)
            self.fail(f"compare: {exc}")
            return False
        self.result = result
        self.problem = None
        self._upload(session.gpu.ctx, register)
        self.say("compare: " + " | ".join(result.caption[:2]))
        return True

    def _upload(self, ctx, register) -> None:
        self.release()
        assert self.result is not None
        for key, pixels in (("a", self.result.a.png), ("b", self.result.b.png),
                            ("heat", self.result.heat)):
            rgb = np.ascontiguousarray(pixels, dtype=np.uint8)
            h, w = rgb.shape[:2]
            tex = ctx.texture((w, h), 3, data=rgb.tobytes())
            tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
            register(tex)
            self.textures[key] = tex

    def release(self, unregister=None) -> None:
        for tex in self.textures.values():
            if unregister is not None:
                unregister(tex)
            tex.release()
        self.textures.clear()

    def save_png(self, folder: Path) -> Path | None:
        if self.result is None:
            return None
        folder.mkdir(parents=True, exist_ok=True)
        for _ in range(100):
            path = next_free_path(folder, f"compare-{self.result.scene}", ".png")
            try:
                png, _json = cmp_logic.write(self.result, path, path.with_suffix(".json"),
                                             ("side", "wipe")[self.layout], float(self.wipe))
            except FileExistsError:
                continue
            except (NaturaError, OSError) as exc:
                self.fail(f"comparison not saved in {folder}: {exc}")
                return None
            self.saved.append(png)
            self.say(f"saved {png}")
            return png
        return None

    def draw(self, session, register, size, save_folder=Path(".")) -> None:
        if not self.shown:
            return
        self.preset_for(session.scene.name)
        w, h = size
        imgui.set_next_window_pos((max(w * 0.5 - 360.0, 10.0), max(h - 470.0, 10.0)),
                                  imgui.Cond_.first_use_ever)
        imgui.set_next_window_size((min(720.0, w - 20.0), min(460.0, h - 20.0)),
                                   imgui.Cond_.first_use_ever)
        expanded, self.shown = imgui.begin("Compare A/B###natura-compare", self.shown)
        if expanded:
            self._draw_controls(session, save_folder)
            self._draw_result()
        imgui.end()

    def _draw_controls(self, session, save_folder) -> None:
        axis = methods_logic.axis_of(session.scene.name)
        for side in ("A", "B"):
            attr = f"{side.lower()}_text"
            _, text = imgui.input_text_with_hint(f"{side}##sets", "NAME=VALUE NAME=VALUE …",
                                                 getattr(self, attr))
            setattr(self, attr, text)
            if axis is not None:
                imgui.same_line()
                imgui.set_next_item_width(90)
                if imgui.begin_combo(f"##method-{side}", "method…"):
                    for value, title in axis.choices:
                        if imgui.selectable(f"{title}##{side}-{value}", False)[0]:
                            setattr(self, attr, f"{axis.param}={value}")
                    imgui.end_combo()
        labels = [f"{a}x{b}" for a, b in SIZES]
        imgui.set_next_item_width(110)
        _, self.size_index = imgui.combo("size", self.size_index, labels)
        imgui.same_line()
        imgui.set_next_item_width(110)
        _, self.rounds = imgui.slider_int("rounds", int(self.rounds), 1, 15)
        imgui.same_line()
        _, self.reference = imgui.checkbox("against the reference", self.reference)
        if imgui.button("Compare"):
            self.requested = True
        self.button_rect = (*imgui.get_item_rect_min(), *imgui.get_item_rect_max())
        if self.result is not None:
            imgui.same_line()
            if imgui.button("Save PNG"):
                self.save_png(save_folder)
            imgui.same_line()
            imgui.set_next_item_width(150)
            _, self.layout = imgui.combo("layout", self.layout, ["side by side", "wipe"])
            if self.layout == 1:
                imgui.same_line()
                imgui.set_next_item_width(150)
                _, self.wipe = imgui.slider_float("wipe", float(self.wipe), 0.0, 1.0)
        if self.problem:
            panel.error_list([self.problem])

    def _draw_result(self) -> None:
        r = self.result
        if r is None or not self.textures:
            imgui.text_wrapped("Both sides render from the current camera and time, each in a "
                               "scene of its own; the live scene is not touched.")
            return
        avail = imgui.get_content_region_avail()
        w, h = r.size
        panels = 3 if self.layout == 0 else 2
        scale = max(min((avail.x - 8.0 * panels) / (panels * w), 2.0), 0.25)
        dw, dh = w * scale, h * scale
        ref = imgui.ImTextureRef
        if self.layout == 0:
            for i, (key, title) in enumerate((("a", "A"), ("b", "B"),
                                              ("heat", f"B − A ×{r.gain:.3g}"))):
                if i:
                    imgui.same_line()
                imgui.begin_group()
                imgui.image(ref(self.textures[key].glo), (dw, dh))
                imgui.text(title)
                imgui.end_group()
        else:
            t = float(self.wipe)
            imgui.begin_group()
            start = imgui.get_cursor_screen_pos()
            if t > 0.0:
                imgui.image(ref(self.textures["a"].glo), (dw * t, dh), (0.0, 0.0), (t, 1.0))
            if 0.0 < t < 1.0:
                imgui.same_line(0.0, 0.0)
            if t < 1.0:
                imgui.image(ref(self.textures["b"].glo), (dw * (1.0 - t), dh), (t, 0.0),
                            (1.0, 1.0))
            imgui.get_window_draw_list().add_line((start.x + dw * t, start.y),
                                                  (start.x + dw * t, start.y + dh),
                                                  imgui.IM_COL32(255, 255, 255, 255), 2.0)
            imgui.text("A | B")
            imgui.end_group()
            imgui.same_line()
            imgui.begin_group()
            imgui.image(ref(self.textures["heat"].glo), (dw, dh))
            imgui.text(f"B − A ×{r.gain:.3g}")
            imgui.end_group()
        imgui.push_text_wrap_pos(0.0)
        for line in r.caption:
            imgui.text_wrapped(line)
        imgui.pop_text_wrap_pos()
