"""Atmospheric scattering on a planet (spec/002) and Hillaire 2020: shaders in ``glsl/planet/`` and
the shared model in ``glsl/atmosphere/``; numpy twins in ``app/sim/atmosphere.py`` and
``app/sim/hillaire.py``."""

from .effect import Planet

__all__ = ["Planet"]
