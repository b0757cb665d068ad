"""Stylised water (spec/003): being built (the village issue); draws nothing yet."""

from __future__ import annotations

from ...frame import Stage
from ..base import Effect, Pass


class ToonWater(Effect):
    name = "toon_water"
    title = "Stylised water"
    spec = "spec/003"
    stages = (Stage.WATER,)

    def passes(self, frame, target) -> list[Pass]:
        return []
