"""Worley (cellular) noise — numpy twin of ``glsl/common/noise_worley.glsl``.

Source: S. Worley, "A cellular texture basis function", SIGGRAPH 1996 (spec/001 §1.1 [50],
spec/000 §1.6 [5]). Vectorised over numpy arrays (shapes that broadcast), float64 inside; the
feature points themselves come from an integer hash and are bit-identical to the GPU's.

The model, for a point p in the unit lattice:

* every cell c ∈ ℤⁿ holds exactly one feature point x_c = c + o(c), o(c) ∈ [0, 1)ⁿ
  (Worley scatters a Poisson-distributed count per cell; the theses use one per cell);
* F1(p) = min_c |p − x_c| and F2(p) the second smallest distance (Euclidean, in cell units);
* the search visits the 3ⁿ cells around p's own cell (9 in 2D, 27 in 3D). A feature point two
  cells away is at least 1 away along that axis, so F1 (F2) is exact wherever it is below 1;
  where the true value exceeds 1 (rare, clustered points) the result is the distance to the
  nearest (second nearest) of the visited points — identical on CPU and GPU;
* helpers: F2 − F1 (cell borders, 0 on the Voronoi edges) and the inverted F1,
  1 − clamp(F1, 0, 1), which is 1 exactly at feature points (spec/001 §6, criterion B4) — the
  billowy pattern of the cloud theses;
* periodic variant: the cell index is wrapped modulo an integer period before it is hashed,
  while the distance uses the unwrapped neighbour position, so the pattern tiles with that
  period and the 3ⁿ search "sees the same point distribution shifted" across the wrap
  (spec/000 §1.6).

Hash: PCG4D (Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020) on
(cx, cy, cz, seed) as uint32 with wrap-around arithmetic: v = v·1664525 + 1013904223, then two
rounds of v.x += v.y·v.w, v.y += v.z·v.x, v.z += v.x·v.y, v.w += v.y·v.z around v ^= v >> 16.
2D uses (cx, cy, 0, seed). The offset is the top 24 bits as float: o = (h >> 8) / 2²⁴,
exact in float32, so GPU and CPU feature points agree to the last bit. Negative cell indices
are taken as their two's-complement uint32 bit pattern (GLSL ``uint(int)`` does the same).

Failure cases: float32 coordinates beyond about 2¹⁶ lose their fraction on the GPU (wrap them,
or use the periodic variant); cells are computed as int, so |p| must stay below 2³¹ (far past
the precision limit anyway); the periodic index is wrapped in floating point before integer
conversion and fixed up into [0, period).
"""

from __future__ import annotations

import numpy as np

_U32 = np.uint32
_MASK = 0xFFFFFFFF


def _u32(a) -> np.ndarray:
    """Two's-complement uint32 view of integer values (any sign), like GLSL ``uint(int)``."""
    return (np.asarray(a, dtype=np.int64) & _MASK).astype(_U32)


def pcg4d(x, y, z, w) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """PCG4D hash of four uint32 arrays (any integer input, wrapped to uint32). Twin of GLSL
    ``Pcg4d``; numpy's uint32 array arithmetic wraps modulo 2³² exactly as GLSL ``uint``."""
    x, y, z, w = np.broadcast_arrays(_u32(x), _u32(y), _u32(z), _u32(w))
    with np.errstate(over="ignore"):
        a, m = _U32(1013904223), _U32(1664525)
        x = x * m + a
        y = y * m + a
        z = z * m + a
        w = w * m + a
        for i in range(2):
            x = x + y * w
            y = y + z * x
            z = z + x * y
            w = w + y * z
            if i == 0:
                x, y, z, w = (x ^ (x >> _U32(16)), y ^ (y >> _U32(16)),
                              z ^ (z >> _U32(16)), w ^ (w >> _U32(16)))
    return x, y, z, w


def _offset(h: np.ndarray) -> np.ndarray:
    """Top 24 bits of a hash as a float in [0, 1) — exact in float32 and float64."""
    return (h >> _U32(8)).astype(np.float64) * (1.0 / 16777216.0)


def feature_offset3(cx, cy, cz, seed: int = 0):
    """o(c) ∈ [0, 1)³ for integer cells (cx, cy, cz)."""
    hx, hy, hz, _ = pcg4d(cx, cy, cz, seed_key(seed))
    return _offset(hx), _offset(hy), _offset(hz)


def feature_offset2(cx, cy, seed: int = 0):
    """o(c) ∈ [0, 1)² for integer cells (cx, cy)."""
    hx, hy, _, _ = pcg4d(cx, cy, 0, seed_key(seed))
    return _offset(hx), _offset(hy)


def feature_point3(cx, cy, cz, seed: int = 0):
    """The feature point x_c = c + o(c) of cells (cx, cy, cz) (of the non-periodic noise; for
    the periodic one pass the wrapped cell and add the period multiple yourself)."""
    ox, oy, oz = feature_offset3(cx, cy, cz, seed)
    return np.asarray(cx) + ox, np.asarray(cy) + oy, np.asarray(cz) + oz


def feature_point2(cx, cy, seed: int = 0):
    ox, oy = feature_offset2(cx, cy, seed)
    return np.asarray(cx) + ox, np.asarray(cy) + oy


def seed_key(seed: int | None) -> int:
    """Worley seeds are uint32; ``None`` means 0."""
    if seed is None:
        return 0
    seed = int(seed)
    if not 0 <= seed <= _MASK:
        raise ValueError(f"Worley seed {seed} is outside [0, 2^32 - 1]")
    return seed


def _as_period(period, n: int) -> np.ndarray | None:
    if period is None:
        return None
    per = np.broadcast_to(np.asarray(period, dtype=np.int64), (n,)).copy()
    if np.any(per < 1):
        raise ValueError(f"Worley period {tuple(per)} has an entry below 1: "
                         "allowed positive integers")
    return per


def _worley(coords, period, seed) -> tuple[np.ndarray, np.ndarray]:
    coords = np.broadcast_arrays(*[np.asarray(c, dtype=np.float64) for c in coords])
    n = len(coords)
    cell_f = [np.floor(c) for c in coords]
    frac = [c - f for c, f in zip(coords, cell_f)]
    if period is None:
        cell = [f.astype(np.int64) for f in cell_f]
    else:
        cell = [np.mod(f, float(per)).astype(np.int64) % per for f, per in zip(cell_f, period)]
    seed = seed_key(seed)
    d1 = np.full(coords[0].shape, np.inf)
    d2 = np.full(coords[0].shape, np.inf)
    # The GLSL loops z outermost, then y, then x; the minima do not depend on the order.
    for offs in np.ndindex(*(3,) * n):
        nb = [o - 1 for o in reversed(offs)]  # (dx, dy[, dz]) with dx fastest
        idx = [c + o for c, o in zip(cell, nb)]
        if period is not None:
            idx = [(i + per) % per for i, per in zip(idx, period)]
        if n == 3:
            o = feature_offset3(idx[0], idx[1], idx[2], seed)
        else:
            o = feature_offset2(idx[0], idx[1], seed)
        dd = sum((float(k) + oi - f) ** 2 for k, oi, f in zip(nb, o, frac))
        d2 = np.minimum(d2, np.maximum(d1, dd))
        d1 = np.minimum(d1, dd)
    return np.sqrt(d1), np.sqrt(d2)


def worley3(x, y, z, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(F1, F2) at (x, y, z); twin of GLSL ``WorleyNoise3``."""
    return _worley((x, y, z), None, seed)


def worley2(x, y, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(F1, F2) at (x, y); twin of GLSL ``WorleyNoise2``."""
    return _worley((x, y), None, seed)


def worley3_periodic(x, y, z, period, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(F1, F2) tiling with ``period`` cells (int or 3 ints); twin of ``WorleyNoise3Periodic``."""
    return _worley((x, y, z), _as_period(period, 3), seed)


def worley2_periodic(x, y, period, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(F1, F2) tiling with ``period`` cells (int or 2 ints); twin of ``WorleyNoise2Periodic``."""
    return _worley((x, y), _as_period(period, 2), seed)


def worley_f2_minus_f1(f1, f2) -> np.ndarray:
    """F2 − F1: 0 on the Voronoi cell borders; twin of ``WorleyF2MinusF1``."""
    return np.asarray(f2) - np.asarray(f1)


def worley_inverted_f1(f1) -> np.ndarray:
    """1 − clamp(F1, 0, 1): 1 at feature points; twin of ``WorleyInvertedF1``."""
    return 1.0 - np.clip(f1, 0.0, 1.0)
