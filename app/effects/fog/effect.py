"""Fog (spec/003 §2.11): the thesis's two fogs and their ``FogGenerator``.

(a) The ground fog plane, ``Custom/Fog`` (``glsl/fog/plane.*``, placed by :mod:`.plane`): a
semitransparent plane just above the island's ground with a generated, tileable RGBA fog texture
(spec/003 Fig. 118), its uv scrolled with the wind, its alpha cut by a sin(t)-modulated cutoff
so the fog comes and goes. It draws in the transparent stage, first of the stage's effects (the
scene lists the fog before the others: the thesis gives it a lower queue, Transparent−1, than
the other semitransparent materials, so those above it blend over it), blended, depth-tested
against the scene, writing no depth.

(b) The global distance fog: this effect only *publishes* it — ``frame.fog``, an
:class:`app.sim.fog.FogSettings`, filled in ``update`` (the scene lists the fog before every
surface that applies it). Each lit surface's shader applies it after its lighting through
``glsl/common/fog.glsl``: Unity's Lighting › Fog panel (Fig. 123: Fog Color, Fog Mode
Exponential Squared, Density 0.1; linear start and end), the factor per vertex carried in the w
of the world position (spec/003 eq. 7.24, spec/003 eq. 7.27, spec/003 eq. 7.28,
spec/003 eq. 7.29), or per pixel (``fog.per_pixel``, beyond the thesis), or Quílez's analytic
exponential height fog instead (``fog.height``, the scene's H key, beyond the thesis).

``FogGenerator`` (Fig. 124: Fog Intensity 0.324, Speed 0.264, Fog Mode Exponential Squared)
drives both fogs from one intensity I; the mapping is in :mod:`app.sim.fog`'s docstring.
I = 0 turns both fogs off.

Metres: FogGenerator's constants (density 0.1·I per metre, linear end 30·(1 − I) m) were set for
Fracsland's village. This village's houses stand 20–30 m from its centre and the default camera
is 25 m south of it, so the far houses are 45–55 m away: ``fog.scale`` = 2 stretches the
thesis's distances twice, which puts exp2's half-fog distance √(ln 2)/t at 51 m with the
thesis's I = 0.324 (t = 0.0162/m: the near houses keep 85 % of their colour, the far ones 45 %,
the sea's horizon is all fog), and the linear fog's end at 41 m.

Its colour (``fog.color``, the day's) follows the sky with ``fog.color_from_sky`` (on by
default): scaled by the sky's ambient luminance over the day's and tinted toward its hue
(:func:`app.sim.fog.sky_fog_colour`), so it does not glow at night; the plane is lit by the main
light (the moon's radiance at night) and the ambient, for the same reason.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ...frame import Stage
from ...gpu.cache import memoised
from ...gpu.programs import ProgramSpec
from ...params import Inspector, Param
from ...sim import fog as fs
from ..base import Effect, Pass
from . import plane as pl

PLANE = ProgramSpec("fog/plane")
#: the day fog colour (linear): about the default sky's horizon at noon, so the sea fades into
#: the sky where they meet
DAY_COLOUR = (0.58, 0.70, 0.84)


def plane_anisotropy(setting: int, software: bool) -> int:
    """The fog texture's anisotropy: ``setting``, or with 0 (auto) 1× on a software renderer
    and 8× on a GPU."""
    return int(setting) if setting > 0 else (1 if software else 8)


class Fog(Effect):
    name = "fog"
    title = "Fog"
    spec = "spec/003"
    programs = (PLANE,)
    stages = (Stage.TRANSPARENT,)
    produces = frozenset({"fog"})
    consumes = {"terrain": "optional", "main_light": "optional", "wind": "optional"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s, a, b = "spec/003 §2.11", "spec/003 §2.11 a", "spec/003 §2.11 b"
        return [
            Param("fog.mode", "exp2", doc="Fog Mode of the global fog (Figs. 123–124: "
                  "Exponential Squared): off, linear (spec/003 eq. 7.27), exponential "
                  "(spec/003 eq. 7.28), exponential squared (spec/003 eq. 7.29)", kind="choice",
                  choices=fs.MODES, section=b),
            Param("fog.intensity", 0.324, 0.0, 1.0, "FogGenerator's Fog Intensity (Fig. 124: "
                  "0.324): the global fog's density and the plane's opacity (its cutoff is "
                  "1 − intensity); 0 turns both fogs off", step=0.001, section=s),
            Param("fog.speed", 0.264, 0.0, 1.0, "FogGenerator's Speed (Fig. 124: 0.264): the "
                  "plane's texture drifts along the wind by speed·t/20 tiles", step=0.001,
                  section=a),
            Param("fog.scale", 2.0, 0.25, 10.0, "metres of this village per metre of the "
                  "thesis's: FogGenerator's distances (density 0.1·I per m, linear end 30·(1 − I)"
                  " m) are stretched by it", step=0.05, section=b),
            Param("fog.density", 0.1, 0.0, 1.0, "the Lighting window's Density (Fig. 123: 0.1) "
                  "at intensity 1, per metre of the thesis: t = density·intensity/scale",
                  step=0.001, unit="1/m", section=b),
            Param("fog.start", 0.0, 0.0, 500.0, "linear fog: the distance where it starts (the "
                  "repository's 0), in the thesis's metres", step=0.5, unit="m", section=b),
            Param("fog.end", 30.0, 0.0, 500.0, "linear fog: its end at intensity 0 (the "
                  "repository's 30 − 30·intensity), in the thesis's metres", step=0.5, unit="m",
                  section=b),
            Param("fog.color", DAY_COLOUR, 0.0, 4.0, "Fog Color (Fig. 123), by day (linear "
                  "radiance): about the sky's horizon at noon", kind="color", section=b),
            Param("fog.color_from_sky", True, doc="the fog's colour follows the sky: Fog Color "
                  "scaled by the sky's ambient luminance over the day's and tinted toward its "
                  "hue (no glowing fog at night)", kind="bool", section=b),
            Param("fog.sky_tint", 0.3, 0.0, 1.0, "how far the sky's hue tints the fog colour "
                  "(with color_from_sky)", step=0.01, section=b),
            Param("fog.per_pixel", False, doc="the fog factor per pixel instead of per vertex "
                  "(the thesis computes it per vertex; beyond the thesis)", kind="bool",
                  section=b),
            Param("fog.height", False, doc="Quílez's analytic exponential height fog instead of "
                  "the distance fog, when fog.mode is not off (beyond the thesis; H)",
                  kind="bool", section=b),
            Param("fog.height_density", 0.15, 0.0, 2.0, "height fog: its density at its base "
                  "height at intensity 1 (times the intensity)", step=0.005, unit="1/m",
                  section=b),
            Param("fog.height_falloff", 0.35, 0.0, 5.0, "height fog: how fast the density "
                  "falls with height, exp(−falloff·(y − base))", step=0.01, unit="1/m",
                  section=b),
            Param("fog.height_base", 0.0, -50.0, 200.0, "height fog: the height where its "
                  "density is height_density·intensity (the sea level is 0)", step=0.1,
                  unit="m", section=b),
            Param("fog.plane", True, doc="the ground fog plane (Custom/Fog)", kind="bool",
                  section=a),
            Param("fog.plane_height", 0.35, 0.0, 5.0, "the plane's height above the land's "
                  "median height (the plateau): low, so it cuts the houses little (Fig. 119)",
                  step=0.01, unit="m", section=a),
            Param("fog.plane_anisotropy", 0, 0, 16, "anisotropic filtering of the plane's fog "
                  "texture, seen at grazing angles (0 = auto: 8× on a GPU, where it is almost "
                  "free; 1× — trilinear, Unity's default Aniso Level — on a software renderer, "
                  "where 8× costs the pass four times as much for wisps this soft)", kind="int",
                  section=a),
        ]

    #: what each global fog mode teaches (fog.mode)
    lesson_param = "fog.mode"
    LESSONS = {
        "off": "Global fog off (spec/003 §2.11(b)); the scrolling ground-fog plane of spec/003 "
               "§2.11(a) is a separate switch (fog.plane).",
        "linear": "Linear fog (spec/003 §2.11(b)): f = (end − d)/(end − start) from "
                  "the clip-space distance, per vertex, lerped after lighting; full fog at a "
                  "hard distance.",
        "exp": "Exponential fog (spec/003 §2.11(b)): f = e^(−t·d), thinning smoothly "
               "with distance and never quite opaque.",
        "exp2": "Exponential squared fog (spec/003 §2.11(b), the thesis's choice): "
                "f = e^(−(t·d)²) keeps the near scene clear and closes in faster beyond.",
    }

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        aniso = int(params["fog.plane_anisotropy"])
        chosen = plane_anisotropy(aniso, caps.software)
        how = "set" if aniso else ("auto: software renderer" if caps.software else "auto")
        return {"fog plane texture anisotropy": f"{chosen}× ({how})"}

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.scroll = np.zeros(2)  # the plane's uv offset [tiles], integrated per frame
        self.settings: fs.FogSettings | None = None
        self._layout = self.keyed(lambda key: self._build_layout(key), self._free_layout)
        self._texture = None
        self._notes: list[str] = []

    def generator(self) -> fs.FogGenerator:
        p = self.params
        start = p["fog.start"]
        return fs.FogGenerator(intensity=p["fog.intensity"], speed=p["fog.speed"],
                               mode=p["fog.mode"], scale=p["fog.scale"], density=p["fog.density"],
                               start=start, end=max(p["fog.end"], start))

    def fog_colour(self, frame) -> tuple[float, float, float]:
        colour = tuple(float(c) for c in self.params["fog.color"])
        light = frame.main_light
        if self.params["fog.color_from_sky"] and light is not None and light.ambient is not None:
            return fs.sky_fog_colour(colour, light.ambient, self.params["fog.sky_tint"])
        return colour

    def update(self, frame, dt: float) -> None:
        p = self.params
        gen = self.generator()
        wind = frame.wind
        direction = np.array([0.0, 1.0])  # the thesis's +v without a wind
        if wind is not None and float(np.hypot(*wind)) > 1e-6:
            direction = np.asarray(wind, np.float64) / float(np.hypot(*wind))
        # the texture drifts with the wind: its content moves along +direction in the world
        self.scroll = self.scroll - direction * gen.speed * fs.UNITY_TIME_X * max(dt, 0.0)
        self.scroll = np.mod(self.scroll, 1.0)  # a tile's offset: stays small in fp32
        colour = self.fog_colour(frame)
        self.settings = gen.settings(colour, per_pixel=p["fog.per_pixel"], height=p["fog.height"],
                                     height_density=p["fog.height_density"],
                                     height_falloff=p["fog.height_falloff"],
                                     height_base=p["fog.height_base"])
        frame.fog = self.settings
        notes = [f"global fog: {gen.mode}" if self.settings else "global fog: off"]
        if self.settings is not None:
            if p["fog.height"]:
                notes.append(f"height fog: a = {self.settings.height_density:.4f}/m at "
                             f"{self.settings.height_base:g} m, b = "
                             f"{self.settings.height_falloff:g}/m")
            elif gen.mode == "linear":
                notes.append(f"linear: s = {self.settings.start:.1f} m, "
                             f"e = {self.settings.end:.1f} m")
            else:
                t = self.settings.density
                if t > 0.0:
                    half = (math.sqrt(math.log(2.0)) if gen.mode == "exp2" else math.log(2.0)) / t
                    notes.append(f"t = {t:.4f}/m, half fog at {half:.0f} m")
                else:
                    notes.append("t = 0: no distance fog")
        if p["fog.end"] < p["fog.start"]:
            notes.append("fog.end < fog.start: the end is taken at the start")
        notes.append(f"plane cutoff now {float(gen.plane_cutoff(frame.time)):.3f} "
                     f"(max {1.0 - gen.intensity:.3f})")
        self._notes = notes

    def panel_notes(self) -> list[str]:
        return list(self._notes)

    #: the inspector's popups: FogGenerator's three fields (Fig. 124), Unity's Lighting › Fog
    #: panel (Fig. 123), the colour, the plane, and the beyond-the-thesis switches
    INSPECTOR = {
        "Fog Generator": ["fog.intensity", "fog.speed", "fog.mode"],
        "Lighting › Fog": ["fog.density", "fog.start", "fog.end", "fog.scale"],
        "Colour": ["fog.color", "fog.color_from_sky", "fog.sky_tint"],
        "Ground plane": ["fog.plane", "fog.plane_height", "fog.plane_tile",
                         "fog.plane_anisotropy"],
        "Ground plane's wisps": ["fog.plane_opacity", "fog.plane_breakup", "fog.plane_hug",
                                 "fog.plane_grazing"],
        "Beyond the thesis": ["fog.per_pixel", "fog.height", "fog.height_density",
                              "fog.height_falloff", "fog.height_base"],
    }

    def panel_items(self) -> list:
        """The FogGenerator inspector (Fig. 124) with the fog texture (Fig. 118) and the
        plane's ground mask as thumbnails, once made."""
        popups = {t: [n for n in names if n in self.params] for t, names in self.INSPECTOR.items()}
        textures = {}
        if self._texture is not None:
            textures["fog texture (Fig. 118)"] = self._texture
        if self._layout.built and self._layout.value is not None:
            textures["ground mask"] = self._layout.value[3]
        return [Inspector("Fog Generator (spec/003 §2.11)", popups, textures)]

    def _build_layout(self, key):
        terrain, offset = key[0], key[2]
        layout = pl.plane_layout(terrain, offset)
        verts, idx = pl.plane_grid(layout.rect)
        vbo = self.gpu.buffer(self.name, "fog plane vertices", verts.tobytes())
        ibo = self.gpu.buffer(self.name, "fog plane indices", idx.tobytes())
        mask = pl.upload_texture(self.gpu, self.name, "fog plane ground mask",
                                 layout.mask_texture(), repeat=False)
        return layout, vbo, ibo, mask

    def _free_layout(self, value) -> None:
        for obj in value[1:]:
            self.gpu.free(obj)

    def texture(self):
        if self._texture is None:
            self._texture = pl.upload_texture(self.gpu, self.name, "fog texture",
                                              memoised(fs.fog_texture, pl.TEXTURE_SIZE),
                                              repeat=True)
        aniso = float(plane_anisotropy(int(self.params["fog.plane_anisotropy"]),
                                       self.gpu.caps.software))
        if self._texture.anisotropy != aniso:
            self._texture.anisotropy = aniso
        return self._texture

    def plane_layout(self, frame):
        """(PlaneLayout, vertex buffer, index buffer, mask texture) over this frame's terrain."""
        terrain = frame.terrain
        key = (terrain, getattr(terrain, "revision", 0), float(self.params["fog.plane_height"]))
        return self._layout.get(key)

    def passes(self, frame, target) -> list[Pass]:
        gen = self.generator()
        if not (self.params["fog.plane"] and gen.on):
            return []
        return [Pass("fog.plane", lambda: self.draw_plane(frame, target, gen),
                     Stage.TRANSPARENT)]

    def draw_plane(self, frame, target, gen: fs.FogGenerator) -> None:
        layout, vbo, ibo, mask = self.plane_layout(frame)
        prog = self.program(PLANE)
        self.apply_params(prog)
        cam = frame.camera
        light = frame.main_light
        radiance = tuple(float(v) for v in light.radiance) if light is not None else (1, 1, 1)
        ambient = (tuple(float(v) for v in light.ambient)
                   if light is not None and light.ambient is not None else (0.0, 0.0, 0.0))
        direction = tuple(float(v) for v in light.direction) if light is not None else (0, 1, 0)
        x0, z0, x1, z1 = layout.rect
        prog.set_many({
            "uViewProj": cam.projection_matrix(frame.aspect) @ cam.view_matrix(),
            "uPlaneY": layout.y, "uScroll": tuple(float(v) for v in self.scroll),
            "uMaskRect": (x0, z0, 1.0 / max(x1 - x0, 1e-6), 1.0 / max(z1 - z0, 1e-6)),
            "uCutoff": 1.0 - gen.intensity, "uTime": float(frame.time),
            "uCameraPos": tuple(float(v) for v in cam.position), "uLightDir": direction,
            "uLightRadiance": radiance, "uAmbient": ambient,
            **fs.fog_uniforms(frame.fog, cam.position, cam.near, cam.far)})
        prog.bind_textures({"uFogTexture": self.texture(), "uGroundMask": mask})
        ctx = self.gpu.ctx
        target.use()
        fbo = getattr(target, "fbo", None)
        ctx.enable(moderngl.DEPTH_TEST | moderngl.BLEND)
        ctx.disable(moderngl.CULL_FACE)
        ctx.blend_func = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA,
                          moderngl.ZERO, moderngl.ONE)
        if fbo is not None:
            fbo.depth_mask = False
        try:
            prog.vao([(vbo, "2f", "in_position")], index_buffer=ibo).render(moderngl.TRIANGLES)
        finally:
            if fbo is not None:
                fbo.depth_mask = True
            ctx.blend_func = moderngl.DEFAULT_BLENDING
            ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)

    def release(self) -> None:
        self._texture = None
        super().release()
