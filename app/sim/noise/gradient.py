"""Perlin's improved gradient noise — numpy twin of ``glsl/common/noise_perlin.glsl``.

Source: K. Perlin, "Improving Noise", SIGGRAPH 2002 (cited as [35] in spec/001 §1.1 and as the
1985 model's successor in spec/000 §1.6). Everything here is vectorised over numpy arrays
(any shapes that broadcast together) and computed in float64.

The model, for a point p with lattice cell i = ⌊p⌋ and offset f = p − i ∈ [0, 1)³:

* each lattice corner c ∈ i + {0, 1}³ owns a pseudo-random gradient g(c), chosen by a hash
  through a permutation table P of 0..255:
  h(c) = P[(P[(P[cx mod 256] + cy) mod 256] + cz) mod 256]   (3D; 2D stops after two lookups);
* the corner's contribution is the linear ramp g(c) · (p − c), zero at the corner itself;
* the eight ramps are blended with the quintic fade s(t) = 6t⁵ − 15t⁴ + 10t³ per axis
  (s' = s'' = 0 at t = 0 and 1, so the noise is C² across cell faces — the 2002 fix of the
  1985 cubic 3t² − 2t³, whose second derivative jumps there).

3D gradients: the 12 vectors from the centre of a cube to its edge midpoints,
(±1, ±1, 0), (±1, 0, ±1), (0, ±1, ±1), picked by h & 15; the 16 entries repeat (1,1,0),
(−1,1,0), (0,−1,1), (0,−1,−1) so the choice needs no division (Perlin's ``grad``).

2D gradients (our choice; Perlin 2002 gives only 3D): the 8 directions at 45° steps with
length √2, picked by h & 7 — g_k = √2 (cos 45°k, sin 45°k):
(√2, 0), (1, 1), (0, √2), (−1, 1), (−√2, 0), (−1, −1), (0, −√2), (1, −1).
The set is symmetric under quarter turns and mirror images, so the noise has no preferred axis,
and with length √2 the 2D noise stays within [−1, 1] (bound attained at a cell centre when all
four corner gradients point at it).

Range: |perlin3| ≤ PERLIN3_BOUND = 1.0363538 — the maximum over a cell of
Σ_corners weight · max_g g·(p − c) (the weights are non-negative, so choosing the best
gradient per corner bounds every permutation), found at f ≈ (0.355, 0.481, 0.5) and
symmetric points; |perlin2| ≤ PERLIN2_BOUND = 1 (same argument, maximum at the centre).

Seeds: ``None`` or 0 is Perlin's published permutation (his reference ``ImprovedNoise``
values are reproduced to the last bit: ``perlin3(3.14, 42, 7) == 0.13691995878400012``); any
other integer is ``numpy.random.default_rng(seed).permutation(256)``.

Periodic variants wrap the lattice index modulo an integer ``period`` per axis before hashing,
so the noise repeats every ``period`` units (the non-periodic noise is the periodic one with
period 256 — the table's own period).

Failure cases: coordinates beyond about 2¹⁶ lose the fractional part in float32 on the GPU
(the twin, in float64, does not), so keep |p| small there and wrap offsets or time modulo 256
(or the period) on the CPU; lattice indices are wrapped in floating point before any integer
conversion, so huge or negative coordinates never overflow an int. Beyond |p| ~ 2²⁴ the GPU's
wrap by a non power-of-two period is inexact (it stays in range, the value finite and bounded)
while the twin's float64 wrap is exact: the two agree only below that.
"""

from __future__ import annotations

import numpy as np

#: Ken Perlin's permutation of 0..255 from his 2002 reference implementation (ImprovedNoise).
REFERENCE_PERMUTATION = np.array([
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30,
    69, 142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94,
    252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171,
    168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60,
    211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1,
    216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86,
    164, 100, 109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118,
    126, 255, 82, 85, 212, 207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170,
    213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39,
    253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34,
    242, 193, 238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49,
    192, 214, 31, 181, 199, 106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254,
    138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180,
], dtype=np.int64)

#: max |perlin3| over all permutations (see module doc).
PERLIN3_BOUND = 1.0363538
#: max |perlin2| over all permutations (see module doc).
PERLIN2_BOUND = 1.0

_SQRT2 = float(np.sqrt(2.0))
#: The 2D gradient set, indexed by hash & 7 (the same table as kPerlinGradients2 in GLSL).
GRADIENTS2 = np.array([
    (_SQRT2, 0.0), (1.0, 1.0), (0.0, _SQRT2), (-1.0, 1.0),
    (-_SQRT2, 0.0), (-1.0, -1.0), (0.0, -_SQRT2), (1.0, -1.0),
])

def seed_key(seed: int | None) -> int:
    """The canonical seed: ``None`` and 0 both name Perlin's reference permutation."""
    if seed is None:
        return 0
    seed = int(seed)
    if seed < 0:
        raise ValueError(f"noise seed {seed} is negative: "
                         "allowed 0 (Perlin's table) or a positive integer")
    return seed


def permutation(seed: int | None = None) -> np.ndarray:
    """The permutation table of 0..255 (int64, length 256) for ``seed``.

    ``None`` or 0: Perlin's published table; otherwise ``default_rng(seed).permutation(256)``.
    This is exactly what the GPU texture ``uPerlinPermutation`` holds
    (``app.render.noise.GradientNoiseTextures``)."""
    key = seed_key(seed)
    if key == 0:
        table = REFERENCE_PERMUTATION.copy()
    else:
        table = np.random.default_rng(key).permutation(256).astype(np.int64)
    table.setflags(write=False)
    return table


def fade(t):
    """Perlin's quintic fade 6t⁵ − 15t⁴ + 10t³, written as in his reference code."""
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def _lerp(t, a, b):
    return a + t * (b - a)  # the reference's operation order, so values match it bit for bit


def _grad3(h, x, y, z):
    """g(h & 15) · (x, y, z) with Perlin's bit tests (no multiplications)."""
    h = h & 15
    u = np.where(h < 8, x, y)
    v = np.where(h < 4, y, np.where((h == 12) | (h == 14), x, z))
    return np.where(h & 1 == 0, u, -u) + np.where(h & 2 == 0, v, -v)


def _grad2(h, x, y):
    g = GRADIENTS2[h & 7]
    return g[..., 0] * x + g[..., 1] * y


def _as_period(period, n: int) -> np.ndarray:
    per = np.broadcast_to(np.asarray(period, dtype=np.int64), (n,)).copy()
    if np.any(per < 1):
        raise ValueError(f"noise period {tuple(per)} has an entry below 1: "
                         "allowed positive integers")
    return per


def _lattice(coord, period: int):
    """(i0, i1, f): the cell's two lattice indices wrapped into [0, period) and the offset."""
    c = np.asarray(coord, dtype=np.float64)
    cell = np.floor(c)
    i0 = np.mod(cell, float(period)).astype(np.int64) % period  # float wrap first: no int overflow
    return i0, (i0 + 1) % period, c - cell


def _noise3(x, y, z, period, perm) -> np.ndarray:
    x, y, z = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64),
                                  np.asarray(z, np.float64))
    X0, X1, x = _lattice(x, int(period[0]))
    Y0, Y1, y = _lattice(y, int(period[1]))
    Z0, Z1, z = _lattice(z, int(period[2]))
    u, v, w = fade(x), fade(y), fade(z)
    p = perm
    A, B = p[X0 & 255], p[X1 & 255]          # first lookup, per x index
    AA, AB = p[(A + Y0) & 255], p[(A + Y1) & 255]
    BA, BB = p[(B + Y0) & 255], p[(B + Y1) & 255]

    def h(row, zi):
        return p[(row + zi) & 255]

    return _lerp(
        w,
        _lerp(v, _lerp(u, _grad3(h(AA, Z0), x, y, z), _grad3(h(BA, Z0), x - 1, y, z)),
              _lerp(u, _grad3(h(AB, Z0), x, y - 1, z), _grad3(h(BB, Z0), x - 1, y - 1, z))),
        _lerp(v, _lerp(u, _grad3(h(AA, Z1), x, y, z - 1), _grad3(h(BA, Z1), x - 1, y, z - 1)),
              _lerp(u, _grad3(h(AB, Z1), x, y - 1, z - 1), _grad3(h(BB, Z1), x - 1, y - 1, z - 1))),
    )


def _noise2(x, y, period, perm) -> np.ndarray:
    x, y = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
    X0, X1, x = _lattice(x, int(period[0]))
    Y0, Y1, y = _lattice(y, int(period[1]))
    u, v = fade(x), fade(y)
    p = perm
    A, B = p[X0 & 255], p[X1 & 255]
    return _lerp(
        v,
        _lerp(u, _grad2(p[(A + Y0) & 255], x, y), _grad2(p[(B + Y0) & 255], x - 1, y)),
        _lerp(u, _grad2(p[(A + Y1) & 255], x, y - 1), _grad2(p[(B + Y1) & 255], x - 1, y - 1)),
    )


def perlin3(x, y, z, seed: int | None = None) -> np.ndarray:
    """Improved noise at (x, y, z); twin of GLSL ``PerlinNoise3``. |value| ≤ PERLIN3_BOUND,
    0 at every integer lattice point, period 256 on each axis."""
    return _noise3(x, y, z, (256, 256, 256), permutation(seed))


def perlin2(x, y, seed: int | None = None) -> np.ndarray:
    """2D gradient noise (8 gradients, see module doc); twin of GLSL ``PerlinNoise2``.
    |value| ≤ 1, 0 at lattice points, period 256."""
    return _noise2(x, y, (256, 256), permutation(seed))


def perlin3_periodic(x, y, z, period, seed: int | None = None) -> np.ndarray:
    """``perlin3`` with lattice indices wrapped modulo ``period`` (int or 3 ints): tiles with
    that period. Twin of GLSL ``PerlinNoise3Periodic``."""
    return _noise3(x, y, z, _as_period(period, 3), permutation(seed))


def perlin2_periodic(x, y, period, seed: int | None = None) -> np.ndarray:
    """``perlin2`` tiled with ``period`` (int or 2 ints). Twin of GLSL ``PerlinNoise2Periodic``."""
    return _noise2(x, y, _as_period(period, 2), permutation(seed))
