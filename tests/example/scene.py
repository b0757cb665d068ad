"""The example's scene (in your own project: app/scenes/vignette.py)."""

from __future__ import annotations

from app.effects.sky import Sky
from app.scenes.base import Scene
from tests.example.vignette import Vignette


class VignetteScene(Scene):
    name = "vignette"
    order = 80
    title = "Sky through a lens"
    description = "the day–night sky with natural vignetting (the example of docs/architecture.md)"
    effects = (Sky, Vignette)
    default_camera = {"position": (0.0, 2.0, 0.0), "yaw": 225.0, "pitch": 25.0, "fov": 90.0}
