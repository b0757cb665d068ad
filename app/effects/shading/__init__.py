"""The lighting and toon lab (spec/003 §2.1–2.3, §2.12): the thesis's test objects on a
turntable, lit by a sun, street lamps and a spot light, with every lighting model and toon mode
a live switch. Shaders in ``glsl/shading/``; numpy twins in ``app/sim/lighting.py``,
``app/sim/staircase.py``, ``app/sim/bump.py`` and ``app/sim/parallax.py``."""

from .effect import Shading

__all__ = ["Shading"]
