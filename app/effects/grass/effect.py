"""Grass (spec/003): being built (the village issue); draws nothing yet."""

from __future__ import annotations

from ...frame import Stage
from ..base import Effect, Pass


class Grass(Effect):
    name = "grass"
    title = "Grass"
    spec = "spec/003"
    stages = (Stage.OPAQUE,)

    def passes(self, frame, target) -> list[Pass]:
        return []
