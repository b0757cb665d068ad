"""Small vector helpers for the physics' inner loops.

``cross`` is ``numpy.cross`` for 3-vectors (the last axis), written out: the same products
in the same order, so bit-identical results, at half the cost (``numpy.cross`` moves axes and
checks shapes on every call, which the buoyancy's per-substep calls on a few hundred
triangles pay thousands of times a simulated minute).

``norm`` and ``length`` are ``numpy.linalg.norm`` along an axis and of a whole vector, for real
floating arrays: the very reductions ``numpy.linalg.norm`` ends in (√Σx² by ``add.reduce``, and
√(x·x) by ``dot``), so bit-identical, without its argument handling (several µs a call, most of
the cost on 3-vectors and a few hundred rows)."""

from __future__ import annotations

import math

import numpy as np


def cross(a, b, out: np.ndarray | None = None) -> np.ndarray:
    """``numpy.cross(a, b)`` of 3-vectors (written into ``out`` when given)."""
    a = np.asarray(a)
    b = np.asarray(b)
    if a.shape == b.shape == (3,) and a.dtype == b.dtype == np.float64 and out is None:
        # two single vectors: the same six products and three differences on Python floats
        # (IEEE doubles, one rounding each, as numpy's), without four gathers of three numbers
        ax, ay, az = a.tolist()
        bx, by, bz = b.tolist()
        return np.array([ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx])
    # (a₁b₂ − a₂b₁, a₂b₀ − a₀b₂, a₀b₁ − a₁b₀) as whole arrays: a's components cycled once
    # times b's cycled twice, minus the reverse (four gathers and three operations, in place of
    # nine operations on strided columns and a stack)
    return np.subtract(a.take(_NEXT, -1) * b.take(_AFTER_NEXT, -1),
                       a.take(_AFTER_NEXT, -1) * b.take(_NEXT, -1), out=out)


#: the components cycled once (1, 2, 0) and twice (2, 0, 1)
_NEXT = np.array([1, 2, 0])
_AFTER_NEXT = np.array([2, 0, 1])


def norm(a, axis: int = -1, keepdims: bool = False) -> np.ndarray:
    """``numpy.linalg.norm(a, axis=axis, keepdims=keepdims)`` of a real floating array: √Σx²."""
    a = _floating(a)
    if a.ndim and a.shape[-1] == 3 and axis in (-1, a.ndim - 1):
        # a reduction over a last axis of three adds in order, (x² + y²) + z² (measured
        # bit-identical, every shape and sign of zero), and pays its loop's set-up per row: the
        # same additions written out on the columns cost a sixth
        x, y, z = a[..., 0], a[..., 1], a[..., 2]
        s = np.sqrt(x * x + y * y + z * z)
        return s[..., None] if keepdims else s
    return np.sqrt(np.add.reduce(a * a, axis=axis, keepdims=keepdims))  # what .sum() calls


def length(v) -> float:
    """``float(numpy.linalg.norm(v))`` of a real floating vector: √(v·v)."""
    v = _floating(v).ravel()
    return math.sqrt(v.dot(v))


def _floating(a) -> np.ndarray:
    """``a`` as an array, integers as float64 (as ``numpy.linalg.norm`` takes them)."""
    a = np.asarray(a)
    return a if a.dtype.kind == "f" else a.astype(float)
