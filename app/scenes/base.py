"""Scenes compose effects. A scene names exactly the effects it uses; nothing else is created.

Per frame (DESIGN.md, "What flows through a frame"): each effect's ``update`` runs in order and
fills the :class:`~app.frame.FrameContext` (the sky adds the lights), then each effect renders
into the scene's linear-radiance target.
"""

from __future__ import annotations

from typing import ClassVar

from .. import RESOURCES
from ..effects.base import Effect, Pass
from ..frame import FrameContext
from ..gpu.shaders import ShaderLibrary
from ..imageio import TONEMAPS
from ..params import Param, ParamSet
from ..sim.camera import Camera
from ..ui.keymap import FLY

PRESETS = RESOURCES / "presets"


def output_params() -> list[Param]:
    return [
        Param("output.exposure", 1.0, 0.001, 1000.0, "exposure multiplier before tone mapping", step=0.01),
        Param("output.tonemap", "aces", doc="tone map for PNG and the window (EXR stays linear)", kind="choice",
              choices=TONEMAPS),
    ]


class Scene:
    name: ClassVar[str] = ""
    title: ClassVar[str] = ""
    description: ClassVar[str] = ""
    effects: ClassVar[tuple[type[Effect], ...]] = ()
    camera: ClassVar[dict] = {}
    background: ClassVar[tuple[float, float, float]] = (0.0, 0.0, 0.0)  # linear radiance behind everything
    keymap: ClassVar = FLY  # the window's key bindings (app/ui/keymap.py)
    #: switches between effects of the scene: parameter → (default, {choice: effect name}, doc).
    #: An effect that is not chosen is skipped entirely, so it creates no GL resources.
    selectors: ClassVar[dict] = {}

    @classmethod
    def declare_params(cls, library: ShaderLibrary) -> ParamSet:
        params = ParamSet(output_params())
        for name, (default, choices, doc) in cls.selectors.items():
            params.add(Param(name, default, doc=doc, kind="choice", choices=tuple(choices)))
        for effect in cls.effects:
            for p in effect.declare(library):
                params.add(p)
        preset = PRESETS / f"{cls.name}.toml"
        if preset.is_file():
            params.load_preset(preset)
        return params

    def __init__(self, gpu, params: ParamSet, camera: Camera | None = None):
        self.gpu = gpu
        self.params = params
        self.camera = camera or Camera(**self.camera)
        self.time = 0.0
        self.index = 0
        self.instances: list[Effect] = [cls(gpu, params, self) for cls in self.effects]
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

    def has_effect(self, name: str) -> bool:
        return any(e.name == name for e in self.instances)

    def frame(self, size: tuple[int, int], dt: float = 0.0) -> FrameContext:
        """Advance the simulation by ``dt`` seconds and return this frame's context."""
        self.time += dt
        frame = FrameContext(size=tuple(size), camera=self.camera, time=self.time, dt=dt, index=self.index,
                             interactive=self.interactive)
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
        for effect in self.active_instances():
            effect.render(frame, target)

    def passes(self, frame: FrameContext, target) -> list[Pass]:
        out = []
        for effect in self.active_instances():
            out.extend(effect.passes(frame, target))
        return out

    def release(self) -> None:
        for effect in self.instances:
            effect.release()
