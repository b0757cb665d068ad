"""Procedural solid materials (spec/004): shaders in ``glsl/materials/``, numpy twins in
``app/sim/materials.py``."""

from .effect import Materials

__all__ = ["Materials"]
