"""Volumetric clouds, model A — the cloud thesis (spec/001): shaders in ``glsl/clouds/``, numpy
twins in ``app/sim/clouds.py``; the amortised march (reduced resolution, temporal reprojection)
in ``app/render/amortise.py``."""

from .effect import Clouds

__all__ = ["Clouds"]
