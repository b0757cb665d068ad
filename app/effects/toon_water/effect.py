"""The toon village's water (spec/003 §2.10, the thesis's §7.2 ``Custom/Nature/Water``): the
stylised sea around the island. docs/theory/003-toon-village.md (§2.10) describes the method,
the document against the repository and what Natura takes; this module draws it.

One pass in the water stage, lit by the main directional light only:

* a plane at the terrain's sea level lifted by the tide, a polar grid of 14 doubling rings ×
  24 segments (648 triangles) for the rasteriser's depth precision near the camera: two
  triangles of several kilometres put the depth 1 cm off at 35 m on llvmpipe, a jagged
  shoreline;
* refraction by a grab pass (:mod:`.grab`), distorted by one generated, tileable normal map
  (``app.sim.toon_water.wave_normal_map``) sampled twice: crossing waves;
* the depth fog by ``toon_water.fog_method`` (``document``, ``repository``, or ``thickness``,
  the default and beyond the thesis), then the ``simple`` or ``complex`` water type, a toon
  highlight of the main light (beyond the thesis), and the scene's global fog once, per
  fragment (rings kilometres wide cannot carry the thesis's per-vertex factor).

Seen from below (beyond the thesis): ``glsl/toon_water/underwater.frag`` tints what the camera
sees through the water, and the surface shows the refraction of what is above.

Slots: ``image`` (required: the grab), ``environment``, ``main_light``, ``fog`` and ``terrain``
(its ``sea_level``); their fallbacks are in docs/architecture.md's table.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ...frame import Stage
from ...gpu.cache import memoised
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...params import Inspector, Param
from ...render.environment import flat_environment
from ...sim import toon_water as tw
from ...sim.daynight import Light
from ...sim.fog import fog_uniforms
from ..base import Effect, Pass
from .grab import GrabPass


def _surface(name: str, complex_: int, ramp: int) -> ProgramSpec:
    return ProgramSpec(f"toon_water/{name}", vert="toon_water/water.vert",
                       frag="toon_water/water.frag",
                       defines=(("WATER_COMPLEX", complex_), ("WATER_FRESNEL_RAMP", ramp)))


SIMPLE = _surface("water_simple", 0, 1)
COMPLEX = _surface("water_complex", 1, 1)
COMPLEX_POW5 = _surface("water_complex_pow5", 1, 0)
UNDERWATER = fullscreen("toon_water/underwater")

TYPES = ("simple", "complex")
FRESNEL = ("ramp", "pow5")
#: the main light when the frame has none: white, 55° up, toward the south-east
FALLBACK_AMBIENT = (0.25, 0.3, 0.38)
FALLBACK_LIGHT = Light("fallback", np.array([0.47, 0.819, 0.33]) / np.linalg.norm(
    [0.47, 0.819, 0.33]), (1.0, 1.0, 1.0), 1.0, FALLBACK_AMBIENT)
#: the environment when the frame has none: a flat sky blue (linear)
FALLBACK_SKY = (0.35, 0.5, 0.7, 1.0)


class ToonWater(Effect):
    name = "toon_water"
    title = "Stylised water"
    spec = "spec/003"
    programs = (SIMPLE, COMPLEX, COMPLEX_POW5, UNDERWATER)
    stages = (Stage.WATER,)
    consumes = {"image": "required", "environment": "optional", "main_light": "optional",
                "fog": "optional", "terrain": "optional"}

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        return {"toon water texture anisotropy": "1× (software renderer)" if caps.software
                else "8×"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/003 §2.10"
        return [
            Param("toon_water.type", "complex", doc="Water Type: simple (refraction, flat colour "
                  "and v·n in 3 bands) or complex (toon reflection and refraction by the "
                  "Fresnel ramp)", kind="choice", choices=TYPES, section=s),
            Param("toon_water.fog_method", "thickness", doc="the depth fog: document (the raw "
                  "depth value), repository (Linear01Depth·intensity·31) or thickness (the "
                  "water's thickness along the ray, exponential in metres; beyond the thesis)",
                  kind="choice", choices=tw.FOG_METHODS, section=s),
            Param("toon_water.fresnel", "ramp", doc="Complex: the reflectance from the ramp "
                  "texture baked from 0.018 + 0.982·(1 − u)^5 (the thesis's, to avoid the 5th "
                  "power) or the power itself", kind="choice", choices=FRESNEL, section=s),
        ]

    #: what each Water Type teaches (toon_water.type)
    lesson_param = "toon_water.type"
    LESSONS = {
        "simple": "Simple water (spec/003 §2.10): refraction only — a grab of what lies under "
                  "the water, distorted by scrolling wave normals — over a flat colour, with "
                  "v·n discretised into 3 bands; no reflection, so it is cheap.",
        "complex": "Complex water (spec/003 §2.10): lerp(refraction, reflection, F), the "
                   "probe's reflection discretised by Toon Value and F read "
                   "from a ramp texture baked from Schlick's 0.018 + 0.982·(1 − u)^5.",
    }

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self._grab = GrabPass(gpu, self.name)
        self._textures: dict[str, moderngl.Texture] = {}
        self._plane = None
        self._flat_env = None
        self.time = 0.0
        self.sea_level = 0.0
        self.level = 0.0  # the plane's height this frame (tide included)
        self.camera_height = 0.0
        self.underwater = False

    def wave_normals(self) -> moderngl.Texture:
        """The tileable wave normal map (generated once), mipmapped and repeating."""
        if "normals" not in self._textures:
            data = memoised(tw.wave_normal_map)
            size = data.shape[0]
            tex = self.gpu.texture(self.name, "wave normals", (size, size), 4,
                                   data=np.ascontiguousarray(data).tobytes(), dtype="f4",
                                   repeat=True)
            tex.build_mipmaps()
            tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
            tex.anisotropy = 1.0 if self.gpu.caps.software else 8.0
            self._textures["normals"] = tex
        return self._textures["normals"]

    def fresnel_ramp(self) -> moderngl.Texture:
        """The Fresnel ramp texture (spec/003 eq. 7.22 baked, the thesis's Fig. 110), float."""
        if "ramp" not in self._textures:
            data = tw.fresnel_ramp()
            tex = self.gpu.texture(self.name, "fresnel ramp", (len(data), 1), 1,
                                   data=data.tobytes(), dtype="f4")
            self._textures["ramp"] = tex
        return self._textures["ramp"]

    def _plane_buffers(self):
        """The plane's polar grid (``app.sim.toon_water.plane_mesh``): vertices and indices."""
        if self._plane is None:
            vertices, indices = tw.plane_mesh()
            self._plane = (self.gpu.buffer(self.name, "plane vertices", vertices.tobytes()),
                           self.gpu.buffer(self.name, "plane indices", indices.tobytes()))
        return self._plane

    def environment(self, frame):
        """The sky's probe without the sun disk (the highlight draws the sun), or a flat sky
        colour when the frame has no environment."""
        if frame.environment is not None:
            return frame.environment.cubemap(sun=False)
        if self._flat_env is None:
            self._flat_env = flat_environment(self.gpu, self.name, FALLBACK_SKY)
        return self._flat_env

    @staticmethod
    def light(frame) -> Light:
        return frame.main_light if frame.main_light is not None else FALLBACK_LIGHT

    def update(self, frame, dt: float) -> None:
        self.time = frame.time
        self.sea_level = float(frame.terrain.sea_level) if frame.terrain is not None else 0.0
        self.level = float(tw.tide_level(self.sea_level, self.params["toon_water.tide_height"],
                                         frame.time))
        self.camera_height = float(frame.camera.position[1])
        self.underwater = self.camera_height < self.level

    def surface_spec(self) -> ProgramSpec:
        """The surface program of ``toon_water.type`` and ``toon_water.fresnel``."""
        p = self.params
        if p["toon_water.type"] == "simple":
            return SIMPLE
        return COMPLEX if p["toon_water.fresnel"] == "ramp" else COMPLEX_POW5

    @staticmethod
    def corner_reach(frame) -> float:
        """How far the frustum's corner rays reach per metre of view depth:
        sqrt(1 + tan²(fov/2)·(1 + aspect²))."""
        t = math.tan(math.radians(frame.camera.fov) * 0.5)
        return math.sqrt(1.0 + t * t * (1.0 + frame.aspect ** 2))

    def near_surface(self, frame, level: float) -> bool:
        """Whether any pixel's view ray can start under the water: the camera below the level
        plus the reach of its near plane's corners."""
        cam = frame.camera
        return cam.position[1] < level + cam.near * self.corner_reach(frame)

    def _common(self, prog, frame, target) -> None:
        cam = frame.camera
        light = self.light(frame)
        ambient = light.ambient if light.ambient is not None else FALLBACK_AMBIENT
        self.apply_params(prog)
        prog.set_many({
            "uCameraPos": tuple(cam.position), "uViewport": tuple(float(s) for s in target.size),
            "uNearFar": (float(cam.near), float(cam.far)), "uTime": float(frame.time),
            "uSeaLevel": self.sea_level, "uLightDir": tuple(float(v) for v in light.direction),
            "uLightRadiance": tuple(float(v) for v in light.radiance),
            "uAmbient": tuple(float(v) for v in ambient),
            "uFogMethod": tw.FOG_METHODS.index(self.params["toon_water.fog_method"])})

    def draw(self, frame, target) -> None:
        ctx = self.gpu.ctx
        image = frame.image_for(target)
        colour, depth = self._grab.of(image.target)
        cam = frame.camera
        level = float(tw.tide_level(self.sea_level, self.params["toon_water.tide_height"],
                                    frame.time))
        target.use()
        if self.near_surface(frame, level):
            under = self.program(UNDERWATER)
            self._common(under, frame, target)
            under.set_many(frame.camera_uniforms())
            under.bind_textures({"uSceneDepth": depth})
            ctx.disable(moderngl.DEPTH_TEST)
            draw_fullscreen(under, blend=(moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA,
                                          moderngl.ZERO, moderngl.ONE))
        prog = self.program(self.surface_spec())
        self._common(prog, frame, target)
        prog.set_many(fog_uniforms(frame.fog, cam.position, cam.near, cam.far))
        prog.set_many({"uFogPerPixel": True,  # rings kilometres wide cannot carry it per vertex
                       "uViewProjRel": cam.view_projection_relative(frame.aspect),
                       # the plane reaches the far plane's corners in every direction
                       "uExtent": float(max(cam.far, 1.0) * self.corner_reach(frame))})
        prog.bind_textures({"uGrab": colour, "uSceneDepth": depth,
                            "uWaveNormals": self.wave_normals(),
                            "uFresnelRamp": self.fresnel_ramp(),
                            "uEnvironment": self.environment(frame)})
        ctx.enable(moderngl.DEPTH_TEST)  # against the image, writing its own depth
        ctx.depth_func = "<"
        ctx.disable(moderngl.CULL_FACE)  # seen from below too
        ctx.disable(moderngl.BLEND)  # the refraction already holds what is behind
        vertices, indices = self._plane_buffers()
        try:
            prog.vao([(vertices, "2f", "in_xz")], indices).render(moderngl.TRIANGLES)
        finally:
            ctx.disable(moderngl.DEPTH_TEST)

    def passes(self, frame, target) -> list[Pass]:
        return [Pass(self.name, lambda: self.draw(frame, target), Stage.WATER)]

    #: the inspector's popups: the thesis's water material (spec/003 Fig. 115), then ours
    INSPECTOR = {
        "Water": ["toon_water.type", "toon_water.color", "toon_water.wave_intensity",
                  "toon_water.wave_scale", "toon_water.water_speed", "toon_water.tide_height",
                  "toon_water.wave_tile"],
        "Depth fog": ["toon_water.depth_fog", "toon_water.water_fog_intensity",
                      "toon_water.fog_method", "toon_water.refraction"],
        "Toon reflection": ["toon_water.toon_value", "toon_water.fresnel",
                            "toon_water.reflection_tint", "toon_water.band_strength",
                            "toon_water.highlight", "toon_water.highlight_exponent"],
        "Debug": ["toon_water.flip_y", "toon_water.output"],
    }

    def panel_items(self) -> list:
        """The water's material inspector (the thesis's Custom/Nature/Water, Fig. 115) with the
        generated wave normal map and the Fresnel ramp as thumbnails."""
        popups = {title: [n for n in names if n in self.params]
                  for title, names in self.INSPECTOR.items()}
        textures = {label: self._textures[key] for label, key in (
            ("wave normals", "normals"), ("Fresnel ramp", "ramp")) if key in self._textures}
        return [Inspector("Water (Custom/Nature/Water, spec/003 §2.10)",
                          {t: n for t, n in popups.items() if n}, textures)]

    def panel_notes(self) -> list[str]:
        p = self.params
        lines = [f"water at {self.level:+.2f} m (sea level {self.sea_level:+.2f}, tide "
                 f"{p['toon_water.tide_height']:.2f}·sin t)"
                 + ("; camera under the water" if self.underwater else "")]
        if p["toon_water.type"] == "complex":
            lines.append("Fresnel: " + (f"ramp texture, {tw.RAMP_WIDTH} texels"
                                        if p["toon_water.fresnel"] == "ramp"
                                        else "0.018 + 0.982·(1 − u)^5 per pixel"))
        return lines

    def release(self) -> None:
        self._grab.release()
        super().release()
        self._textures = {}
        self._plane = None
        self._flat_env = None
