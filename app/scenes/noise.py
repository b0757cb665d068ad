"""The ``noise`` scene: the noise lab."""

from __future__ import annotations

from ..effects.noise import Noise
from .base import Scene


class NoiseScene(Scene):
    name = "noise"
    order = 50
    title = "Noise lab"
    description = ("every noise function of glsl/common and the cloud bakes (shape, detail, "
                   "weather map), four side by side or one at a time (noise.layout), tiled to "
                   "show they are seamless (spec/001 §1.1, spec/000 §1.6, spec/004)")
    effects = (Noise,)
