"""The noise lab: every noise function and every cloud bake on the screen, tiled so seams show.

Bakes come from :mod:`app.bakes` (cached on disk); a bake reports its progress through
``gpu.progress`` (the window draws a progress bar there while it runs). Changing a ``bake_*``
parameter re-bakes (or loads the matching cache file).
"""

from __future__ import annotations

import moderngl

from ... import bakes
from ...bakes.textures import BakedTextures
from ...frame import Stage
from ...gpu.programs import draw_fullscreen, fullscreen
from ...params import Param
from ..base import Effect

VIEWS = ("shape", "detail", "weather", "perlin", "worley_f1", "worley_f2_f1", "fbm", "turbulence",
         "perlin_worley", "value")
CHANNELS = ("r", "g", "b", "a", "rgb")
#: noise.layout: one view, or four panels side by side (glsl/noise/noise_view.frag)
LAYOUTS = ("single", "kinds", "octaves", "channels")
LIVE_FRACTALS = ("perlin", "worley_f1", "worley_f2_f1", "fbm", "turbulence", "perlin_worley",
                 "value")
NOISE_VIEW = fullscreen("noise/noise_view")


class Noise(Effect):
    name = "noise"
    title = "Noise lab"
    spec = "spec/001"
    programs = (NOISE_VIEW,) + tuple(spec for p in bakes.PROGRAMS.values()
                                     for spec in (p.compute, p.fragment))
    extra_groups = ("bake_shape", "bake_detail", "bake_weather")
    stages = (Stage.BACKGROUND,)

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        return bakes.context_path(caps)

    @classmethod
    def python_params(cls) -> list[Param]:
        return [
            Param("noise.view", "shape", doc="what to show: a bake (shape, detail, weather) or a "
                  "live function", kind="choice", choices=VIEWS, section="spec/001 §1.1"),
            Param("noise.layout", "kinds", doc="single = one view, tiled; kinds = Perlin fBm, "
                  "Worley F1, the shape bake's Perlin–Worley and the thesis's value noise side by "
                  "side; octaves = the view (a live function) at 1, 2, 4 and 8 octaves; channels "
                  "= the shape (or detail) bake's R, G, B, A", kind="choice", choices=LAYOUTS,
                  section="spec/001 §1.1"),
            Param("noise.channel", "r", doc="channel of a bake (rgb: all three)", kind="choice",
                  choices=CHANNELS),
            Param("noise.slice", 0.0, 0.0, 1.0,
                  "z of the slice through a volume or a live 3D function"),
            Param("noise.animate", False, doc="move the slice through the volume", kind="bool"),
            Param("noise.tiles", 2.0, 1.0, 8.0,
                  "repeats across the screen height (seams would show here)"),
            Param("noise.scale", 4.0, 1.0, 32.0, "lattice cells per tile of the live functions",
                  step=1.0),
            Param("noise.octaves", 4, 1, 8, "octaves of the live fractal sums", kind="int"),
        ] + bakes.bake_params()

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.bakes = BakedTextures(gpu, self.name)
        self._extra: dict[str, object] = {}  # value-noise table, permutation textures

    def texture_for(self, kind: str):
        return self.bakes.from_params(kind, self.params)

    def update(self, frame, dt: float) -> None:
        if self.params["noise.animate"] and dt > 0:
            self.params.set("noise.slice", (self.params["noise.slice"] + 0.05 * dt) % 1.0)

    def shown(self) -> tuple[str, ...]:
        """The views the current layout draws (what its textures are bound for)."""
        view, layout = self.params["noise.view"], self.params["noise.layout"]
        if layout == "kinds":
            return ("fbm", "worley_f1", "shape", "value")
        if layout == "octaves":
            return (view if view in LIVE_FRACTALS else "fbm",)
        if layout == "channels":
            return ("detail" if view == "detail" else "shape",)
        return (view,)

    def draw(self, frame, target) -> None:
        p = self.params
        view = p["noise.view"]
        shown = self.shown()
        prog = self.program(NOISE_VIEW)
        textures: dict = {}
        for bake in ("shape", "detail"):
            if bake in shown:
                textures["uVolume"] = self.texture_for(bake)
        if "weather" in shown:
            textures["uMap"] = self.texture_for("weather")
        if "value" in shown:
            from ...render.noise import value_noise_texture

            if "value" not in self._extra:
                self._extra["value"] = value_noise_texture(self.gpu, self.name, 1)
            textures["uValueNoiseTex"] = self._extra["value"]
            prog.set("uValueNoiseWrap", (256.0, 256.0, 256.0))
        if {"perlin", "fbm", "turbulence", "perlin_worley"} & set(shown):
            from ...render.noise import GradientNoiseTextures

            if "gradient" not in self._extra:
                self._extra["gradient"] = GradientNoiseTextures(self.gpu, self.name)
            textures.update(self._extra["gradient"].textures(None))
        # every sampler gets a unit of its own, bound or not: two sampler types on one unit fail
        # the draw
        prog.bind_textures(textures)
        prog.set_many({
            "uView": VIEWS.index(view), "uLayout": LAYOUTS.index(p["noise.layout"]),
            "uChannel": CHANNELS.index(p["noise.channel"]),
            "uSlice": p["noise.slice"],
            "uTiles": p["noise.tiles"], "uAspect": frame.aspect, "uScale": p["noise.scale"],
            "uOctaves": p["noise.octaves"],
        })
        target.use()
        self.gpu.ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog)
