"""Noise, in numpy: the twin of every GLSL noise function in ``glsl/common/noise_*.glsl``.

* ``value`` — the procedural-wood thesis's lattice value noise (spec/004 §1.5–1.6)
* ``gradient`` — Perlin's improved gradient noise (2002), 2D and 3D, plain and periodic
* ``cellular`` — Worley F1/F2, plain and periodic
* ``fractal`` — fBm, turbulence, Worley fBm, Perlin–Worley, and tileable variants

The GL side (permutation textures, a GLSL probe) is ``app.render.noise``: this package is
numpy-only, like all of ``app.sim``.
"""

from .cellular import (
    feature_point2,
    feature_point3,
    pcg4d,
    worley2,
    worley2_periodic,
    worley3,
    worley3_periodic,
    worley_f2_minus_f1,
    worley_inverted_f1,
)
from .fractal import (
    gain_for,
    octave_sum,
    perlin_fbm2,
    perlin_fbm2_periodic,
    perlin_fbm3,
    perlin_fbm3_periodic,
    perlin_turbulence2,
    perlin_turbulence2_periodic,
    perlin_turbulence3,
    perlin_turbulence3_periodic,
    perlin_worley2,
    perlin_worley2_periodic,
    perlin_worley3,
    perlin_worley3_periodic,
    perlin_worley_remap,
    worley_fbm2,
    worley_fbm2_periodic,
    worley_fbm3,
    worley_fbm3_periodic,
)
from .gradient import (
    PERLIN2_BOUND,
    PERLIN3_BOUND,
    REFERENCE_PERMUTATION,
    perlin2,
    perlin2_periodic,
    perlin3,
    perlin3_periodic,
    permutation,
)
from .value import ValueNoise, ease_in, ease_in_out, random_texture

__all__ = [
    "ease_in", "ease_in_out", "feature_point2", "feature_point3", "gain_for", "octave_sum",
    "pcg4d", "perlin2", "PERLIN2_BOUND", "perlin2_periodic", "perlin3", "PERLIN3_BOUND",
    "perlin3_periodic", "perlin_fbm2", "perlin_fbm2_periodic", "perlin_fbm3",
    "perlin_fbm3_periodic", "perlin_turbulence2", "perlin_turbulence2_periodic",
    "perlin_turbulence3", "perlin_turbulence3_periodic", "perlin_worley2",
    "perlin_worley2_periodic", "perlin_worley3", "perlin_worley3_periodic",
    "perlin_worley_remap", "permutation", "random_texture", "REFERENCE_PERMUTATION",
    "ValueNoise", "worley2", "worley2_periodic", "worley3", "worley3_periodic",
    "worley_f2_minus_f1", "worley_fbm2", "worley_fbm2_periodic", "worley_fbm3",
    "worley_fbm3_periodic", "worley_inverted_f1",
]
