"""The global wind manager of the maritime thesis (spec/000 §1.4, ``Wind.cs``): one wind speed
and direction for the whole scene.

It draws nothing. Its ``update`` fills the frame's ``wind`` slot with the (x, z) velocity in m/s
before any other effect runs (a scene lists it first), so every effect of the scene that reads
the slot follows one change. It never names them: the panel lists the scene's readers of the
slot (``app.ui.panel.slot_readers``), so each scene's text says what that scene has.

Direction convention (the slot's, shared by its readers): the direction the wind blows
*toward*, 0° = north (−z), 90° = east (+x).
"""

from __future__ import annotations

import numpy as np

from ...frame import Stage
from ...params import Param
from ...sim.maths import compass_xz
from ..base import Effect


def wind_velocity(speed: float, direction_deg: float) -> np.ndarray:
    """(x, z) velocity [m/s] of a wind of ``speed`` blowing toward ``direction_deg``
    (0° = north = −z, 90° = east = +x)."""
    return speed * compass_xz(direction_deg)


class Wind(Effect):
    name = "wind"
    title = "Wind"
    spec = "spec/000"
    stages = (Stage.BACKGROUND,)
    produces = frozenset({"wind"})

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/000 §1.4"
        return [
            Param("wind.speed", 8.0, 0.0, 40.0, "wind speed 10 m above the ground or the sea: "
                  "every effect of the scene that reads the wind takes it (the panel lists "
                  "them)", step=0.1, unit="m/s", section=s),
            Param("wind.direction", 90.0, 0.0, 360.0, "direction the wind blows toward: 0 = "
                  "north (−z), 90 = east (+x)", step=1.0, unit="°", section=s),
        ]

    def velocity(self) -> np.ndarray:
        return wind_velocity(self.params["wind.speed"], self.params["wind.direction"])

    def update(self, frame, dt: float) -> None:
        frame.wind = self.velocity()

    def passes(self, frame, target) -> list:
        return []

    def panel_notes(self) -> list[str]:
        v = self.velocity()
        speed, direction = self.params["wind.speed"], self.params["wind.direction"]
        return [f"wind {speed:.1f} m/s toward {direction:.0f}° = ({v[0]:+.1f}, {v[1]:+.1f}) m/s "
                "(x, z)"]
