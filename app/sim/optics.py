"""Phase functions and ray intersections: the numpy twin of ``glsl/common/phase.glsl`` and
``glsl/common/intersect.glsl``, shared by every effect that scatters light or marches a volume
(the atmosphere, both cloud models). Float64, vectorised over the last axis.

Phase functions take cos θ between the light's travel direction and the view ray (cos θ = 1:
looking into the light) and return 1/sr; each integrates to 1 over the sphere.
"""

from __future__ import annotations

import math

import numpy as np

from .maths import normalize

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


# --- Fresnel and refraction: the twin of glsl/common/fresnel.glsl and glsl/surfaces/refraction.glsl
# (spec/003 §2.7). Scalars or arrays (cosines), or (..., 3) vectors (directions).

def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _check_indices(n1, n2):
    if np.any(np.asarray(n1) <= 0.0) or np.any(np.asarray(n2) <= 0.0):
        raise ValueError(f"refractive indices n1={n1!r}, n2={n2!r}: must be > 0")


def schlick_fresnel(f0, cos_theta) -> np.ndarray:
    """spec/003 eq. 5.27: F0 + (1 − F0)(1 − cos θ)^5, cos θ clamped into [0, 1]
    (``SchlickFresnel``, fresnel.glsl)."""
    m = 1.0 - np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)
    return np.asarray(f0, dtype=np.float64) + (1.0 - np.asarray(f0, dtype=np.float64)) * m ** 5


def fresnel_exact(cos_i, n1, n2) -> np.ndarray:
    """spec/003 eq. 5.24, spec/003 eq. 5.25, spec/003 eq. 5.26: unpolarised dielectric
    reflectance ½(Rs + Rp) from medium n1 into n2, cos θ1 clamped into [0, 1]; 1 under total
    internal reflection; denominators kept above 1e-20 (``FresnelExact``)."""
    _check_indices(n1, n2)
    c1 = np.clip(np.asarray(cos_i, dtype=np.float64), 0.0, 1.0)
    n1 = np.asarray(n1, dtype=np.float64)
    n2 = np.asarray(n2, dtype=np.float64)
    sin_t2 = (n1 / n2) ** 2 * (1.0 - c1 * c1)
    tir = sin_t2 > 1.0
    c2 = np.sqrt(np.maximum(1.0 - sin_t2, 0.0))
    rs = (n1 * c1 - n2 * c2) / np.maximum(n1 * c1 + n2 * c2, 1e-20)
    rp = (n1 * c2 - n2 * c1) / np.maximum(n1 * c2 + n2 * c1, 1e-20)
    return np.where(tir, 1.0, np.clip(0.5 * (rs * rs + rp * rp), 0.0, 1.0))


def fresnel_transmittance(cos_i, n1, n2) -> np.ndarray:
    """The transmitted fraction ½(Ts + Tp) from the amplitude coefficients
    ts = 2n1cosθ1/(n1cosθ1 + n2cosθ2), tp = 2n1cosθ1/(n1cosθ2 + n2cosθ1), T = (n2cosθ2/n1cosθ1)t²
    (a check of spec/003 eq. 5.26's energy: R + T = 1; 0 under total internal reflection).
    Needs cos θ1 > 0."""
    _check_indices(n1, n2)
    c1 = np.clip(np.asarray(cos_i, dtype=np.float64), 1e-300, 1.0)
    n1 = np.asarray(n1, dtype=np.float64)
    n2 = np.asarray(n2, dtype=np.float64)
    sin_t2 = (n1 / n2) ** 2 * (1.0 - c1 * c1)
    c2 = np.sqrt(np.maximum(1.0 - sin_t2, 0.0))
    ts = 2.0 * n1 * c1 / (n1 * c1 + n2 * c2)
    tp = 2.0 * n1 * c1 / (n1 * c2 + n2 * c1)
    k = n2 * c2 / (n1 * c1)
    return np.where(sin_t2 > 1.0, 0.0, 0.5 * k * (ts * ts + tp * tp))


def fresnel_schlick(cos_i, n1, n2) -> np.ndarray:
    """spec/003 eq. 5.28, spec/003 eq. 5.29: c = ((n1 − n2)/(n1 + n2))², then Schlick at cos θ1
    for n1 ≤ n2; for n1 > n2 (beyond the thesis) at the transmitted cos θ2, and 1 past the
    critical angle (``FresnelSchlick``)."""
    _check_indices(n1, n2)
    n1 = np.asarray(n1, dtype=np.float64)
    n2 = np.asarray(n2, dtype=np.float64)
    c = ((n1 - n2) / (n1 + n2)) ** 2
    c1 = np.clip(np.asarray(cos_i, dtype=np.float64), 0.0, 1.0)
    sin_t2 = (n1 / n2) ** 2 * (1.0 - c1 * c1)
    inside = n1 > n2
    cos_t = np.where(inside, np.sqrt(np.maximum(1.0 - sin_t2, 0.0)), c1)
    return np.where(inside & (sin_t2 > 1.0), 1.0, schlick_fresnel(c, cos_t))


def refract_direction(v, n, eta):
    """spec/003 eq. 5.22, spec/003 eq. 5.23: r = η(v + n cos θ1) − n cos θ2 for v (toward the
    surface) and n (facing v's origin), both normalised here, η = n1/n2. Returns (r, tir):
    under total internal reflection r = reflect(v, n) = v − 2(n·v)n (``RefractDirection``)."""
    eta = np.asarray(eta, dtype=np.float64)
    if np.any(eta <= 0.0):
        raise ValueError(f"eta={eta!r}: the index ratio n1/n2 must be > 0")
    vv, nn = np.broadcast_arrays(*(normalize(np.asarray(a, np.float64)) for a in (v, n)))
    c1 = np.clip(-_dot(vv, nn), -1.0, 1.0)[..., None]
    e = eta[..., None] if eta.ndim else eta
    k = 1.0 - e * e * (1.0 - c1 * c1)
    tir = k[..., 0] < 0.0
    refr = e * (vv + nn * c1) - nn * np.sqrt(np.maximum(k, 0.0))
    refl = vv + 2.0 * c1 * nn
    out = np.where(tir[..., None], refl, refr)
    return normalize(out), tir


def refract_through_sphere(p, v, centre, radius, eta):
    """Beyond the thesis (which refracts once): the exit direction of v entering the sphere
    (centre, radius) at its surface point p, refracted at entry (η) and exit (1/η). Returns
    (direction, tir); tir where either interface totally reflects (entry: the reflected
    direction; inside: the internally reflected one) (``RefractThroughSphere``)."""
    if radius <= 0.0:
        raise ValueError(f"radius={radius!r}: must be > 0")
    p = np.asarray(p, dtype=np.float64)
    c = np.asarray(centre, dtype=np.float64)
    d, tir1 = refract_direction(v, p - c, eta)
    o = p - c
    b = _dot(o, d)
    t = np.maximum(-b + np.sqrt(np.maximum(b * b - (_dot(o, o) - radius * radius), 0.0)), 0.0)
    q = p + t[..., None] * d
    d2, tir2 = refract_direction(d, c - q, 1.0 / np.asarray(eta, dtype=np.float64))
    return np.where(tir1[..., None], d, d2), tir1 | tir2


def refract_sphere(interfaces: int, p, v, centre, radius, eta):
    """One interface (the thesis's front face) or two (:func:`refract_through_sphere`)
    (``RefractSphere``)."""
    if interfaces not in (1, 2):
        raise ValueError(f"interfaces={interfaces!r}: must be 1 or 2")
    if interfaces == 1:
        return refract_direction(v, np.asarray(p, dtype=np.float64) - np.asarray(centre), eta)
    return refract_through_sphere(p, v, centre, radius, eta)


def distortion_strength(amount, smoothness) -> np.ndarray:
    """The thesis's Smoothness scales the distortion: max(amount · clamp(smoothness), 0)
    (``DistortionStrength``)."""
    return np.maximum(np.asarray(amount, dtype=np.float64)
                      * np.clip(np.asarray(smoothness, dtype=np.float64), 0.0, 1.0), 0.0)


def distort_normal(n, tangent, bitangent, distortion_xy, strength) -> np.ndarray:
    """normalize(n + s(d.x·t + d.y·b)), s = max(strength, 0): the distortion texture as a bump
    map (``DistortNormal``)."""
    d = np.asarray(distortion_xy, dtype=np.float64)
    s = np.maximum(np.asarray(strength, dtype=np.float64), 0.0)[..., None]
    out = (np.asarray(n, dtype=np.float64)
           + s * (d[..., 0:1] * np.asarray(tangent, dtype=np.float64)
                  + d[..., 1:2] * np.asarray(bitangent, dtype=np.float64)))
    return normalize(out)


def refraction_lod(transparency, mip_count) -> np.ndarray:
    """(1 − clamp(T, 0, 1))·max(mipCount − 1, 0): the thesis's Transparency (lower = more
    opaque) as the refraction's sample LOD (``RefractionLod``)."""
    t = np.clip(np.asarray(transparency, dtype=np.float64), 0.0, 1.0)
    return (1.0 - t) * np.maximum(np.asarray(mip_count, dtype=np.float64) - 1.0, 0.0)


def refract_reflect_mix(refracted, reflected, reflectance) -> np.ndarray:
    """lerp(refracted, reflected, clamp(R, 0, 1)): the thesis's final colour
    (``RefractReflectMix``)."""
    r = np.clip(np.asarray(reflectance, dtype=np.float64), 0.0, 1.0)[..., None]
    a = np.asarray(refracted, dtype=np.float64)
    return a + (np.asarray(reflected, dtype=np.float64) - a) * r
