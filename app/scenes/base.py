"""Scenes compose effects. A scene names exactly the effects it uses; nothing else is created.

Per frame (docs/architecture.md, "A frame"): each active effect's ``update`` runs in the
scene's order and fills the slots of the :class:`~app.frame.FrameContext` it produces (the sky
adds the lights and the environment probe, the ocean the water and the wind); then every active
effect's passes run stage by stage (:class:`~app.frame.Stage`; within a stage, in the scene's
order) into the scene's linear-radiance target.

A scene whose effects require a slot that none of them produces is refused when it is built.
"""

from __future__ import annotations

from typing import ClassVar

from .. import RESOURCES
from ..colour import TONEMAPS
from ..effects.base import Effect, Pass
from ..errors import NaturaError, UsageError
from ..frame import SCENE_SLOTS, SLOTS, FrameContext, SceneImage, Stage
from ..gpu.shaders import ShaderLibrary
from ..params import Param, ParamSet
from ..sim.camera import Camera
from .keymaps import FLY, KeyMap

PRESETS = RESOURCES / "presets"


#: the window's smallest internal scale per side (dynamic resolution goes no lower)
MIN_SCALE = 0.5
#: ``output.scale``'s value meaning "automatic" (``--set output.scale=auto`` stores it)
AUTO_SCALE = 0.0


class ScaleParam(Param):
    """``output.scale``: ``auto`` (stored as 0) or a scale in [MIN_SCALE, 1] that pins it."""

    def allowed(self) -> str:
        return f"auto (or 0) or a number in [{MIN_SCALE:g}, 1]"

    def written(self, value) -> str:
        return "'auto'" if value == AUTO_SCALE else repr(value)

    def _validate(self, value):
        if isinstance(value, str) and value.strip().lower() == "auto":
            return AUTO_SCALE
        number = super()._validate(value)
        if AUTO_SCALE < number < MIN_SCALE - 1e-12:
            raise self._bad(value, "is out of range")
        return number


def output_params() -> list[Param]:
    return [
        Param("output.exposure", 1.0, 0.001, 1000.0, "exposure multiplier before tone mapping",
              step=0.01),
        Param("output.tonemap", "aces", doc="tone map for PNG and the window (EXR stays linear)",
              kind="choice", choices=TONEMAPS),
        Param("output.frame_budget_ms", 33.0, 1.0, 1000.0, "the window's frame time budget: a "
              "slower frame lowers the 3D scene's internal scale (output.scale=auto)",
              step=1.0, unit="ms"),
        ScaleParam("output.scale", AUTO_SCALE, 0.0, 1.0, "the window's 3D scene resolution per "
                   f"side: auto (dynamic, down to {MIN_SCALE:g} within the frame budget), 1 "
                   f"pins the full scale, a value in [{MIN_SCALE:g}, 1] pins that one; the "
                   "panel and HUD stay sharp; headless renders are always full scale",
                   step=0.125),
        Param("output.upscale", "bicubic", doc="the filter that enlarges a reduced scene to the "
              "window: bicubic (Catmull-Rom, sharper) or bilinear (cheaper)", kind="choice",
              choices=("bicubic", "bilinear")),
    ]


class Scene:
    name: ClassVar[str] = ""
    #: where ``natura scenes`` lists the scene (then by name)
    order: ClassVar[int] = 1000
    title: ClassVar[str] = ""
    description: ClassVar[str] = ""
    effects: ClassVar[tuple[type[Effect], ...]] = ()
    #: Camera(...) arguments of the scene's starting view
    default_camera: ClassVar[dict] = {}
    #: the view (resources/presets/views/<scene>/) the window and ``natura render`` open on when
    #: none is named — the scene's best first picture; None: the defaults themselves. The
    #: parameters' defaults stay the thesis's (the tests and ``natura bench`` start from them)
    default_view: ClassVar[str | None] = None
    #: linear radiance behind everything
    background: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)
    keymap: ClassVar[KeyMap] = FLY  # the window's key bindings (app/scenes/keymaps.py)
    #: switches between effects of the scene: parameter → (default, {choice: effect name}, doc).
    #: An effect that is not chosen is skipped entirely, so it creates no GL resources.
    selectors: ClassVar[dict] = {}
    #: where the camera may stand, metres: (lowest, highest) x, y and z. A flat world is a
    #: patch of the Earth: no point of its surface is farther than half its circumference
    #: (2.0e7 m) from the origin, nothing lies deeper than the deepest sea (−1.1e4 m), and above
    #: the Kármán line (1.0e5 m) a flat sky and sea no longer hold. Far enough for every view,
    #: and a float32 camera-relative frame stays exact to a few metres there.
    camera_box: ClassVar[tuple[tuple[float, float], ...]] = (
        (-2.0e7, 2.0e7), (-1.1e4, 1.0e5), (-2.0e7, 2.0e7))

    @classmethod
    def new_camera(cls) -> Camera:
        """A camera at the scene's starting view."""
        return Camera(**cls.default_camera)

    @classmethod
    def check_camera(cls, camera: Camera, option: str = "--camera") -> None:
        """Refuse a camera position the scene cannot represent (one line with its range)."""
        for axis, value, (lo, hi) in zip("xyz", camera.position, cls.camera_box):
            if not lo <= float(value) <= hi:
                raise UsageError(f"{option}: {axis} = {float(value):.6g} m is outside the "
                                 f"{cls.name} scene: allowed {axis} in [{lo:g}, {hi:g}] m")

    @classmethod
    def on_user_camera(cls, params: ParamSet) -> None:
        """A camera was given on the command line (``--camera``): a scene that places its
        camera itself (a chase or third-person camera) lets this one be. Nothing by default."""

    @classmethod
    def check_slots(cls) -> None:
        """Refuse a scene where an effect requires a frame slot that no effect produces (the
        scene itself fills ``image``: the target the frame is drawn into)."""
        produced = set(SCENE_SLOTS).union(*(e.produces for e in cls.effects))
        for effect in cls.effects:
            unknown = (set(effect.consumes) | set(effect.produces)) - set(SLOTS)
            if unknown:
                raise NaturaError(f"effect {effect.name!r} declares unknown frame slots "
                                  f"{sorted(unknown)}: allowed {', '.join(SLOTS)}")
            for slot, need in effect.consumes.items():
                if need == "required" and slot not in produced:
                    raise NaturaError(f"scene {cls.name!r}: effect {effect.name!r} needs the frame "
                                      f"slot {slot!r} ({SLOTS[slot]}), which none of its effects "
                                      "produces: allowed a scene that also has an effect "
                                      "producing it")

    @classmethod
    def declare_params(cls, library: ShaderLibrary) -> ParamSet:
        cls.check_slots()
        params = ParamSet(output_params())
        for name, (default, choices, doc) in cls.selectors.items():
            params.add(Param(name, default, doc=doc, kind="choice", choices=tuple(choices)))
        for effect in cls.effects:
            for p in effect.declare(library):
                params.add(p)
            for former in effect.former_names:
                params.alias(former, effect.name)
        preset = PRESETS / f"{cls.name}.toml"
        if preset.is_file():
            params.load_preset(preset)
        return params

    def __init__(self, gpu, params: ParamSet, camera: Camera | None = None):
        self.check_slots()
        self.gpu = gpu
        self.params = params
        self.camera: Camera = camera or self.new_camera()
        self.time = 0.0
        self.index = 0
        self.instances: list[Effect] = [cls(gpu, params) for cls in self.effects]
        self.last_frame: FrameContext | None = None
        self.interactive = False  # the window sets it (e.g. clouds reproject only there)

    def active(self, effect: Effect) -> bool:
        """Whether an effect is chosen by the scene's selectors (always, when none names it)."""
        for name, (_, choices, _) in self.selectors.items():
            if effect.name in choices.values():
                return choices[self.params[name]] == effect.name
        return True

    def active_instances(self) -> list[Effect]:
        return [e for e in self.instances if self.active(e)]

    def effect(self, name: str) -> Effect:
        for e in self.instances:
            if e.name == name:
                return e
        raise KeyError(f"scene {self.name!r} has no effect {name!r}")

    def frame(self, size: tuple[int, int], dt: float = 0.0) -> FrameContext:
        """Advance the simulation by ``dt`` seconds and return this frame's context."""
        self.time += dt
        frame = FrameContext(size=(int(size[0]), int(size[1])), camera=self.camera, time=self.time,
                             dt=dt, index=self.index, interactive=self.interactive)
        self.index += 1
        for effect in self.active_instances():
            effect.update(frame, dt)
        self.last_frame = frame
        return frame

    def exposure(self) -> float:
        """output.exposure times what the last frame's effects asked for (e.g. the pupil)."""
        extra = self.last_frame.exposure if self.last_frame is not None else 1.0
        return self.params["output.exposure"] * extra

    def render(self, frame: FrameContext, target) -> None:
        target.use()
        target.clear((*self.background, 1.0))
        for p in self.passes(frame, target):
            p.run()

    def passes(self, frame: FrameContext, target) -> list[Pass]:
        """Every active effect's passes for this frame, stage by stage (stable: within a stage
        in the scene's order). Sets the frame's ``image`` slot to ``target``."""
        return self._staged(frame, target, "passes")

    def bench_passes(self, frame: FrameContext, target) -> list[Pass]:
        """What ``natura bench`` times, stage by stage (see :meth:`Effect.bench_passes`)."""
        return self._staged(frame, target, "bench_passes")

    def _staged(self, frame: FrameContext, target, method: str) -> list[Pass]:
        frame.image = SceneImage(target)
        out = [p for effect in self.active_instances()
               for p in getattr(effect, method)(frame, target)]
        frame.image.opaque = any(Stage.BACKGROUND <= p.stage < Stage.VOLUMES
                                 and p.stage != Stage.SKY for p in out)
        return sorted(out, key=lambda p: p.stage)

    def release(self) -> None:
        for effect in self.instances:
            effect.release()
