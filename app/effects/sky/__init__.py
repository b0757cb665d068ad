"""The day–night sky of the maritime thesis (spec/000 §1.7): effect, shaders in ``glsl/sky/``,
numpy twins in ``app/sim/sky.py``, tests ``tests/**/test_sky*.py``."""

from .effect import Sky

__all__ = ["Sky"]
