"""The reflection probe on a mirror ball (spec/000 §1.7): shaders in ``glsl/probe/``."""

from .effect import Probe

__all__ = ["Probe"]
