"""The Fracsland village (spec/003 §0–1): being built; for now the island's height field in the
``terrain`` slot, the inhabitants in ``npcs`` and the hero's position (the scene's cameras)."""

from __future__ import annotations

import math

import numpy as np

from ...frame import Npc, Stage
from ...params import Param
from ...sim.village import Island
from ..base import Effect, Pass


class Village(Effect):
    name = "village"
    title = "The Fracsland village"
    spec = "spec/003"
    stages = (Stage.SHADOW, Stage.OPAQUE)
    produces = frozenset({"terrain", "npcs", "shadows"})
    consumes = {"main_light": "optional", "fog": "optional"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/003 §1"
        return [
            Param("village.hero_x", 0.0, -100.0, 100.0, "the hero's position (east)", step=0.1,
                  unit="m", section=s),
            Param("village.hero_z", 17.0, -100.0, 100.0, "the hero's position (south)",
                  step=0.1, unit="m", section=s),
            Param("village.hero_heading", 0.0, 0.0, 360.0, "the hero's compass heading",
                  step=1.0, unit="°", section=s),
            Param("village.lamps_auto", True, doc="street lamps light when the sun sets "
                  "(off: always lit)", kind="bool", section=s),
            Param("village.toon", 2, 0, 3, "placeholder", kind="int"),
        ]

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.island = Island()
        self.hero_visible = True

    # -- the hero --------------------------------------------------------------------------
    def hero(self) -> tuple[float, float, float]:
        p = self.params
        return p["village.hero_x"], p["village.hero_z"], p["village.hero_heading"]

    def hero_height(self) -> float:
        return 1.75

    def ground(self, x: float, z: float) -> float:
        return max(self.island.ground(x, z), self.island.sea_level)

    def walk_hero(self, dx: float, dz: float, heading: float) -> None:
        """Move the hero by (dx, dz) metres and turn it to ``heading``, staying on the island
        and out of the sea."""
        x, z, _ = self.hero()
        nx = float(np.clip(x + dx, -100.0, 100.0))
        nz = float(np.clip(z + dz, -100.0, 100.0))
        if self.island.ground(nx, nz) < self.island.sea_level - 0.3:  # no walking into the sea
            nx, nz = x, z
        self.params.set("village.hero_x", nx)
        self.params.set("village.hero_z", nz)
        self.params.set("village.hero_heading", heading % 360.0)

    # -- frame -----------------------------------------------------------------------------
    def update(self, frame, dt: float) -> None:
        frame.terrain = self.island
        frame.npcs = [Npc(p.name, p.role, (p.position[0],
                                           self.island.ground(*p.position) + p.height,
                                           p.position[1]))
                      for p in self.island.layout.people]
        _ = math

    def passes(self, frame, target) -> list[Pass]:
        return []
