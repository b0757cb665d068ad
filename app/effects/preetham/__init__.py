"""Preetham's analytic sky (spec/001 §1.8): shaders in ``glsl/preetham/``, numpy twin
``app/sim/preetham.py``."""

from .effect import Preetham

__all__ = ["Preetham"]
