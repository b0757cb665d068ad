"""Global fog — numpy twin of ``glsl/common/fog.glsl`` (spec/003 §2.11 b; beyond the thesis,
Quílez's analytic exponential height fog) and the settings a scene's fog publishes in the frame's
``fog`` slot (:class:`FogSettings`; :func:`fog_uniforms` turns them into fog.glsl's uniforms).

Factors follow Unity's convention: 1 means no fog, 0 all fog; a surface's colour becomes
``lerp(fog_colour, colour, factor)``. Distances are the thesis's: from Unity's reversed clip z,
i.e. the planar depth past the near plane stretched by f/(f − n) (:func:`fog_distance`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

#: fog.glsl's uFogMode
MODES = ("off", "linear", "exp", "exp2")


@dataclass(frozen=True)
class FogSettings:
    """What the ``fog`` slot holds: Unity's Lighting › Fog panel (spec/003 Fig. 123) and the
    height-fog switch."""

    mode: str = "exp2"
    density: float = 0.1  # t of spec/003 eq. 7.28 and 7.29 [1/m]
    start: float = 0.0  # s of spec/003 eq. 7.27 [m]
    end: float = 10.0  # e of spec/003 eq. 7.27 [m]
    colour: tuple[float, float, float] = (0.5, 0.55, 0.6)  # linear radiance
    per_pixel: bool = False
    height: bool = False
    height_density: float = 0.05  # a: density at height_base [1/m]
    height_falloff: float = 0.2  # b [1/m]
    height_base: float = 0.0  # y0 [m]

    def __post_init__(self):
        if self.mode not in MODES:
            raise ValueError(f"fog mode {self.mode!r}: allowed {', '.join(MODES)}")


def fog_uniforms(settings: FogSettings | None, camera_position, near: float,
                 far: float) -> dict[str, Any]:
    """fog.glsl's uniforms for ``settings`` seen from a camera (None: fog off)."""
    if settings is None:
        return {"uFogMode": 0, "uFogHeight": False, "uFogPerPixel": False,
                "uFogNearFar": (float(near), float(far)), "uFogParams": (0.0, 0.0, 1.0),
                "uFogColor": (0.0, 0.0, 0.0), "uFogHeightParams": (0.0, 1.0, 0.0),
                "uFogCameraPos": tuple(float(v) for v in camera_position)}
    s = settings
    return {"uFogMode": MODES.index(s.mode), "uFogParams": (s.density, s.start, s.end),
            "uFogColor": tuple(float(c) for c in s.colour),
            "uFogNearFar": (float(near), float(far)), "uFogPerPixel": bool(s.per_pixel),
            "uFogHeight": bool(s.height),
            "uFogHeightParams": (s.height_density, s.height_falloff, s.height_base),
            "uFogCameraPos": tuple(float(v) for v in camera_position)}


def _near_far(near: float, far: float) -> tuple[float, float]:
    n = max(float(near), 1e-6)
    return n, max(float(far), n + 1e-6)


def fog_unity_clip_z(w: ArrayLike, near: float, far: float) -> np.ndarray:
    """Unity's reversed clip z of a view depth w: n·(f − w)/(f − n) (spec/003 eq. 7.24)."""
    n, f = _near_far(near, far)
    return n * (f - np.asarray(w, np.float64)) / (f - n)


def fog_distance(w: ArrayLike, near: float, far: float) -> np.ndarray:
    """spec/003 eq. 7.24: d = max(f·(1 − z_u/n), 0); 0 at the near plane (spec/003 eq. 7.26),
    f at the far plane (spec/003 eq. 7.25)."""
    n, f = _near_far(near, far)
    z = fog_unity_clip_z(np.maximum(np.asarray(w, np.float64), 0.0), near, far)
    return np.maximum(f * (1.0 - z / n), 0.0)


def fog_factor_linear(d: ArrayLike, start: float, end: float) -> np.ndarray:
    """spec/003 eq. 7.27: (e − d)/(e − s), clamped; a step at s when e = s."""
    d = np.asarray(d, np.float64)
    span = end - start
    if abs(span) < 1e-6:
        return np.where(d < start, 1.0, 0.0)
    return np.clip((end - d) / span, 0.0, 1.0)


def fog_factor_exp(d: ArrayLike, density: float) -> np.ndarray:
    """spec/003 eq. 7.28: exp(−t·d)."""
    return np.clip(np.exp(-density * np.asarray(d, np.float64)), 0.0, 1.0)


def fog_factor_exp2(d: ArrayLike, density: float) -> np.ndarray:
    """spec/003 eq. 7.29: exp(−(t·d)²)."""
    x = density * np.asarray(d, np.float64)
    return np.clip(np.exp(-x * x), 0.0, 1.0)


def fog_factor(d: ArrayLike, settings: FogSettings) -> np.ndarray:
    """The mode's factor (spec/003 eq. 7.23: the fog's intensity is 1 − this); 1 when off."""
    s = settings
    if s.mode == "linear":
        return fog_factor_linear(d, s.start, s.end)
    if s.mode == "exp":
        return fog_factor_exp(d, s.density)
    if s.mode == "exp2":
        return fog_factor_exp2(d, s.density)
    return np.ones(np.shape(d))


def fog_one_minus_exp_over_x(x: ArrayLike) -> np.ndarray:
    """(1 − e^(−x))/x, with the series 1 − x/2 + x²/6 where |x| < 1e-3."""
    x = np.asarray(x, np.float64)
    small = np.abs(x) < 1e-3
    safe = np.where(small, 1.0, x)
    return np.where(small, 1.0 - 0.5 * x + x * x / 6.0, (1.0 - np.exp(-safe)) / safe)


def fog_height_transmittance(p: ArrayLike, camera: ArrayLike, a: float, b: float,
                             y0: float) -> np.ndarray:
    """Quílez 2010: exp(−τ) of the density a·exp(−b·(y − y0)) from ``camera`` to ``p``."""
    ray = np.asarray(p, np.float64) - np.asarray(camera, np.float64)
    t = np.linalg.norm(ray, axis=-1)
    safe_t = np.maximum(t, 1e-6)
    a, b = max(a, 0.0), max(b, 1e-6)
    dy = ray[..., 1] / safe_t
    start = np.clip(-b * (np.asarray(camera, np.float64)[..., 1] - y0), -60.0, 60.0)
    tau = a * np.exp(start) * t * fog_one_minus_exp_over_x(np.clip(b * dy * t, -60.0, 60.0))
    return np.where(t < 1e-6, 1.0, np.clip(np.exp(-tau), 0.0, 1.0))


def fog_height_reference(p: ArrayLike, camera: ArrayLike, a: float, b: float, y0: float,
                         steps: int = 4096) -> np.ndarray:
    """The height fog's transmittance by midpoint integration of the density along the ray (the
    reference the analytic form is tested and charted against)."""
    p = np.asarray(p, np.float64)
    c = np.asarray(camera, np.float64)
    s = (np.arange(steps) + 0.5) / steps
    pts = c[..., None, :] + (p - c)[..., None, :] * s[:, None]
    rho = a * np.exp(-b * (pts[..., 1] - y0))
    t = np.linalg.norm(p - c, axis=-1)
    return np.exp(-rho.mean(axis=-1) * t)


def fog_apply(colour: ArrayLike, factor: ArrayLike, fog_colour: ArrayLike) -> np.ndarray:
    """lerp(fog colour, colour, f): the lerp with its operands swapped (spec/003 §2.11)."""
    f = np.clip(np.asarray(factor, np.float64), 0.0, 1.0)[..., None]
    return np.asarray(fog_colour, np.float64) * (1.0 - f) + np.asarray(colour, np.float64) * f
