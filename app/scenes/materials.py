"""The ``materials`` scene: the procedural-wood thesis's solid textures on three meshes."""

from __future__ import annotations

from ..effects.materials import Materials
from .base import Scene


class MaterialsScene(Scene):
    name = "materials"
    order = 30
    title = "Procedural materials"
    description = ("the thesis's volumetric wood on a cube, a sphere and a torus; marble and "
                   "granite (spec/004)")
    effects = (Materials,)
    #: the three objects fit with a margin at 16:9 (18 % each side) and at 4:3 (7 %)
    default_camera = {"position": (-0.06, 0.7, 4.9), "yaw": 0.0, "pitch": -8.0, "fov": 40.0}
    background = (0.02, 0.02, 0.025)
