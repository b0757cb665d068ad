"""Small vector helpers for the physics' inner loops.

``cross`` is ``numpy.cross`` for 3-vectors (the last axis), written out: the same products
in the same order, so bit-identical results, at half the cost (``numpy.cross`` moves axes and
checks shapes on every call, which the buoyancy's per-substep calls on a few hundred
triangles pay thousands of times a simulated minute)."""

from __future__ import annotations

import numpy as np


def cross(a, b) -> np.ndarray:
    a = np.asarray(a)
    b = np.asarray(b)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)
