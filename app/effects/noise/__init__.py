"""The noise lab: every noise function and cloud bake on screen (spec/001 §1.1, spec/000 §1.6,
spec/004): shader ``glsl/noise/``, numpy twins in ``app/sim/noise/``."""

from .effect import Noise

__all__ = ["Noise"]
