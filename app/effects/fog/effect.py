"""Fog (spec/003): being built (the village issue); draws nothing yet."""

from __future__ import annotations

from ...frame import Stage
from ..base import Effect, Pass


class Fog(Effect):
    name = "fog"
    title = "Fog"
    spec = "spec/003"
    stages = (Stage.TRANSPARENT,)

    def passes(self, frame, target) -> list[Pass]:
        return []
