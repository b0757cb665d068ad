"""The surfaces lab (spec/003 §2.4–2.8): the room of :mod:`app.sim.surfaces_scene` — three test
spheres (a metal mirror, glass, a dielectric), two cylinders, an occluder slab over the floor, a
crate, and the alpha quads (fence, leaves, smoke, a blue α = 0.5 pane, two intersecting panes) —
lit by a sun (directional, cascaded map), a lamp (point light, cube map) and a spot light
(perspective map) from the shared shadow module (``app.render.shadow_maps``).

A frame, stage by stage:

1. shadow — the three lights' maps, re-rendered only when a light, the maps' own settings,
   the camera (for the cascades: when a snapped cascade moves) or the casters changed — never
   for a receiver's filter, taps or strength (``ShadowSettings.map_key``);
2. environment — the reflection probe's cubemap of the room from its centre (the room and the
   solids, drawn without reflections), re-rendered only when what it shows changed; its mips
   and the GGX-prefiltered copy (:mod:`.reflections`);
3. opaque — the room and the solids (``glsl/surfaces/surface.*``): diffuse and specular under
   the three lights with their shadows, the probe's reflection through ``surfaces.reflection``
   (cube, box projection, the quadratic-stretch or perfect-sphere correction), the metallic /
   dielectric weight of spec/003 eq. 5.18 or the split-sum GGX reference, and refraction with
   exact or Schlick Fresnel on the glass sphere;
4. transparent — the alpha quads in render-queue order (:mod:`.transparency`): cutout,
   alpha-to-coverage (on the lab's 4× MSAA target, ``surfaces.msaa``), sorted blending, weighted
   blended OIT or the depth-peeled reference; then the MSAA target resolves into the frame.

What a frame costs, and what it need not (measured in ``natura bench surfaces``'s speed
section): the opaque pass is drawn nearest solid first, the room last, so the depth test
rejects what a solid hides before it is shaded; it is one of twenty specialised programs
(``surface_spec``: the glass's branch, the other specular model, the debug views and the unused
shadow filters compiled out, the taps' loops of constant length); the shadows' PCF taps follow
``surfaces.shadow_taps`` (``auto``: 3 × 3 on a software renderer, the 5 × 5 reference on a
GPU); and ``surfaces.msaa=auto`` draws
without MSAA on a software renderer unless a quad uses alpha-to-coverage. Each is one switch
from the reference: ``surfaces.specialise=false``, ``surfaces.shadow_taps=full``,
``surfaces.msaa=4``.

``surfaces.failure`` reproduces each of the thesis's failures with one switch (the queue and
intersection failures of Figs. 44–46, shadow acne and Peter Panning of Figs. 86–87) by setting
the parameters that show it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import moderngl
import numpy as np

from ...frame import Stage
from ...gpu.cache import memoised
from ...gpu.programs import ProgramSpec
from ...params import Param
from ...render import shadows as shadow_module
from ...render.shadow_maps import CASTER, ShadowSet, receiver_variants
from ...sim import distortion, surfaces_scene
from ...sim.maths import direction
from ..base import Effect, Pass
from .reflections import ReflectionProbe
from .transparency import BLENDED as BLENDED_MODES
from .transparency import Transparency

SURFACE = ProgramSpec("surfaces/surface")
#: the room and the solids as the camera sees them (the probe on, no refraction), specialised
#: to each shadow filter and tap set (glsl/surfaces/surface.frag's header; Surfaces.surface_spec)
SURFACE_SCENE = tuple(v for model in (0, 1) for v in receiver_variants(ProgramSpec(
    "surfaces/surface", defines=(("SURFACE_SCENE", 1), ("SURFACE_SCENE_SPECULAR", model)))))
FORMAT = ("3f 3f 2f 4f", "in_position", "in_normal", "in_uv", "in_tangent")
CASTER_FORMAT = ("3f 3f 2f 16x", "in_position", "in_normal", "in_uv")
ATTRIBUTES = ("position", "normal", "uv", "tangent")
#: the lamp (point light) and the spot light of the lab
LAMP_POSITION = (-0.6, 2.3, 0.9)
#: the multisampled target's clear colour (the room hides it: the camera is inside)
CLEAR = (0.05, 0.06, 0.08, 1.0)
SPOT_POSITION = (1.2, 2.85, -0.4)
SPOT_TARGET = (0.3, 0.0, -2.2)

#: one switch per failure of the thesis: the parameters that show it (spec/003 §2.4, §2.8);
#: "none" puts them back to their defaults
FAILURES: dict[str, dict[str, object]] = {
    "none": {},
    # Fig. 44c: the blue α = 0.5 pane queued Geometry (2000, ZWrite on) before the cutout fence
    "queue_order": {"surfaces.blue_queue": "Geometry", "surfaces.transparency": "sorted"},
    # Fig. 45: intersecting blended panes sorted by their centres, ZWrite on
    "intersecting": {"surfaces.transparency": "sorted", "surfaces.zwrite_blended": True},
    # Fig. 46: the partial workaround, ZWrite off
    "zwrite_off": {"surfaces.transparency": "sorted", "surfaces.zwrite_blended": False},
    # Fig. 86 left: no bias — shadow acne
    "acne": {"surfaces.shadow_linear_bias": 0.0, "surfaces.shadow_normal_bias": 0.0},
    # Fig. 87: linear bias 0.6 — Peter Panning
    "peter_panning": {"surfaces.shadow_linear_bias": 0.6, "surfaces.shadow_normal_bias": 0.3},
}


#: where a user's ``--mesh`` stands: under the occluder slab (fitted to USER_SIZE, so it
#: clears the slab's underside at 1.15 m), casting and receiving shadows
USER_SPOT = (0.6, 0.0, -1.6)
USER_SIZE = 1.0


@dataclass(frozen=True)
class UserObject:
    """A user's mesh in the room (``natura … surfaces --mesh FILE``): a grey dielectric."""

    name: str = "user"
    albedo: tuple[float, float, float] = (0.62, 0.62, 0.64)


@dataclass
class WorkTarget:
    """Where the lab draws: the frame's own target, or its 4× multisampled twin (resolved into
    the frame at the end of the transparent stage). ``colour``/``color`` and ``depth`` are
    textures (multisampled when ``samples`` > 0)."""

    fbo: moderngl.Framebuffer
    colour: moderngl.Texture
    depth: moderngl.Texture
    size: tuple[int, int]
    samples: int = 0

    @property
    def color(self) -> moderngl.Texture:
        return self.colour

    def use(self) -> None:
        self.fbo.use()


class Surfaces(Effect):
    name = "surfaces"
    title = "Surfaces and shadows lab"
    spec = "spec/003"
    programs = (SURFACE, *SURFACE_SCENE, CASTER, *Transparency.programs,
                *ReflectionProbe.programs)
    stages = (Stage.SHADOW, Stage.ENVIRONMENT, Stage.OPAQUE, Stage.TRANSPARENT)
    produces = frozenset({"shadows"})

    @classmethod
    def python_params(cls) -> list[Param]:
        s1, s5, s7 = "spec/003 §1", "spec/003 §2.6", "spec/003 §2.7"
        own = [
            Param("surfaces.failure", "none", doc="reproduce one of the thesis's failures: the "
                  "blended pane queued before the cutout fence (Fig. 44c), intersecting blended "
                  "panes (Fig. 45), the ZWrite-off workaround (Fig. 46), shadow acne without bias "
                  "(Fig. 86), Peter Panning with linear bias 0.6 (Fig. 87)", kind="choice",
                  choices=tuple(FAILURES), section="spec/003 §4"),
            Param("surfaces.msaa", "auto", doc="samples of the lab's target: 4 for alpha-to-"
                  "coverage (spec/003 §2.4: AlphaToMask needs MSAA), 0 draws straight into the "
                  "frame; auto: 4 on a GPU or while a quad uses alpha-to-coverage, else 0 on a "
                  "software renderer (whose MSAA triples the lab's frame)", kind="choice",
                  choices=("auto", "0", "4"), section="spec/003 §2.4"),
            Param("surfaces.sun_elevation", 55.0, -90.0, 90.0, "the sun (directional light) "
                  "above the horizon", step=0.5, unit="°", section=s1),
            Param("surfaces.sun_azimuth", 150.0, 0.0, 360.0, "the sun's compass azimuth",
                  step=1.0, unit="°", section=s1),
            Param("surfaces.sun_intensity", 0.8, 0.0, 50.0, "the sun's irradiance on a surface "
                  "facing it (the room's roof lets it through: the walls cast no shadow)",
                  step=0.1, section=s1),
            Param("surfaces.ambient", 0.05, 0.0, 5.0, "ambient radiance", step=0.01, section=s1),
            Param("surfaces.lamp", True, doc="the lamp: a point light with a cube shadow map",
                  kind="bool", section="spec/003 §2.8"),
            Param("surfaces.lamp_intensity", 1.5, 0.0, 200.0, "the lamp's intensity", step=0.1,
                  section=s1),
            Param("surfaces.lamp_range", 6.0, 0.5, 50.0, "the lamp's range (its cube map "
                  "stores |l|/range)", step=0.1, unit="m", section="spec/003 §2.8"),
            Param("surfaces.spot", True, doc="the spot light: a perspective shadow map",
                  kind="bool", section="spec/003 §2.8"),
            Param("surfaces.spot_angle", 32.0, 1.0, 80.0, "the spot's half-angle (its inner "
                  "cone is 80 % of it)", step=0.5, unit="°", section="spec/003 §2.8"),
            Param("surfaces.spot_intensity", 4.0, 0.0, 500.0, "the spot's intensity",
                  step=0.5, section=s1),
            Param("surfaces.spot_range", 8.0, 0.5, 50.0, "the spot's range", step=0.1,
                  unit="m", section="spec/003 §2.8"),
            Param("surfaces.mirror_smoothness", 1.0, 0.0, 1.0, "the metal sphere's smoothness "
                  "(Fig. 63: 0.25, 0.5, 0.85, 1; blurs its reflection through the probe's mips)",
                  step=0.01, section=s5),
            Param("surfaces.mirror_metallic", 1.0, 0.0, 1.0, "the metal sphere's metallic",
                  step=0.01, section=s5),
            Param("surfaces.dielectric_smoothness", 0.5, 0.0, 1.0, "the red dielectric sphere's "
                  "smoothness", step=0.01, section=s5),
            Param("surfaces.dielectric_metallic", 0.0, 0.0, 1.0, "the red sphere's metallic",
                  step=0.01, section=s5),
            Param("surfaces.metallic_map", False, doc="the red sphere reads metallic (R) and "
                  "smoothness (G) from a texture (generated: four metal and dielectric bands "
                  "around it, smoothness rising from its foot to its top) instead of the sliders",
                  kind="bool", section=s5),
            Param("surfaces.floor_smoothness", 0.0, 0.0, 1.0, "the floor's smoothness: 1 with "
                  "metallic 1 makes it the flat mirror of Fig. 53 (the box probe's cube shape)",
                  step=0.01, section="spec/003 §2.5"),
            Param("surfaces.floor_metallic", 0.0, 0.0, 1.0, "the floor's metallic", step=0.01,
                  section="spec/003 §2.5"),
            Param("surfaces.n1", 1.0, 1.0, 3.0, "N1: the index of refraction outside the glass "
                  "sphere (usually 1)", step=0.01, section=s7),
            Param("surfaces.n2", 1.52, 1.0, 3.0, "N2: the glass sphere's index (Fig. 69: 1, "
                  "1.15, 1.31, 2.42)", step=0.01, section=s7),
            Param("surfaces.fresnel", "exact", doc="reflectance of the glass sphere: exact "
                  "Fresnel (R = ½(Rs + Rp)) or Schlick's approximation", kind="choice",
                  choices=("exact", "schlick"), section=s7),
            Param("surfaces.transparency_lod", 0.569, 0.0, 1.0, "Transparency of the glass "
                  "(lower is more opaque, through the probe's mip level; 0.569 in Fig. 68)",
                  step=0.001, section=s7),
            Param("surfaces.glass_smoothness", 1.0, 0.0, 1.0, "the glass's smoothness: blurs "
                  "its reflection and scales the distortion", step=0.01, section=s7),
            Param("surfaces.distortion", 0.0, 0.0, 1.0, "strength of the distortion texture "
                  "(a bump map) on the glass", step=0.01, section=s7),
            Param("surfaces.interfaces", 2, 1, 2, "refraction through the glass: 1 interface "
                  "(the thesis: refract once and look the probe up) or 2 (in and out of the "
                  "sphere)", kind="int", section=s7),
            Param("surfaces.specialise", True, doc="compile the surface program for each draw's "
                  "switches (lights, probe, material, reflection mode, shadow filters) instead of "
                  "branching on uniforms: the same image; a software rasteriser runs both sides "
                  "of every branch, so off shows what the branches cost", kind="bool",
                  section="spec/003 §2.8"),
            Param("surfaces.debug", "none", doc="a debug view: the cascade index, the sun's "
                  "shadow alone, the reflection direction", kind="choice",
                  choices=("none", "cascades", "shadow", "reflection"), section="spec/003 §2.8"),
        ]
        return (own + _lab_shadow_params() + Transparency.python_params()
                + ReflectionProbe.python_params())

    #: what each of the thesis's failures teaches (surfaces.failure)
    lesson_param = "surfaces.failure"
    LESSONS = {
        "none": "No failure shown (spec/003 §4): surfaces.failure reproduces the thesis's "
                "failures — queue order, intersecting panes, ZWrite off, shadow acne, Peter "
                "Panning — each with the switch that shows it.",
        "queue_order": "Queue order (spec/003 §2.4, Fig. 44c): the blue α = 0.5 pane queued "
                       "as Geometry draws before the cut-out fence behind it and writes depth, "
                       "so the fence vanishes behind it; blended objects go after AlphaTest.",
        "intersecting": "Intersecting blended panes (spec/003 §2.4, Fig. 45): sorting by "
                        "object centre cannot order two panes that cross, so one hides part of "
                        "the other; the sort is per object, not per pixel.",
        "zwrite_off": "ZWrite off (spec/003 §2.4, Fig. 46): the blended panes no longer hide "
                      "each other, but their order is still wrong where they cross; the thesis "
                      "accepts it only for distant objects.",
        "acne": "Shadow acne (spec/003 §2.8, Fig. 86): without a bias a surface shadows itself "
                "in stripes wherever its depth and the shadow map's differ by less than the "
                "map's precision.",
        "peter_panning": "Peter Panning (spec/003 §2.8, Fig. 87): a linear bias of 0.6 pushes "
                         "the shadow off its caster, so objects seem to float; the thesis "
                         "balances a normal 0.3 with a linear 0.01.",
    }

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.layout = surfaces_scene.default_scene()
        self._meshes: dict[str, tuple] = {}
        self._textures: dict[str, moderngl.Texture] = {}
        self._bounds: dict[str, tuple] = {}  # name → (its vertex buffer, lowest, highest)
        #: the sun's (cascaded), the lamp's (point) and the spot's maps: the shared module
        self.shadows = ShadowSet(gpu, self.name)
        self.probe = ReflectionProbe(gpu, self.name, params)
        self.transparency = Transparency(gpu, self.name, params)
        self._msaa = self.keyed(self._make_msaa, release=self._free_msaa)
        self._failure_applied = "none"
        self.user_mesh = None
        self._user_revision = 0
        self._camera_pos: tuple = self.layout.probe_position
        self.time = 0.0

    def set_user_mesh(self, mesh):
        """A user's own mesh (``--mesh FILE``, loaded by app.sim.mesh_files), fitted to
        :data:`USER_SIZE` and stood at :data:`USER_SPOT` among the solids: it casts and
        receives shadows and shows in the probe (the ray-cast references do not know it)."""
        from ...sim.lab_meshes import transformed
        from ...sim.mesh_files import fit

        fitted = transformed(fit(mesh, size=USER_SIZE), 1.0, USER_SPOT)
        held = self._meshes.pop("user", None)
        if held is not None:
            for obj in held[:2]:
                self.gpu.free(obj)
        self.user_mesh = fitted
        self._user_revision += 1
        return fitted

    def solids(self) -> list:
        """The solids drawn and casting: the scene's, and the user's mesh when there is one."""
        return [*self.layout.solids(), *([UserObject()] if self.user_mesh is not None else [])]

    def _mesh(self, obj):
        """(vertex buffer, index buffer, LabMesh) of a primitive of the scene, made once."""
        name = "room" if isinstance(obj, surfaces_scene.Room) else obj.name
        if name not in self._meshes:
            mesh = (self.user_mesh if isinstance(obj, UserObject)
                    else surfaces_scene.mesh(obj))
            if mesh is None:
                raise ValueError(f"surfaces: no mesh for {name!r}: allowed a scene primitive "
                                 "or a loaded user mesh")
            vbo = self.gpu.buffer(self.name, f"{name} vertices", mesh.vertex_data(ATTRIBUTES))
            ibo = self.gpu.buffer(self.name, f"{name} indices", mesh.index_data())
            self._meshes[name] = (vbo, ibo, mesh)
        return self._meshes[name]

    def _texture(self, key: str, make, repeat: bool = True) -> moderngl.Texture:
        if key not in self._textures:
            tex = self.gpu.array_texture(self.name, key, np.asarray(make(), np.float32), repeat)
            tex.build_mipmaps()
            tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
            self._textures[key] = tex
        return self._textures[key]

    def alpha_texture(self, kind: str) -> moderngl.Texture:
        return self._texture(f"alpha {kind}",
                             lambda: memoised(surfaces_scene.alpha_texture, kind, 256),
                             repeat=False)

    def _make_msaa(self, key):
        size, samples = key
        colour = self.gpu.texture(self.name, "msaa colour", size, 4, dtype="f2", samples=samples)
        depth = self.gpu.depth_texture(self.name, "msaa depth", size, samples=samples)
        fbo = self.gpu.framebuffer(self.name, "msaa", [colour], depth)
        return WorkTarget(fbo, colour, depth, size, samples)

    def _free_msaa(self, work: WorkTarget) -> None:
        for obj in (work.fbo, work.colour, work.depth):
            self.gpu.free(obj)

    def samples(self) -> int:
        """The lab's MSAA samples: ``surfaces.msaa``, with ``auto`` resolved — 4 on a GPU or
        when a quad is drawn with alpha-to-coverage (a mode or ``surfaces.a2c`` on the cut-out
        quads), else 0 on a software renderer (``Caps.software``)."""
        chosen = str(self.params["surfaces.msaa"])
        if chosen != "auto":
            return int(chosen)
        p = self.params
        modes = [str(p.get(f"surfaces.{q.name.split('_')[0]}_mode", "blend"))
                 for q in self.layout.quads]
        coverage = "alpha-to-coverage" in modes or (bool(p["surfaces.a2c"]) and "cutout" in modes)
        return 4 if coverage or not self.gpu.caps.software else 0

    def work_target(self, target) -> WorkTarget:
        samples = self.samples()
        if samples > 0:
            return self._msaa.get((tuple(target.size), samples))
        return WorkTarget(target.fbo, target.color, target.depth, tuple(target.size), 0)

    def sun_direction(self) -> np.ndarray:
        """Unit vector toward the sun (compass azimuth from −z toward +x)."""
        return direction(self.params["surfaces.sun_elevation"], self.params["surfaces.sun_azimuth"])

    def spot_axis(self) -> np.ndarray:
        d = np.subtract(SPOT_TARGET, SPOT_POSITION)
        return d / np.linalg.norm(d)

    def update(self, frame, dt: float) -> None:
        self.time = frame.time
        self._apply_failure()

    def _apply_failure(self) -> None:
        """``surfaces.failure``: set the parameters that show it (once, when it changes); back
        to none, the ones the previous failure set return to their defaults."""
        chosen = self.params["surfaces.failure"]
        if chosen == self._failure_applied:
            return
        for name in FAILURES.get(self._failure_applied, {}):
            if name in self.params:
                self.params.set(name, self.params.spec(name).default)
        for name, value in FAILURES.get(chosen, {}).items():
            if name in self.params:
                self.params.set(name, value)
        self._failure_applied = chosen

    def caster_mode(self, quad) -> int:
        """The caster's alpha mode of ``quad`` (shadow_caster.frag: 0 opaque, 1 cut out, 2
        dithered), from how the quad is drawn: an opaque quad casts an ordinary shadow, a
        cut-out one (cutout, alpha test, alpha-to-coverage) a cut-out shadow, and only a
        semi-transparent one — blended, with an alpha below 1 — asks for the dithered shadow
        (``surfaces.shadow_dithered``; off, it casts a solid one, the thesis's failure)."""
        mode = str(self.params.get(f"surfaces.{quad.name.split('_')[0]}_mode", "blend"))
        if mode == "opaque":
            return 0
        if mode not in BLENDED_MODES or quad.alpha in ("fence", "leaves", "gradient"):
            return 1
        return 2 if self.params["surfaces.shadow_dithered"] else 0

    def casters(self, prog) -> None:
        """Draw every shadow caster with the shadow module's caster program ``prog``: the
        solids opaque, each quad as :meth:`caster_mode` says — the fence and the leaves cut
        out, the smoke and the blended panes dithered (``surfaces.shadow_dithered``) or solid.
        The room casts nothing (its roof lets the sun in)."""
        cutoff = float(self.params["surfaces.cutoff"])
        white = self.alpha_texture("solid")
        for obj in self.solids():
            vbo, ibo, _ = self._mesh(obj)
            prog.set_many({"uAlphaMode": 0, "uOpacity": 1.0, "uCutoff": cutoff})
            prog.bind_textures({"uAlphaTex": white})
            prog.vao([(vbo, *CASTER_FORMAT)], ibo).render(moderngl.TRIANGLES)
        for quad in self.layout.quads:
            vbo, ibo, _ = self._mesh(quad)
            mode = self.caster_mode(quad)
            prog.set_many({"uAlphaMode": mode, "uOpacity": float(quad.opacity),
                           "uCutoff": cutoff})
            prog.bind_textures({"uAlphaTex": self.alpha_texture(quad.alpha)})
            prog.vao([(vbo, *CASTER_FORMAT)], ibo).render(moderngl.TRIANGLES)

    def render_shadows(self, frame) -> None:
        settings = shadow_module.ShadowSettings.from_params(self.params, self.name)
        self.shadows.sun.render(self.casters, frame.camera, frame.aspect, self.sun_direction(),
                                settings, revision=self._caster_revision())
        p = self.params
        if p["surfaces.lamp"]:
            self.shadows.point.render(self.casters, LAMP_POSITION, p["surfaces.lamp_range"],
                                      settings, revision=self._caster_revision())
        if p["surfaces.spot"]:
            self.shadows.spot.render(self.casters, SPOT_POSITION, self.spot_axis(),
                                     p["surfaces.spot_angle"], p["surfaces.spot_range"],
                                     settings, revision=self._caster_revision())
        self.shadows.publish(frame)

    def _caster_revision(self) -> int:
        """What the casters draw beyond the shadow settings: the cutoff of the cut-out quads and
        the user's mesh."""
        modes = tuple(self.caster_mode(q) for q in self.layout.quads)
        return hash((float(self.params["surfaces.cutoff"]), self._user_revision, modes))

    def material(self, obj) -> dict:
        """The surface uniforms of one object: albedo, metallic, smoothness, refraction."""
        p = self.params
        out = {"uAlbedo": tuple(obj.albedo), "uMetallic": 0.0, "uSmoothness": 0.0,
               "uRefractive": False, "uUseMetallicMap": False}
        if isinstance(obj, surfaces_scene.Room):
            out.update(uMetallic=p["surfaces.floor_metallic"],
                       uSmoothness=p["surfaces.floor_smoothness"])
        elif obj.name == "mirror":
            out.update(uMetallic=p["surfaces.mirror_metallic"],
                       uSmoothness=p["surfaces.mirror_smoothness"])
        elif obj.name == "dielectric":
            out.update(uMetallic=p["surfaces.dielectric_metallic"],
                       uSmoothness=p["surfaces.dielectric_smoothness"],
                       uUseMetallicMap=bool(p["surfaces.metallic_map"]))
        elif obj.name == "glass":
            out.update(uSmoothness=p["surfaces.glass_smoothness"], uRefractive=True,
                       uSphereCentre=tuple(obj.centre), uSphereRadius=float(obj.radius))
        return out

    def light_uniforms(self) -> dict:
        p = self.params
        half = math.radians(p["surfaces.spot_angle"])
        lamp = (1.0, 0.82, 0.6)
        return {
            "uSunDir": tuple(self.sun_direction()),
            "uSunRadiance": (p["surfaces.sun_intensity"],) * 3,
            "uAmbient": (p["surfaces.ambient"],) * 3,
            "uLampOn": bool(p["surfaces.lamp"]), "uLampPos": LAMP_POSITION,
            "uLampRadiance": tuple(c * p["surfaces.lamp_intensity"] for c in lamp),
            "uLampRange": p["surfaces.lamp_range"],
            "uSpotOn": bool(p["surfaces.spot"]), "uSpotPos": SPOT_POSITION,
            "uSpotDir": tuple(self.spot_axis()), "uSpotCos": (math.cos(0.8 * half),
                                                              math.cos(half)),
            "uSpotRadiance": (p["surfaces.spot_intensity"],) * 3,
            "uSpotRange": p["surfaces.spot_range"],
        }

    def surface_spec(self, mat: dict, probe: bool) -> ProgramSpec:
        """The surface program of one draw (glsl/surfaces/surface.frag's header): the room and
        the solids the camera sees — the probe on, no refraction — with the program specialised
        to that, to the specular model and to the shadows' filter and taps
        (``ShadowSet.defines``), so the branches the draw does not take cost nothing (a
        software rasteriser runs both sides of a branch on a uniform); the glass, the probe's
        capture, a debug view and every draw with ``surfaces.specialise`` off with the one
        generic program. The same image either way."""
        p = self.params
        if not (probe and not mat["uRefractive"] and p["surfaces.specialise"]
                and p["surfaces.debug"] == "none"):
            return SURFACE
        model = self.probe.lighting()[1]["uSpecularModel"]
        defines = (("SURFACE_SCENE", 1), ("SURFACE_SCENE_SPECULAR", model),
                   *self.shadows.defines())
        return ProgramSpec(SURFACE.name, defines=defines)

    def _prepare_surface(self, prog, view_proj, view, camera_pos, probe: bool) -> None:
        """Every uniform and texture of the surface program but the material's."""
        p = self.params
        prog.set_many({"uViewProj": view_proj, "uView": view, "uCameraPos": tuple(camera_pos),
                       **self.light_uniforms(), "uProbeOn": bool(probe),
                       "uN1": p["surfaces.n1"], "uN2": p["surfaces.n2"],
                       "uFresnelSchlick": p["surfaces.fresnel"] == "schlick",
                       "uTransparency": p["surfaces.transparency_lod"],
                       "uDistortion": p["surfaces.distortion"],
                       "uInterfaces": int(p["surfaces.interfaces"]),
                       "uDebug": ("none", "cascades", "shadow", "reflection").index(
                           p["surfaces.debug"])})
        self.apply_params(prog)
        lighting, lighting_uniforms = self.probe.lighting()  # the probe's capture needs them too
        prog.set_many(lighting_uniforms)
        textures = {"uDistortionMap": self._texture("distortion", _distortion_rgba),
                    "uMetallicMap": self._texture("metallic", metallic_map),
                    **lighting, **self.shadows.bind(prog)}
        if probe:
            textures.update(self.probe.textures())
            prog.set_many(self.probe.uniforms())
        prog.bind_textures(textures)  # once per switch of program: it assigns the units

    def draw_order(self, camera_pos) -> list:
        """The room and the solids, nearest solid first and the room last: the depth test then
        rejects what lies behind a solid before it is shaded (the same image, fewer fragments)."""
        cam = np.asarray(camera_pos, np.float64)

        def distance(obj) -> float:
            vbo, _, mesh = self._mesh(obj)
            if self._bounds.get(obj.name, (None,))[0] is not vbo:
                self._bounds[obj.name] = (vbo, *mesh.bounds())
            _, lo, hi = self._bounds[obj.name]
            return float(np.linalg.norm(np.clip(cam, lo, hi) - cam))

        return [*sorted(self.solids(), key=distance), self.layout.room]

    def draw_solids(self, view_proj, view, camera_pos, target_fbo, probe: bool) -> None:
        """The room and the solids with the surface program. ``probe`` false draws them as the
        reflection probe sees them: no reflection, no refraction (the probe has no probe)."""
        ctx = self.gpu.ctx
        target_fbo.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.enable(moderngl.CULL_FACE)
        current = None
        for obj in self.draw_order(camera_pos):
            vbo, ibo, _ = self._mesh(obj)
            mat = self.material(obj)
            if not probe:
                mat["uRefractive"] = False
            prog = self.program(self.surface_spec(mat, probe))
            if prog is not current:
                self._prepare_surface(prog, view_proj, view, camera_pos, probe)
                current = prog
            prog.set_many(mat)
            user = isinstance(obj, UserObject)
            if user:  # a user's winding may be either way
                ctx.disable(moderngl.CULL_FACE)
            prog.vao([(vbo, *FORMAT)], ibo).render(moderngl.TRIANGLES)
            if user:
                ctx.enable(moderngl.CULL_FACE)
        ctx.disable(moderngl.CULL_FACE)

    def probe_key(self) -> tuple:
        """What the probe's cubemap shows: the lights, the materials of the room and solids."""
        p = self.params
        shown = ("surfaces.sun", "surfaces.lamp", "surfaces.spot", "surfaces.shadow",
                 "surfaces.ambient", "surfaces.floor", "surfaces.mirror", "surfaces.dielectric",
                 "surfaces.metallic", "surfaces.probe")
        names = [n for n in p.values("surfaces") if n.startswith(shown)]
        return (*((n, _hashable(p[n])) for n in names), ("user", self._user_revision))

    def render_probe(self, frame) -> None:
        def draw_scene(view, proj, fbo):
            self.draw_solids(proj @ view, view, self.layout.probe_position, fbo, probe=False)

        room = self.layout.room
        self.probe.update(self.probe_key(), draw_scene, self.layout.probe_position, room.lo,
                          room.hi)

    def draw_opaque(self, frame, target) -> None:
        self._camera_pos = tuple(frame.camera.position)
        work = self.work_target(target)
        if work.samples:  # the frame's own target is cleared by the scene
            work.fbo.clear(*CLEAR, depth=1.0)
        cam = frame.camera
        view = cam.view_matrix()
        self.draw_solids(cam.projection_matrix(frame.aspect) @ view, view, cam.position,
                         work.fbo, probe=True)
        self.gpu.ctx.disable(moderngl.DEPTH_TEST)

    def draw_transparent(self, frame, target) -> None:
        work = self.work_target(target)
        cam = frame.camera
        p = self.params
        light = {"direction": tuple(self.sun_direction()),
                 "radiance": (p["surfaces.sun_intensity"],) * 3,
                 "ambient": (p["surfaces.ambient"],) * 3}
        quads = [(q, *self._mesh(q)[:2], self.alpha_texture(q.alpha)) for q in self.layout.quads]
        self.transparency.draw(work, cam.projection_matrix(frame.aspect) @ cam.view_matrix(),
                               tuple(cam.position), light, quads)
        if work.samples:  # resolve the multisampled target into the frame
            self.gpu.ctx.copy_framebuffer(target.fbo, work.fbo)

    def passes(self, frame, target) -> list[Pass]:
        return [Pass("surfaces.shadows", lambda: self.render_shadows(frame), Stage.SHADOW),
                Pass("surfaces.probe", lambda: self.render_probe(frame), Stage.ENVIRONMENT),
                Pass("surfaces.opaque", lambda: self.draw_opaque(frame, target), Stage.OPAQUE),
                Pass("surfaces.transparent", lambda: self.draw_transparent(frame, target),
                     Stage.TRANSPARENT)]

    #: the inspector's popups, grouped as the thesis's sections are (§2.4–2.8)
    INSPECTOR = {
        "Lights": ["surfaces.sun_elevation", "surfaces.sun_azimuth", "surfaces.sun_intensity",
                   "surfaces.ambient", "surfaces.lamp", "surfaces.lamp_intensity",
                   "surfaces.lamp_range", "surfaces.spot", "surfaces.spot_angle",
                   "surfaces.spot_intensity", "surfaces.spot_range"],
        "Transparency": ["surfaces.transparency", "surfaces.cutoff", "surfaces.a2c",
                         "surfaces.zwrite_blended", "surfaces.blue_queue", "surfaces.fence_queue",
                         "surfaces.fence_mode", "surfaces.leaves_mode", "surfaces.smoke_mode",
                         "surfaces.blue_mode", "surfaces.cross_mode", "surfaces.wboit_weight",
                         "surfaces.peel_layers", "surfaces.msaa"],
        "Reflections": ["surfaces.reflection", "surfaces.reflection_optimize",
                        "surfaces.specular_model", "surfaces.probe_size",
                        "surfaces.probe_sphere_radius", "surfaces.prefilter_samples",
                        "surfaces.mirror_smoothness", "surfaces.mirror_metallic",
                        "surfaces.dielectric_smoothness", "surfaces.dielectric_metallic",
                        "surfaces.metallic_map",
                        "surfaces.floor_smoothness", "surfaces.floor_metallic"],
        "Refraction": ["surfaces.n1", "surfaces.n2", "surfaces.fresnel",
                       "surfaces.transparency_lod", "surfaces.glass_smoothness",
                       "surfaces.distortion", "surfaces.interfaces"],
        "Shadows": ["surfaces.shadow_map_size", "surfaces.shadow_cascades",
                    "surfaces.shadow_split_lambda", "surfaces.shadow_stable_fit",
                    "surfaces.shadow_distance", "surfaces.shadow_linear_bias",
                    "surfaces.shadow_normal_bias", "surfaces.shadow_filter",
                    "surfaces.shadow_taps", "surfaces.specialise",
                    "surfaces.shadow_pcss_light_size", "surfaces.shadow_vsm_blur",
                    "surfaces.shadow_vsm_bleed", "surfaces.shadow_dithered",
                    "surfaces.shadow_strength"],
    }

    def panel_items(self) -> list:
        """The lab's inspector: a popup per thesis section (transparency, reflections,
        refraction, shadows) and thumbnails of the generated maps — the sun's shadow atlas
        (its first moment: depth), the lamp's six faces, the split-sum and NHxRoughness LUTs."""
        from ...params import Inspector

        popups = {t: [n for n in names if n in self.params] for t, names in self.INSPECTOR.items()}
        textures = {label: tex for label, tex in (
            ("sun shadow atlas", self.shadows.sun.colour),
            ("lamp faces", self.shadows.point.colour),
            ("split-sum LUT", self.probe.brdf), ("NHxRoughness LUT", self.probe.nhx))
            if tex is not None}
        return [Inspector("Surfaces inspector (spec/003 §2.4–2.8)",
                          {t: n for t, n in popups.items() if n}, textures)]

    def panel_notes(self) -> list[str]:
        p = self.params
        return [f"failure shown: {p['surfaces.failure']}",
                f"shadow renders: sun {self.shadows.sun.renders}, lamp "
                f"{self.shadows.point.renders}, spot {self.shadows.spot.renders}; probe "
                f"captures {self.probe.captures}",
                *self.transparency.notes(self.layout.quads, self._camera_pos)]

    def release(self) -> None:
        self.shadows.release()
        self.probe.release()
        self.transparency.release()
        self._meshes = {}
        self._textures = {}
        super().release()


#: the lab's own defaults of the shared shadow parameters: the 5 × 5 Gaussian PCF, whose
#: footprint (6 × 6 texels with its bilinear taps) covers the 4 × 4 dither period, so a
#: semi-transparent caster's dithered shadow reads as a smooth partial shadow instead of a grid
#: of dots; the thesis's four-tap (its taps on the diagonal neighbours, which the half-tone
#: pattern shares) shows the pattern and stays one switch away (spec/003 §2.8)
SHADOW_DEFAULTS = {"surfaces.shadow_filter": "pcf"}


def _lab_shadow_params() -> list[Param]:
    from dataclasses import replace

    return [replace(p, default=SHADOW_DEFAULTS[p.name]) if p.name in SHADOW_DEFAULTS else p
            for p in shadow_module.shadow_params("surfaces")]


def metallic_map(size: int = 128) -> np.ndarray:
    """The red sphere's metallic/smoothness texture (spec/003 §2.6: R = metallic, G =
    smoothness): four bands around the sphere (u) alternating metal and dielectric, smoothness
    rising with v from 0.1 at the foot to 1 at the top."""
    v, u = (np.mgrid[0:size, 0:size] + 0.5) / size
    out = np.ones((size, size, 4), np.float32)
    out[..., 0] = (np.floor(u * 4) % 2 == 0)
    out[..., 1] = 0.1 + 0.9 * v
    out[..., 2] = 0.0
    return out


def _distortion_rgba() -> np.ndarray:
    """The glass's distortion texture (app.sim.distortion) as RGBA: xy in [−1, 1] → [0, 1]."""
    xy = distortion.distortion_map(128)
    out = np.ones((*xy.shape[:2], 4), np.float32)
    out[..., :2] = distortion.encode(xy) / 255.0
    return out


def _hashable(value):
    return tuple(value) if isinstance(value, (list, tuple, np.ndarray)) else value
