"""Noise, in numpy: the twin of every GLSL noise function in ``glsl/common/noise_*.glsl``.

* ``value`` — the procedural-wood thesis's lattice value noise (spec/004 §1.5–1.6)
* ``gradient`` — Perlin's improved gradient noise (2002), 2D and 3D, plain and periodic
* ``cellular`` — Worley F1/F2, plain and periodic
* ``fractal`` — fBm, turbulence, Worley fBm, Perlin–Worley, and tileable variants

The GL side (permutation textures, a GLSL probe) is ``app.render.noise``: this package is
numpy-only, like all of ``app.sim``.
"""

# app.sim.surface_maps imports these two from the package; everything else imports the
# defining module (gradient, cellular, fractal, value).
from .cellular import worley2_periodic
from .fractal import perlin_fbm2_periodic

__all__ = ["perlin_fbm2_periodic", "worley2_periodic"]
