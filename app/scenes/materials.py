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
    #: the three objects fit with a margin at 16:9 (15 % each side) and at 4:3 (3 %), seen from
    #: 22° above so the end grain of the cube's top and the sphere's rings face the camera
    default_view = "low-sun"
    default_camera = {"position": (-0.04, 1.75, 4.35), "yaw": 0.0, "pitch": -22.0, "fov": 40.0}
    background = (0.02, 0.02, 0.025)
