"""Volumetric clouds, model B — the maritime thesis (spec/000 §1.6): shaders in ``glsl/clouds_b/``,
numpy twins in ``app/sim/clouds_b.py``."""

from .effect import CloudsB

__all__ = ["CloudsB"]
