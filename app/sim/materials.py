"""Numpy twins of the procedural-wood thesis's ring chain (``glsl/materials/wood.glsl``;
spec/004 §1.4–1.6): the tests compare the GPU with these."""

from __future__ import annotations

import numpy as np

from .noise.value import ValueNoise, ease_in


def effective(v) -> np.ndarray:
    """A thesis Vector property's effective 3D scale: xyz·w."""
    v = np.asarray(v, dtype=np.float64)
    return v[:3] * v[3]


def wood_radius(pos: np.ndarray, noise01: np.ndarray, vol_tex_scale=(1, 1, 1, 10),
                distor_factor=(1, 1, 1, 0.5)):
    """r = √(x² + z²) of the distorted point (spec/004 §1.4 step 1, distortion of §1.5)."""
    distor = (noise01 - 0.5) * effective(distor_factor)
    vt = pos * effective(vol_tex_scale) + distor
    return np.sqrt(vt[..., 0] ** 2 + vt[..., 2] ** 2)


def wood_value(radius) -> np.ndarray:
    """g∘w(r) = ((r mod 1))² (spec/004 §1.4 steps 3–4, ``valueFromRadius`` and ``easeIn``)."""
    return ease_in(np.mod(radius, 1.0))


def wood_colour(pos: np.ndarray, noise: ValueNoise | None = None, rec_depth: int = 3,
                vol_tex_scale=(1, 1, 1, 10), noise_grid_size=(0.2, 1, 1, 10),
                distor_factor=(1, 1, 1, 0.5),
                inner=(0.75, 0.5, 0.25), outer=(0.5, 0.25, 0.0)) -> np.ndarray:
    """The thesis's colour (display values, as its Unity shader output them) at object points:
    C∘g∘w(r) (spec/004 §1.4 step 5, the fragment shader of spec/004 §1.6)."""
    pos = np.asarray(pos, dtype=np.float64)
    if noise is None:
        n = np.full(pos.shape, 0.5)
    else:
        n = noise.octaves(pos * effective(noise_grid_size), rec_depth)
    v = wood_value(wood_radius(pos, n, vol_tex_scale, distor_factor))[..., None]
    return np.asarray(inner) * (1 - v) + np.asarray(outer) * v
