"""Volumetric clouds, model A — the cloud thesis (spec/001): shaders in ``glsl/clouds/``, numpy
twins in ``app/sim/clouds.py``, temporal reprojection in :mod:`.reprojection`."""

from .effect import Clouds

__all__ = ["Clouds"]
