"""The ``probe`` scene: the sky's reflection probe on a mirror ball."""

from __future__ import annotations

from ..effects.probe import Probe
from ..effects.sky import Sky
from .base import Scene


class ProbeScene(Scene):
    name = "probe"
    order = 20
    title = "Sky with a reflection probe"
    description = ("the sky's environment cubemap on a mirror ball, re-rendered only when the sky "
                   "changes (spec/000 §1.7)")
    effects = (Sky, Probe)
    default_camera = {"position": (0.0, 2.0, 0.0), "yaw": 0.0, "pitch": 5.0, "fov": 60.0}
