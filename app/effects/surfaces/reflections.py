"""Reflection probes of the surfaces lab (spec/003 §2.5 reflections, §2.6 metallic vs
dielectric): a cubemap captured from a point of the room, its mips (the blur of
``SampleProbe``), and the physically based reference — a GGX-prefiltered cube (one level per
perceptual roughness, importance-sampled, Karis 2013) with the split-sum BRDF LUT — plus the
recreated Unity NHxRoughness LUT of the thesis's specular. GLSL functions in
``glsl/surfaces/reflection.glsl`` (numpy twin ``app/sim/reflections.py``).

API: ``ReflectionProbe(gpu, owner, params)``; ``update(key, draw_scene, position, box_min,
box_max)`` in the environment stage; ``bind(prog, extra_textures)`` before drawing a reflective
surface. ``draw_scene(view, proj, face_fbo)`` is the caller's: it draws the scene (what the
probe must see) with the given 4×4 numpy matrices (world → view, view → clip; ``proj @ view``)
into ``face_fbo`` — a moderngl framebuffer (RGBA16F colour + depth, size²), already bound,
cleared to black and depth 1, its viewport set, depth test on. The six faces are captured in GL
order +X, −X, +Y, −Y, +Z, −Z with the standard orientation (forward, up) = (+x, −y), (−x, −y),
(+y, +z), (−y, −z), (+z, −y), (−z, −y), 90° square frusta (``app.sim.reflections.cube_view``,
``cube_projection``); each rendered image is stored as it is (GL row 0 = the face's t = 0 row),
which is what ``glsl/common/cubemap.glsl`` and ``samplerCube`` expect.

The capture runs only when ``key`` (any ==-comparable value the caller builds from what the
probe shows), the position, the box or ``surfaces.probe_size`` changed: ``captures`` counts
them. Mips are rebuilt after each capture; the prefiltered cube after each capture or a change
of ``surfaces.prefilter_samples``; the BRDF LUT and the NHxRoughness LUT once.

``bind(program, extra)`` binds, in one ``Program.bind_textures`` call (so the units of the
caller's own textures, passed as ``extra``, do not collide): ``uProbe`` (the capture, trilinear),
``uProbePrefiltered``, ``uBrdfLut``, ``uNhxLut``; and sets ``uProbePos``, ``uProbeBoxMin``,
``uProbeBoxMax``, ``uProbeSphereRadius``, ``uProbeMips`` (levels of ``uProbe``),
``uPrefilteredMips`` (levels of ``uProbePrefiltered``), ``uReflection`` (the mode code of
``surfaces.reflection``) and ``uSpecularModel`` (0 thesis, 1 ggx).
"""

from __future__ import annotations

import math
import time
from typing import Any, Callable

import moderngl
import numpy as np

from ...errors import ParamError
from ...gpu.programs import draw_fullscreen, fullscreen
from ...params import Param
from ...sim import reflections as rf
from ...sim import surfaces_scene as ss

PREFILTER = fullscreen("surfaces/prefilter_ggx")
BRDF_LUT = fullscreen("surfaces/brdf_lut")
#: the tests' and bench's position-coded scene and GLSL probe (not drawn by the effect)
PROBE_SCENE = "surfaces/probe_scene"
PROBE_EVAL = "surfaces/probe_reflection_eval"
PROGRAMS = (PREFILTER, BRDF_LUT)

SPECULAR_MODELS = ("thesis", "ggx")
#: the prefiltered cube's face size at most (its levels: this, /2, … down to 8 or 6 levels)
PREFILTER_SIZE = 64
PREFILTER_LEVELS = 6
BRDF_LUT_SIZE = 64
BRDF_LUT_SAMPLES = 256
NHX_LUT_SIZE = 64


def reflection_params() -> list[Param]:
    """The Python parameters of the reflection probe (group ``surfaces``)."""
    s5, s6 = "spec/003 §2.5", "spec/003 §2.6"
    return [
        Param("surfaces.reflection", "box", doc="how the probe's cubemap is looked up: "
              "none; cube (the reflected direction as it is); box (box projection, "
              "spec/003 eq. 5.1 with d of spec/003 eq. 5.4); approximation (quadratic "
              "stretch toward the probe's sphere, spec/003 eq. 5.9); perfect (ray–sphere "
              "intersection, spec/003 eq. 5.10 to spec/003 eq. 5.17)", kind="choice",
              choices=rf.MODES, section=s5),
        Param("surfaces.probe_size", 128, 64, 512, "reflection probe face size (texels)",
              kind="int", section=s5),
        Param("surfaces.probe_sphere_radius", 0.0, 0.0, 50.0, "radius of the probe's sphere "
              "for the approximation and perfect modes (0: the distance from the probe to the "
              "room's farthest corner, so the sphere holds the room)", step=0.05, unit="m",
              section=s5),
        Param("surfaces.specular_model", "thesis", doc="thesis: diffuse lerped with the probe "
              "by weight = 0.25·smoothness + 0.75·metallic (spec/003 eq. 5.18), the NHxRoughness "
              "specular tinted lerp(light, albedo, metallic); ggx: the split-sum prefiltered "
              "GGX reference (Karis 2013)", kind="choice", choices=SPECULAR_MODELS,
              section=s6),
        Param("surfaces.prefilter_samples", 64, 8, 1024, "GGX importance samples per texel "
              "of the prefiltered probe", kind="int", section=s6),
    ]


class ReflectionProbe:
    """One reflection probe (module docstring); GL resources under ``owner``."""

    programs = PROGRAMS

    def __init__(self, gpu, owner: str, params: Any = None) -> None:
        self.gpu = gpu
        self.owner = owner
        self.params = params
        self.cube: moderngl.TextureCube | None = None
        self.prefiltered: moderngl.TextureCube | None = None
        self.brdf: moderngl.Texture | None = None
        self.nhx: moderngl.Texture | None = None
        self._face: tuple | None = None  # (size, colour, depth, fbo)
        self._key: Any = None
        self._prefilter_key: Any = None
        self.position = np.zeros(3)
        self.box_min = np.full(3, -1.0)
        self.box_max = np.full(3, 1.0)
        #: how many captures / prefilter builds ran (tests check nothing re-renders idly)
        self.captures = 0
        self.prefilters = 0
        #: wall ms of the last capture (six faces + mips) and of the last prefilter
        self.capture_ms = 0.0
        self.prefilter_ms = 0.0

    @classmethod
    def python_params(cls) -> list[Param]:
        return reflection_params()

    def _param(self, name: str, default):
        if self.params is None:
            return default
        try:
            return self.params[name]
        except (KeyError, ParamError):  # a dict, or a scene's ParamSet without the parameter
            return default

    @property
    def size(self) -> int:
        return int(self._param("surfaces.probe_size", 128))

    @property
    def mode(self) -> str:
        return str(self._param("surfaces.reflection", "box"))

    @property
    def sphere_radius(self) -> float:
        r = float(self._param("surfaces.probe_sphere_radius", 0.0))
        return r if r > 0 else rf.farthest_corner(self.position, self.box_min, self.box_max)

    @property
    def mips(self) -> int:
        """Mip levels of the capture cube."""
        return int(math.log2(self.cube.size[0])) + 1 if self.cube is not None else 1

    def update(self, key: Any, draw_scene: Callable[[np.ndarray, np.ndarray, Any], None],
               position, box_min, box_max) -> bool:
        """Capture the probe if ``key``, the position, the box or the size changed (and then
        the mips and the prefiltered cube); True when it captured."""
        position = np.asarray(position, float).reshape(3)
        box_min = np.asarray(box_min, float).reshape(3)
        box_max = np.asarray(box_max, float).reshape(3)
        if np.any(box_max <= box_min):
            raise ValueError(f"probe box {box_min.tolist()}–{box_max.tolist()}: allowed "
                             "box_min < box_max on every axis")
        size = self.size
        full = (key, tuple(position), tuple(box_min), tuple(box_max), size)
        captured = False
        with self.gpu.keep_framebuffer():
            self._luts()  # before the capture: its draws read the NHx LUT (``lighting``)
            if self.cube is None or full != self._key:
                self.position, self.box_min, self.box_max = position, box_min, box_max
                self._capture(draw_scene, size)
                self._key = full
                captured = True
            samples = int(self._param("surfaces.prefilter_samples", 64))
            if captured or self._prefilter_key != samples or self.prefiltered is None:
                self._prefilter(samples)
                self._prefilter_key = samples
        return captured

    def _face_target(self, size: int):
        if self._face is None or self._face[0] != size:
            self._free_face()
            colour = self.gpu.texture(self.owner, "probe face", (size, size), 4, dtype="f2")
            depth = self.gpu.depth_texture(self.owner, "probe face depth", (size, size))
            fbo = self.gpu.framebuffer(self.owner, "probe face", [colour], depth)
            self._face = (size, colour, depth, fbo)
        return self._face

    def _free_face(self) -> None:
        if self._face is not None:
            _, colour, depth, fbo = self._face
            self.gpu.free(fbo)
            self.gpu.free(colour)
            self.gpu.free(depth)
            self._face = None

    def _capture(self, draw_scene, size: int) -> None:
        ctx = self.gpu.ctx
        t0 = time.perf_counter()
        if self.cube is None or self.cube.size[0] != size:
            if self.cube is not None:
                self.gpu.free(self.cube)
            self.cube = self.gpu.texture_cube(self.owner, "reflection probe", size, dtype="f2")
            self.cube.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        _, _, _, fbo = self._face_target(size)
        proj = rf.cube_projection()
        for face in range(6):
            fbo.use()
            ctx.viewport = (0, 0, size, size)
            fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
            ctx.enable(moderngl.DEPTH_TEST)
            draw_scene(rf.cube_view(face, self.position), proj, fbo)
            fbo.use()  # the caller's drawing may have bound another framebuffer
            self.gpu.copy_to_cube_face(self.cube, face, 0, size)
        ctx.disable(moderngl.DEPTH_TEST)
        if self.captures == 0:  # the first capture: levels a session that saw the same left
            self.cube.build_mipmaps()
        else:
            self.cube.build_mipmaps()
        ctx.finish()
        self.capture_ms = (time.perf_counter() - t0) * 1e3
        self.captures += 1

    def _prefilter(self, samples: int) -> None:
        assert self.cube is not None
        ctx = self.gpu.ctx
        t0 = time.perf_counter()
        base = min(PREFILTER_SIZE, self.cube.size[0])
        if self.prefiltered is None or self.prefiltered.size[0] != base:
            if self.prefiltered is not None:
                self.gpu.free(self.prefiltered)
            self.prefiltered = self.gpu.texture_cube(self.owner, "prefiltered probe", base,
                                                     dtype="f2")
            self.prefiltered.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
            self.prefiltered.build_mipmaps(0, PREFILTER_LEVELS - 1)  # allocates the levels
        prog = self.gpu.program(self.owner, PREFILTER)
        prog.bind_textures({"uSource": self.cube})
        prog.set_many({"uSamples": int(samples), "uSourceSize": float(self.cube.size[0]),
                       "uSourceMips": float(self.mips)})
        ctx.disable(moderngl.DEPTH_TEST)
        for level in range(PREFILTER_LEVELS):
            s = max(base >> level, 1)
            with self.gpu.scratch_target(self.owner, "prefilter level", (s, s), dtype="f2",
                                         depth=False) as target:
                prog.set("uRoughness", level / (PREFILTER_LEVELS - 1))
                for face in range(6):
                    target.use()
                    ctx.viewport = (0, 0, s, s)
                    prog.set("uFace", face)
                    draw_fullscreen(prog)
                    self.gpu.copy_to_cube_face(self.prefiltered, face, level, s)
        ctx.finish()
        self.prefilter_ms = (time.perf_counter() - t0) * 1e3
        self.prefilters += 1

    def _luts(self) -> None:
        if self.nhx is None:
            lut = rf.nhx_roughness_lut(NHX_LUT_SIZE)
            self.nhx = self.gpu.texture(self.owner, "NHxRoughness LUT", lut.shape[::-1], 1,
                                        lut.tobytes())
        if self.brdf is None:
            ctx = self.gpu.ctx
            with self.gpu.scratch_target(self.owner, "BRDF LUT", (BRDF_LUT_SIZE,) * 2,
                                         depth=False) as target:
                prog = self.gpu.program(self.owner, BRDF_LUT)
                prog.set("uSamples", BRDF_LUT_SAMPLES)
                target.use()
                ctx.viewport = (0, 0, BRDF_LUT_SIZE, BRDF_LUT_SIZE)
                ctx.disable(moderngl.DEPTH_TEST)
                draw_fullscreen(prog)
                data = target.fbo.read(components=2, dtype="f4")
            self.brdf = self.gpu.texture(self.owner, "BRDF LUT", (BRDF_LUT_SIZE,) * 2, 2, data)

    def lighting(self) -> tuple[dict[str, Any], dict[str, Any]]:
        """(textures, uniforms) every draw of the surface program needs, the probe's own
        capture included: the NHxRoughness LUT and the specular model the lights' specular
        reads (a capture without them read whatever texture unit its sampler was last left
        on: the first capture of a session differed from the next ones)."""
        self._luts()
        return ({"uNhxLut": self.nhx},
                {"uSpecularModel": SPECULAR_MODELS.index(
                    str(self._param("surfaces.specular_model", "thesis")))})

    def textures(self) -> dict[str, Any]:
        return {"uProbe": self.cube, "uProbePrefiltered": self.prefiltered,
                "uBrdfLut": self.brdf, "uNhxLut": self.nhx}

    def uniforms(self) -> dict[str, Any]:
        return {"uProbePos": tuple(self.position), "uProbeBoxMin": tuple(self.box_min),
                "uProbeBoxMax": tuple(self.box_max),
                "uProbeSphereRadius": float(self.sphere_radius),
                "uProbeMips": float(self.mips), "uPrefilteredMips": float(PREFILTER_LEVELS),
                "uReflection": rf.MODE_CODE[self.mode],
                "uSpecularModel": SPECULAR_MODELS.index(
                    str(self._param("surfaces.specular_model", "thesis")))}

    def bind(self, program, extra_textures: dict[str, Any] | None = None) -> None:
        """Bind the probe's textures (with the caller's ``extra_textures``, one unit each)
        and set its uniforms on ``program`` (an ``app.gpu.shaders.Program``)."""
        if self.cube is None:
            raise ValueError("ReflectionProbe.bind before update: allowed after the first "
                             "update(key, draw_scene, …)")
        program.bind_textures({**self.textures(), **(extra_textures or {})})
        program.set_many(self.uniforms())

    def release(self) -> None:
        self._free_face()
        for attr in ("cube", "prefiltered", "brdf", "nhx"):
            obj = getattr(self, attr)
            if obj is not None:
                self.gpu.free(obj)
                setattr(self, attr, None)
        self._key = self._prefilter_key = None


class PositionScene:
    """The probe test scene: meshes of ``app.sim.surfaces_scene`` (the room and the solids
    not in ``skip``) drawn with their world position as colour (``glsl/surfaces/probe_scene.frag``),
    so a capture tells where each texel's ray hit — or, with ``radiance``, each object's albedo
    on a checker under a glowing ceiling; ``draw`` is a ``draw_scene`` callback."""

    def __init__(self, gpu, owner: str, scene, skip: tuple[str, ...] = (),
                 solids: bool = True, radiance: bool = False) -> None:
        self.gpu = gpu
        self.radiance = radiance
        self.ceiling = float(scene.room.hi[1]) - 0.01
        self.prog = gpu.program(owner, PROBE_SCENE)
        objects = [scene.room] + ([o for o in scene.solids() if o.name not in skip]
                                  if solids else [])
        self.albedos = [tuple(o.albedo) for o in objects]
        self.vaos = []
        for obj in objects:
            m = ss.mesh(obj)
            vbo = gpu.buffer(owner, f"probe scene {m.name}", m.vertex_data(["position"]))
            ibo = gpu.buffer(owner, f"probe scene {m.name} indices",
                             np.ascontiguousarray(m.indices, dtype="i4").tobytes())
            self.vaos.append(self.prog.vao([(vbo, "3f", "in_position")], index_buffer=ibo))

    def draw(self, view: np.ndarray, proj: np.ndarray, fbo=None) -> None:
        self.prog.set_many({"uViewProj": proj @ view, "uColourMode": int(self.radiance),
                            "uCeiling": self.ceiling})
        for vao, albedo in zip(self.vaos, self.albedos):
            self.prog.set("uAlbedo", albedo)
            vao.render(moderngl.TRIANGLES)
