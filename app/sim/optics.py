"""Phase functions and ray intersections: the numpy twin of ``glsl/common/phase.glsl`` and
``glsl/common/intersect.glsl``, shared by every effect that scatters light or marches a volume
(the atmosphere, both cloud models). Float64, vectorised over the last axis.

Phase functions take cos θ between the light's travel direction and the view ray (cos θ = 1:
looking into the light) and return 1/sr; each integrates to 1 over the sphere.
"""

from __future__ import annotations

import math

import numpy as np

#: direction components smaller than this in magnitude are replaced by ±TINY (ray_box)
TINY = 1.0e-20


def henyey_greenstein(cos_theta, g):
    """spec/001 eq. 4.19 (also spec/000 eq. 3.1): (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}),
    the cosine clamped into [−1, 1] and the denominator kept above 1e-6 (``HenyeyGreenstein``)."""
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), -1.0, 1.0)
    g = np.asarray(g, dtype=np.float64)
    denom = np.maximum(1.0 + g * g - 2.0 * g * c, 1e-6)
    return (1.0 - g * g) / (4.0 * math.pi * denom * np.sqrt(denom))


def phase_rayleigh(mu):
    """Rayleigh phase 3/(16π) (1 + μ²), μ = cos θ (spec/002 §1.2; ``PhaseRayleigh``)."""
    mu = np.asarray(mu, dtype=np.float64)
    return 3.0 / (16.0 * np.pi) * (1.0 + mu * mu)


def phase_mie_cornette_shanks(mu, g):
    """Cornette–Shanks phase (spec/002 §1.2, after Yusov; ``PhaseMieCornetteShanks``)::

        P_M(μ) = 1/(4π) · 3(1 − g²) / (2(2 + g²)) · (1 + μ²) / (1 + g² − 2gμ)^{3/2}

    Normalised to 1 over the sphere for any |g| < 1; equals :func:`phase_rayleigh` at g = 0;
    forward/backward ratio ((1+g)/(1−g))³. At g = ±1 the denominator vanishes at μ = g: callers
    validate g (the shader clamps it to |g| ≤ 0.9999)."""
    mu = np.asarray(mu, dtype=np.float64)
    g = np.asarray(g, dtype=np.float64)
    g2 = g * g
    return (1.0 / (4.0 * np.pi) * 3.0 * (1.0 - g2) / (2.0 * (2.0 + g2))
            * (1.0 + mu * mu) / (1.0 + g2 - 2.0 * g * mu) ** 1.5)


def ray_box(origin, direction, box_min, box_max):
    """Slab method (``RayBoxIntersect``): (t_near, t_far) along origin + t·direction, unclamped
    (either may be negative); the ray hits the box when t_far ≥ max(t_near, 0). Direction
    components below :data:`TINY` in magnitude become ±TINY (their sign kept, + for zero), so
    axis-parallel rays give no NaN."""
    o = np.asarray(origin, dtype=np.float64)
    d = np.array(direction, dtype=np.float64)
    d = np.where(np.abs(d) < TINY, np.where(d >= 0.0, TINY, -TINY), d)
    t0 = (np.asarray(box_min, dtype=np.float64) - o) / d
    t1 = (np.asarray(box_max, dtype=np.float64) - o) / d
    return np.minimum(t0, t1).max(axis=-1), np.maximum(t0, t1).min(axis=-1)


def ray_sphere(origin, direction, centre, radius):
    """Distances (near, far) along ``origin + t·direction`` (``direction`` normalised here) to
    the sphere of ``radius`` about ``centre``; NaN where the line misses it; either may be
    negative (``RaySphereIntersect``).

    Stable for planet-sized spheres (Numerical Recipes): with b = (o − C)·d and
    c = (|o − C| − R)(|o − C| + R), q = −(b + sign(b)·√(b² − c)) gives t = q and t = c/q without
    cancellation; the miss is decided on the discriminant b² − c (spec/001 erratum 7)."""
    o = np.asarray(origin, dtype=np.float64) - np.asarray(centre, dtype=np.float64)
    d = np.asarray(direction, dtype=np.float64)
    d = d / np.linalg.norm(d, axis=-1, keepdims=True)
    o, d = np.broadcast_arrays(o, d)
    b = np.einsum("...i,...i->...", o, d)
    ro = np.linalg.norm(o, axis=-1)
    c = (ro - radius) * (ro + radius)
    disc = b * b - c
    miss = disc < 0.0
    sq = np.sqrt(np.where(miss, 0.0, disc))
    q = -(b + np.where(b >= 0.0, sq, -sq))
    with np.errstate(divide="ignore", invalid="ignore"):
        other = np.where(q != 0.0, c / np.where(q != 0.0, q, 1.0), -b)
    near = np.where(miss, np.nan, np.minimum(q, other))
    far = np.where(miss, np.nan, np.maximum(q, other))
    return near, far
