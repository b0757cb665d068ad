"""What every pass sees in a frame: camera, time, resolution, lights and wind.

Effects earlier in a scene's list fill in what later ones read: the sky sets the sun, the moon
and the main light (sun by day, moon by night); later issues add wind and water queries.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .sim.camera import Camera
from .sim.daynight import Light


@dataclass
class FrameContext:
    size: tuple[int, int]
    camera: Camera
    time: float = 0.0  # seconds since the scene started
    dt: float = 0.0
    index: int = 0
    hour: float = 12.0
    sun: Light | None = None
    moon: Light | None = None
    main_light: Light | None = None
    wind: np.ndarray = field(default_factory=lambda: np.zeros(2))
    exposure: float = 1.0  # multiplies output.exposure (e.g. the atmosphere thesis's "pupil")
    interactive: bool = False  # rendered in the window (frames follow each other)
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def aspect(self) -> float:
        return self.size[0] / self.size[1]

    def camera_uniforms(self) -> dict[str, Any]:
        return self.camera.uniforms(self.aspect)

    def light_uniforms(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        if self.main_light is not None:
            out["uMainLightDir"] = tuple(self.main_light.direction)
            out["uMainLightRadiance"] = tuple(self.main_light.radiance)
        if self.sun is not None:
            out["uSunDir"] = tuple(self.sun.direction)
        if self.moon is not None:
            out["uMoonDir"] = tuple(self.moon.direction)
        return out
