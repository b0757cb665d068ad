"""VR mode (spec/003 §2.15): being built (the village issue); the stereo pair itself is drawn
by the scene (app.render.stereo), from these parameters."""

from __future__ import annotations

from ...frame import Stage
from ...params import Param
from ..base import Effect, Pass


class Vr(Effect):
    name = "vr"
    title = "VR mode"
    spec = "spec/003"
    stages = (Stage.OVERLAY,)

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/003 §2.15"
        return [
            Param("vr.enabled", False, doc="side-by-side stereo: each eye its own view and "
                  "projection, the camera at the hero's head", kind="bool", section=s),
            Param("vr.ipd", 0.064, 0.0, 0.2, "interpupillary distance", step=0.001, unit="m",
                  section=s),
            Param("vr.render_scale", 1.0, 0.25, 2.0, "each eye's render texture, relative to "
                  "its half of the frame (Unity's eye texture resolution scale)", step=0.05,
                  section=s),
        ]

    def passes(self, frame, target) -> list[Pass]:
        return []
