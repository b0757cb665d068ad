"""The ``village`` scene: the toon-village thesis's one scene (spec/003 §0–1) — Fracsland's
village on an island surrounded by water, in the toon look, at any hour of the day–night sky:
houses with lit windows, props, inhabitants, a bonfire, street lamps that light at night, grass
moving in the scene's one wind, the stylised water, ground and distance fog, and the VR mode
(spec/003 §2.15: a stereo pair with the head-locked health ring).

It builds only what it uses: the wind, the day–night sky (its sun and hour, and its
environment cubemap for the water's reflection), the fog, the village (the island, what stands
on it, its lights and shadows), the grass, the stylised water and the VR overlays.

Cameras (``village.camera``): ``third`` follows the hero from behind (the thesis's normal play:
W A S D walk the hero, looking around turns the hero); ``first`` is the hero's eyes (the hero
is hidden, spec/003 §2.15's SetHeroVisibility); ``free`` is the fly camera. In VR the third
person becomes the first (the thesis lowers the camera to the hero's head). A ``--camera``
given on the command line is a free camera.

Anti-aliasing (``village.msaa``): the opaque stages (sky, village, grass) draw into a
multisampled twin of the frame, resolved before the water, so the billboard grass's
AlphaToMask (alpha to coverage, spec/003 §2.9) has samples to cover; ``0`` draws straight into
the frame (the grass then cuts at its alpha cutoff); ``auto`` (the default) is 4 on a GPU and
0 on a software renderer, where multisampling shades the village's small triangles per sample.
"""

from __future__ import annotations

import math

import numpy as np

from ..effects.fog import Fog
from ..effects.grass import Grass
from ..effects.sky import Sky
from ..effects.toon_water import ToonWater
from ..effects.village import Village
from ..effects.village.effect import msaa_samples
from ..effects.vr import Vr
from ..effects.wind import Wind
from ..frame import FrameContext, Stage
from ..params import Param, ParamSet
from ..render.stereo import StereoRenderer
from .base import Scene
from .keymaps import FLY, KeyMap

VILLAGE = KeyMap("village", {
    **FLY.bindings, "C": "cycle:village.camera", "V": "toggle:vr.enabled",
    "G": "cycle:grass.method", "F": "cycle:fog.mode", "H": "toggle:fog.height",
    "T": "cycle:village.toon", "O": "cycle:toon_water.type", "L": "toggle:village.lamps_auto",
}, FLY.help[:-2] + (
    ("C", "camera: third person, first person, free"), ("V", "VR mode (side-by-side eyes)"),
    ("G", "grass: geometry-shader blades, crossed billboards, instanced blades"),
    ("F", "fog: off, linear, exp, exp2"), ("H", "height fog on / off"),
    ("T", "toon: none, flat, stepped, ramp"), ("O", "water: simple / complex"),
    ("L", "street lamps by the hour / always on"),
) + FLY.help[-2:])

#: the eye height of the hero above the ground (the first-person camera) [m]
EYE_HEIGHT = 1.62


class VillageScene(Scene):
    name = "village"
    order = 90
    title = "Toon village (Fracsland)"
    description = ("the toon-village thesis's scene: an island village in the toon look — "
                   "houses, props, inhabitants, bonfire and street lamps under the day–night "
                   "sky; grass (geometry-shader, billboard and instanced blades), stylised "
                   "water, ground and distance fog; the VR mode with the health ring "
                   "(spec/003 §0–1, §2.9–2.11, §2.15)")
    effects = (Wind, Sky, Fog, Village, Grass, ToonWater, Vr)
    default_camera = {"position": (0.0, 4.8, 25.0), "yaw": 0.0, "pitch": -12.0, "fov": 60.0,
                      "near": 0.1, "far": 2000.0}
    keymap = VILLAGE

    @classmethod
    def declare_params(cls, library) -> ParamSet:
        params = super().declare_params(library)
        s = "spec/003 §2.15"
        params.add(Param("village.camera", "third", doc="third: behind the hero (W A S D walk "
                         "the hero); first: the hero's eyes (the hero hidden); free: the fly "
                         "camera", kind="choice", choices=("third", "first", "free"), section=s))
        # high enough above the hero that the plaza, the houses and the sea read over the grass
        params.add(Param("village.follow_distance", 6.0, 1.0, 60.0, "third person: the "
                         "camera's distance behind the hero", step=0.1, unit="m", section=s))
        params.add(Param("village.follow_height", 3.4, 0.3, 40.0, "third person: the camera's "
                         "height above the hero's feet", step=0.1, unit="m", section=s))
        params.add(Param("village.msaa", "auto", doc="samples of the opaque stages (the "
                         "billboard grass's AlphaToMask needs them); 0 draws straight into the "
                         "frame (the billboards cut at their alpha cutoff, the thesis's clip); "
                         "auto: 4 on a GPU, 0 on a software renderer, whose 4× MSAA shades "
                         "the village's many small triangles per sample (four times the "
                         "frame)", kind="choice", choices=("auto", "0", "4"),
                         section="spec/003 §2.9"))
        return params

    def __init__(self, gpu, params, camera=None):
        super().__init__(gpu, params, camera)
        self._placed: tuple[float, float, float] | None = None  # (x, z) and yaw last placed
        self._stereo = StereoRenderer(gpu, "village")
        self._msaa = None

    @classmethod
    def on_user_camera(cls, params: ParamSet) -> None:
        """A camera given on the command line is a free camera."""
        params.set("village.camera", "free")

    def village(self) -> Village:
        effect = self.effect("village")
        assert isinstance(effect, Village)
        return effect

    def camera_mode(self) -> str:
        mode = self.params["village.camera"]
        if mode == "third" and self.params["vr.enabled"]:
            return "first"  # spec/003 §2.15: in VR the camera is lowered to the hero's head
        return mode

    def frame(self, size, dt: float = 0.0) -> FrameContext:
        mode = self.camera_mode()
        village = self.village()
        village.hero_visible = mode != "first"
        if mode != "free":
            self._walk(village)
        else:
            self._placed = None
        frame = super().frame(size, dt)
        if mode != "free":
            self._place(village, mode)
        return frame

    def _walk(self, village: Village) -> None:
        """What the fly controls did to the camera since it was last placed moves the hero:
        the camera's horizontal displacement becomes the hero's step, its yaw the heading."""
        if self._placed is None:
            # the first frame: a view turned away from the scene's start (--yaw) turns the hero
            if abs(self.camera.yaw - self.default_camera["yaw"] % 360.0) > 1e-9:
                village.walk_hero(0.0, 0.0, self.camera.yaw)
            return
        x0, z0, _ = self._placed
        x, _, z = self.camera.position
        village.walk_hero(x - x0, z - z0, self.camera.yaw)

    def _place(self, village: Village, mode: str) -> None:
        hx, hz, heading = village.hero()
        ground = village.ground(hx, hz)
        yaw = math.radians(heading)
        forward = np.array([math.sin(yaw), 0.0, -math.cos(yaw)])
        if mode == "first":
            eye = np.array([hx, ground + EYE_HEIGHT * village.hero_height() / 1.75, hz])
        else:
            back = self.params["village.follow_distance"]
            eye = (np.array([hx, ground + self.params["village.follow_height"], hz])
                   - back * forward)
            eye[1] = max(eye[1], village.ground(eye[0], eye[2]) + 0.4)
        self.camera.set(position=tuple(eye), yaw=heading)
        self._placed = (float(eye[0]), float(eye[2]), heading)

    def render(self, frame: FrameContext, target) -> None:
        if self.params["vr.enabled"]:
            # the shadow maps and the probes once, from the head (the eyes, 3.2 cm either side,
            # share the frame's slots): each eye's own camera would otherwise invalidate the
            # cascades the other eye just drew, and a still head would redraw them twice
            for p in self.passes(frame, target):
                if p.stage < Stage.BACKGROUND:
                    p.run()
            self._stereo.render(frame, target, self.params["vr.ipd"],
                                self.params["vr.render_scale"],
                                lambda f, t: self._render_mono(f, t, Stage.BACKGROUND))
            return
        self._render_mono(frame, target)

    def _msaa_target(self, size, samples: int):
        """The frame's multisampled twin, kept while its size and samples hold."""
        if self._msaa is None or (self._msaa.size, self._msaa.samples) != (tuple(size), samples):
            self._free_msaa()
            self._msaa = self.gpu.target("village", "msaa", size, samples=samples)
        return self._msaa

    def _free_msaa(self) -> None:
        if self._msaa is not None:
            self.gpu.free(self._msaa)
            self._msaa = None

    def _render_mono(self, frame: FrameContext, target, first: Stage = Stage.SHADOW) -> None:
        """One view's passes from stage ``first`` on: up to the opaque stage into the
        multisampled twin (resolved into ``target``), the rest into ``target``."""
        samples = msaa_samples(self.params["village.msaa"], self.gpu.caps.software)
        target.use()
        target.clear((*self.background, 1.0))
        if samples <= 0:
            for p in self.passes(frame, target):
                if p.stage >= first:
                    p.run()
            return
        work = self._msaa_target(target.size, samples)
        work.clear((*self.background, 1.0))
        for p in self.passes(frame, work):
            if first <= p.stage <= Stage.OPAQUE:
                p.run()
        self.gpu.ctx.copy_framebuffer(target.fbo, work.fbo)  # resolves colour and depth
        for p in self.passes(frame, target):
            if p.stage > Stage.OPAQUE and p.stage >= first:
                p.run()

    def release(self) -> None:
        self._stereo.release()
        self._free_msaa()
        super().release()

