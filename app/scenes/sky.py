"""The ``sky`` scene: the day–night sky at sea level."""

from __future__ import annotations

from ..effects.sky import Sky
from .base import Scene


class SkyScene(Scene):
    name = "sky"
    order = 10
    title = "Day–night sky at sea level"
    description = "procedural sky, sun, halo, moon and stars over 24 h (spec/000 §1.7)"
    effects = (Sky,)
    default_camera = {"position": (0.0, 2.0, 0.0), "yaw": 225.0, "pitch": 25.0, "fov": 90.0}
