"""A calm sea plane below a sky (beyond the theses): the numpy twin of
``glsl/common/sea_plane.glsl``, which the day–night sky (``SkySea``) and the Preetham sky
(``PreethamSea``) share. Float64, vectorised over the leading axes of the view directions.

Each sky supplies what is its own — its radiance toward :func:`sea_reflection_direction` and at
the horizon (:func:`sea_horizon_direction`), its ambient, the main light — and
:func:`sea_plane_radiance` does the rest: Schlick 1994's Fresnel at the incidence the waves
leave, the body lit by the ambient and the light, the light's Beckmann glitter for Cox & Munk
1954's slope variance, haze toward the horizon over distance. See the GLSL file's header for the
equations and the guards (the same here).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..params import Param
from .optics import schlick_fresnel  # noqa: F401  (the one twin of fresnel.glsl's SchlickFresnel; re-exported)

#: Fresnel reflectance of water at normal incidence (n = 1.333)
SEA_F0 = 0.0204
#: what a sky shows below its horizon: its source's clamped horizon colour, or the sea plane
GROUNDS = ("horizon", "sea")


def ground_params(group: str, section: str, horizon_doc: str, sky_doc: str) -> list[Param]:
    """``<group>.ground`` (horizon | sea) and ``<group>.sea_wind``, as each sky declares them:
    ``horizon_doc`` says what its horizon colour is, ``sky_doc`` names the sky the sea reflects."""
    return [
        Param(f"{group}.ground", "horizon", doc=f"below the horizon: horizon = {horizon_doc}; "
              f"sea = beyond the theses, a calm sea plane that reflects {sky_doc} (Fresnel), lit "
              "by the main light and the sky's ambient, with the main light's glitter and haze "
              "toward the horizon", kind="choice", choices=GROUNDS, section=section),
        Param(f"{group}.sea_wind", 5.0, 0.0, 30.0, "wind speed that roughens the sea plane's "
              "glitter (Cox–Munk slope variance 0.003 + 0.00512·U)", step=0.5, unit="m/s",
              section=section),
    ]


def cox_munk_mss(wind_speed: float) -> float:
    """Cox & Munk 1954's isotropic slope variance 0.003 + 0.00512·U for the wind U (m/s)."""
    return 0.003 + 0.00512 * float(wind_speed)


def sea_rough_incidence(p, mss: float) -> np.ndarray:
    """cos θr = min(√((n·v)² + mss), 1), n·v = max(−p.y, 1e-4) (``SeaRoughIncidence``)."""
    nv = np.maximum(-np.asarray(p, dtype=np.float64)[..., 1], 1e-4)
    return np.minimum(np.sqrt(nv * nv + mss), 1.0)


def sea_reflection_direction(p, mss: float) -> np.ndarray:
    """p mirrored and lifted to the incidence θr (``SeaReflectionDirection``), (…, 3)."""
    p = np.asarray(p, dtype=np.float64)
    c = sea_rough_incidence(p, mss)
    flat = p * np.array([1.0, 0.0, 1.0])
    horiz = np.maximum(np.hypot(p[..., 0], p[..., 2]), 1e-6)
    r = flat * (np.sqrt(1.0 - c * c) / horiz)[..., None]
    r[..., 1] = c
    return r / np.linalg.norm(r, axis=-1, keepdims=True)


def sea_horizon_direction(p) -> np.ndarray:
    """normalize(p.x, 1e-4, p.z) (``SeaHorizonDirection``)."""
    p = np.asarray(p, dtype=np.float64)
    h = np.stack([p[..., 0], np.full(p.shape[:-1], 1e-4), p[..., 2]], axis=-1)
    return h / np.linalg.norm(h, axis=-1, keepdims=True)


def sea_beckmann(nh, mss: float) -> np.ndarray:
    """exp(−tan²θh / mss) / (π·mss·cos⁴θh), cos²θh ≥ 1e-4 (``SeaBeckmann``)."""
    c2 = np.maximum(np.asarray(nh, dtype=np.float64) ** 2, 1e-4)
    tan2 = (1.0 - c2) / c2
    return np.exp(-tan2 / mss) / (math.pi * mss * c2 * c2)


def sea_plane_radiance(p, reflected, horizon, sky_ambient, light_dir, light_radiance,
                       body_color, mss: float, glitter: float, eye_height: float,
                       haze_distance: float) -> np.ndarray:
    """The sea's radiance toward unit directions ``p`` (…, 3), p.y < 0 (``SeaPlaneRadiance``).

    ``reflected`` and ``horizon`` (…, 3) or (3,): the sky's radiance toward
    :func:`sea_reflection_direction` and :func:`sea_horizon_direction`; ``sky_ambient``,
    ``light_radiance``, ``body_color``: RGB; ``light_dir``: unit, toward the light."""
    p = np.asarray(p, dtype=np.float64)
    nv = np.maximum(-p[..., 1], 1e-4)
    v = -p
    F = schlick_fresnel(SEA_F0, sea_rough_incidence(p, mss))[..., None]
    light = np.asarray(light_dir, dtype=np.float64)
    E = np.asarray(light_radiance, dtype=np.float64)
    body = np.asarray(body_color, dtype=np.float64) * (np.asarray(sky_ambient, dtype=np.float64)
                                                      + E * max(float(light[1]), 0.0) / math.pi)
    h = light + v
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    nh = np.maximum(h[..., 1], 0.0)
    vh = np.maximum(np.einsum("...i,...i->...", v, h), 1e-3)
    nl = max(float(light[1]), 0.0)
    G = np.minimum(1.0, np.minimum(2.0 * nh * nv / vh, 2.0 * nh * nl / vh))
    spec = schlick_fresnel(SEA_F0, vh) * sea_beckmann(nh, mss) * G / (4.0 * nv)
    sea = body * (1.0 - F) + np.asarray(reflected, dtype=np.float64) * F \
        + E * (spec * glitter)[..., None]
    haze = (1.0 - np.exp(-(eye_height / nv) / haze_distance))[..., None]
    return sea * (1.0 - haze) + np.asarray(horizon, dtype=np.float64) * haze


@dataclass(frozen=True)
class SeaPlane:
    """What a sky's sea needs besides the sky's own radiance (the uniforms of its shader)."""

    sky_ambient: tuple[float, float, float]
    light_dir: tuple[float, float, float]
    light_radiance: tuple[float, float, float]
    body_color: tuple[float, float, float] = (0.01, 0.045, 0.06)
    mss: float = 0.003 + 0.00512 * 5.0
    glitter: float = 1.0
    eye_height: float = 2.0
    haze_distance: float = 12000.0

    def radiance(self, p, reflected, horizon) -> np.ndarray:
        """:func:`sea_plane_radiance` toward ``p`` with this plane's light and sea."""
        return sea_plane_radiance(p, reflected, horizon, self.sky_ambient,
                                  np.asarray(self.light_dir, dtype=np.float64),
                                  self.light_radiance, self.body_color, self.mss, self.glitter,
                                  self.eye_height, self.haze_distance)
