"""Numpy twins of the day–night sky's shader (``glsl/sky/sky_radiance.glsl``; spec/000 §1.7,
annex B): the tests compare the GPU with these, function by function."""

from __future__ import annotations

import math

import numpy as np

from .maths import smoothstep

MIE_G = -0.990
MIE_G2 = 0.9801

def mie_phase(c, c2, sun_size: float = 0.05):
    """spec/000 eq. B.2: ``getMiePhase`` with the SunSize exponent and the 1e-4 clamp."""
    t = 1.0 + MIE_G2 - 2.0 * MIE_G * np.asarray(c, dtype=np.float64)
    t = np.maximum(t, 0.0) ** (sun_size**0.65 * 10.0)
    t = np.maximum(t, 1e-4)
    return 1.5 * ((1.0 - MIE_G2) / (2.0 + MIE_G2)) * (1.0 + np.asarray(c2)) / t


def sun_term(cos_angle, sun_size: float = 0.05, intensity: float = 2.0):
    """Sun disk value (per unit SunCol) at angle ``acos(cos_angle)`` from the sun
    (spec/000 eq. B.3, ``calcSunAttenuation``, times SunIntensity)."""
    f = np.clip(np.asarray(cos_angle, dtype=np.float64), 0.0, 1.0) ** 5
    return mie_phase(-f, f * f, sun_size) * intensity


def scattering_intensity_factor(sun_sin_elevation):
    """scatInt = max(0.15, smoothstep(0.6, 0.0, sin elevation)), the reversed ramp by hand
    (spec/000 eq. B.4)."""
    return np.maximum(0.15, 1.0 - smoothstep(0.0, 0.6, sun_sin_elevation))


def cubemap_face_direction(face: int, s, t) -> np.ndarray:
    """Twin of ``CubemapFaceDirection`` (glsl/common/cubemap.glsl)."""
    s, t = np.broadcast_arrays(np.asarray(s, dtype=np.float64), np.asarray(t, dtype=np.float64))
    one = np.ones_like(s)
    d = {
        0: (one, -t, -s), 1: (-one, -t, s), 2: (s, one, t),
        3: (s, -one, -t), 4: (s, -t, one), 5: (-s, -t, -one),
    }[face]
    d = np.stack(d, axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def elevation_u(directions: np.ndarray) -> np.ndarray:
    """sphereUV.y = asin(p.y) / (π/2), the sky gradient's coordinate (spec/000 eq. B.4)."""
    return np.arcsin(np.clip(directions[..., 1], -1.0, 1.0)) / (math.pi / 2)
