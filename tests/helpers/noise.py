"""Shared by the gradient-noise tests (tests/unit, tests/gl, tests/stability): Perlin's
reference transcribed as plain Python, the float32 view of points, the GLSL probe call and
the expression evaluated at huge coordinates with its numpy twin.
"""

from __future__ import annotations

import math

import numpy as np

from app.sim.noise import cellular, fractal, gradient


def f32(a) -> np.ndarray:
    """Points as the GPU sees them, back in float64 for the twin."""
    return np.asarray(a, dtype=np.float32).astype(np.float64)


def glsl(probe, expr, pts, **kw) -> np.ndarray:
    return probe.evaluate(expr, pts, **kw).astype(np.float64)


# ---- Perlin's reference ------------------------------------------------------------------------

def _reference_noise(x: float, y: float, z: float) -> float:
    """A plain scalar transcription of Perlin's 2002 ImprovedNoise.noise (doubled table p[512]),
    kept apart from the vectorised twin so each checks the other."""
    p = [int(v) for v in gradient.REFERENCE_PERMUTATION] * 2

    def fade(t):
        return t * t * t * (t * (t * 6 - 15) + 10)

    def lerp(t, a, b):
        return a + t * (b - a)

    def grad(h, x, y, z):
        h &= 15
        u = x if h < 8 else y
        v = y if h < 4 else (x if h in (12, 14) else z)
        return (u if h & 1 == 0 else -u) + (v if h & 2 == 0 else -v)

    X, Y, Z = math.floor(x) & 255, math.floor(y) & 255, math.floor(z) & 255
    x, y, z = x - math.floor(x), y - math.floor(y), z - math.floor(z)
    u, v, w = fade(x), fade(y), fade(z)
    A = p[X] + Y
    AA, AB = p[A] + Z, p[A + 1] + Z
    B = p[X + 1] + Y
    BA, BB = p[B] + Z, p[B + 1] + Z
    return lerp(w, lerp(v, lerp(u, grad(p[AA], x, y, z), grad(p[BA], x - 1, y, z)),
                        lerp(u, grad(p[AB], x, y - 1, z), grad(p[BB], x - 1, y - 1, z))),
                lerp(v, lerp(u, grad(p[AA + 1], x, y, z - 1), grad(p[BA + 1], x - 1, y, z - 1)),
                     lerp(u, grad(p[AB + 1], x, y - 1, z - 1),
                          grad(p[BB + 1], x - 1, y - 1, z - 1))))


HUGE_EXPR = ("vec4(PerlinNoise3(P.xyz), PerlinNoise3Periodic(P.xyz, ivec3(6)),"
             " WorleyNoise3Periodic(P.xyz, ivec3(6), 1u).x,"
             " PerlinFbm3Periodic(P.xyz, ivec3(3), 5, 2, 0.5))")


def _huge_twin(pts):
    return np.stack([gradient.perlin3(*pts.T), gradient.perlin3_periodic(*pts.T, 6),
                     cellular.worley3_periodic(*pts.T, 6, seed=1)[0],
                     fractal.perlin_fbm3_periodic(*pts.T, 3)], 1)
