"""Fog — numpy twin of ``glsl/common/fog.glsl`` (spec/003 §2.11 b, the global fog; beyond the
thesis, Quílez's analytic exponential height fog) and of the ground fog plane's shader
``glsl/fog/plane.glsl`` (spec/003 §2.11 a), the settings a scene's fog publishes in the frame's
``fog`` slot (:class:`FogSettings`; :func:`fog_uniforms` turns them into fog.glsl's uniforms),
and the thesis's ``FogGenerator`` (:class:`FogGenerator`, spec/003 Fig. 124) that derives both
fogs from one intensity.

Factors follow Unity's convention: 1 means no fog, 0 all fog; a surface's colour becomes
``lerp(fog_colour, colour, factor)``. Distances are the thesis's: from Unity's reversed clip z,
i.e. the planar depth past the near plane stretched by f/(f − n) (:func:`fog_distance`).

FogGenerator, as the thesis's public repository writes it (``FogGenerator.cs``; the document
only says "Intensity modifies both the plane's fog and the global fog, Speed only the plane's")
— with the scene's distance scale ``scale`` (metres here per metre of Fracsland's village):

* exp / exp2 density  t = density · I / scale   (``RenderSettings.fogDensity = 0.1·I``: the
  Lighting window's Density 0.1 of Fig. 123 is the value at I = 1);
* linear              s = start · scale, e = (start + (end − start)·(1 − I)) · scale
  (``fogStartDistance = 0``, ``fogEndDistance = 30 − 30·I``);
* the plane's cutoff  c = saturate((1 − I) · sin(t/8))   (``_Cutoff = 1 − I``, then the shader's
  ``saturate(_Cutoff·_SinTime.x)``; ``_SinTime.x = sin(t/8)``), its alpha ``saturate(a − c)``:
  the higher the intensity, the less of the texture's alpha the cutoff removes;
* the plane's scroll  Δuv = Speed · t/20 along the wind (``uv.y += _Speed·_Time.x``,
  ``_Time.x = t/20``);
* I = 0 turns both off (``RenderSettings.fog = false``, the plane's renderer disabled).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..colour import LUMINANCE
from .noise.fractal import perlin_fbm2_periodic

#: fog.glsl's uFogMode
MODES = ("off", "linear", "exp", "exp2")
#: Unity's _Time.x is t/20 (the plane's UV scroll, uv += Speed·_Time.x)
UNITY_TIME_X = 1.0 / 20.0
#: Unity's _SinTime.x is sin(t/8) (the plane's cutoff modulation)
UNITY_SIN_TIME_X = 1.0 / 8.0
#: the largest exponent the height fog evaluates (exp(60) ≈ 1e26: fp32-safe even times a
#: distance of 1e6 m and a density of 100/m; anything denser is opaque anyway)
HEIGHT_EXPONENT_MAX = 60.0
#: below this |b·Δy| the height fog uses the series of (1 − e^(−u))/u (fp32 cancellation)
HEIGHT_SERIES_BELOW = 1e-2
#: the luminance of the default day–night sky's ambient at noon (resources/sky/keyframes.toml:
#: 0.40); ``sky_fog_colour`` scales the fog's colour by the sky's ambient luminance over it
DAY_AMBIENT_LUMINANCE = 0.40
#: the fog texture's densest wisp: the plane never hides the ground completely
TEXTURE_MAX_ALPHA = 0.6


def _finite(name: str, value: float, lo: float, hi: float = math.inf,
            what: str = "") -> float:
    v = float(value)
    if not (math.isfinite(v) and lo <= v <= hi):
        rng = f"[{lo:g}, {hi:g}]" if math.isfinite(hi) else f"≥ {lo:g}"
        raise ValueError(f"fog {name} {value!r}: allowed a finite number {rng}{what}")
    return v


@dataclass(frozen=True)
class FogSettings:
    """What the ``fog`` slot holds: Unity's Lighting › Fog panel (spec/003 Fig. 123) and the
    height-fog switch, in the scene's metres."""

    mode: str = "exp2"
    density: float = 0.1  # t of spec/003 eq. 7.28 and 7.29 [1/m]
    start: float = 0.0  # s of spec/003 eq. 7.27 [m]
    end: float = 10.0  # e of spec/003 eq. 7.27 [m]
    colour: tuple[float, float, float] = (0.5, 0.55, 0.6)  # linear radiance
    per_pixel: bool = False
    height: bool = False  # the height fog replaces the distance fog (whatever the mode)
    height_density: float = 0.05  # a: density at height_base [1/m]
    height_falloff: float = 0.2  # b [1/m]
    height_base: float = 0.0  # y0 [m]

    def __post_init__(self):
        if self.mode not in MODES:
            raise ValueError(f"fog mode {self.mode!r}: allowed {', '.join(MODES)}")
        _finite("density", self.density, 0.0, what=" [1/m]")
        _finite("start", self.start, -math.inf, what=" [m]")
        _finite("end", self.end, self.start, what=f" [m] (at least the start, {self.start:g})")
        _finite("height_density", self.height_density, 0.0, what=" [1/m]")
        _finite("height_falloff", self.height_falloff, 0.0, what=" [1/m]")
        _finite("height_base", self.height_base, -math.inf, what=" [m]")
        c = tuple(self.colour)
        if len(c) != 3 or not all(math.isfinite(float(x)) and float(x) >= 0.0 for x in c):
            raise ValueError(f"fog colour {self.colour!r}: allowed three finite numbers ≥ 0 "
                             "(linear RGB)")


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


def fog_view_depth(d: ArrayLike, near: float, far: float) -> np.ndarray:
    """The view depth w whose thesis distance is ``d`` (the inverse of spec/003 eq. 7.24 on
    d ≥ 0): w = n + d·(f − n)/f."""
    n, f = _near_far(near, far)
    return n + np.asarray(d, np.float64) * (f - n) / f


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
    """(1 − e^(−x))/x, with the series 1 − x/2 + x²/6 where |x| < HEIGHT_SERIES_BELOW (fp32
    cancels there; in float64 ``expm1`` is exact elsewhere)."""
    x = np.asarray(x, np.float64)
    small = np.abs(x) < HEIGHT_SERIES_BELOW
    safe = np.where(small, 1.0, x)
    return np.where(small, 1.0 - 0.5 * x + x * x / 6.0, -np.expm1(-safe) / safe)


def fog_height_optical_depth(p: ArrayLike, camera: ArrayLike, a: float, b: float,
                             y0: float) -> np.ndarray:
    """Quílez 2010: the optical depth τ = ∫ a·exp(−b·(y − y0)) dl from ``camera`` to ``p``.

    Along the segment, y runs linearly from the camera's height o_y to p_y over its length t,
    so with e_i = −b·(y_i − y0) at the two ends
        τ = a·t·(e^(e0) − e^(e1))/(e0 − e1) = a·t·e^m·(1 − e^(−u))/u,
    m = max(e0, e1), u = |e0 − e1| = b·|p_y − o_y| — the form Quílez writes as
    a·e^(−b·o_y)·(1 − e^(−b·d_y·t))/(b·d_y) rewritten around the denser end, so that neither
    exponential can overflow toward the thin end (a camera high above the fog looking down a
    long ray) nor divide 0/0 on a grazing ray (u → 0: the series, τ → a·t·e^m) nor at t = 0
    (τ = 0). a·e^m is taken as exp(ln a + m) clamped at ``HEIGHT_EXPONENT_MAX``: a camera far
    below y0 sees an opaque fog, not an overflow. b = 0 is a uniform fog (τ = a·t)."""
    p = np.asarray(p, np.float64)
    c = np.asarray(camera, np.float64)
    a, b = max(float(a), 0.0), max(float(b), 0.0)
    t = np.linalg.norm(p - c, axis=-1)
    e0 = -b * (c[..., 1] - y0)
    e1 = -b * (p[..., 1] - y0)
    m = np.maximum(e0, e1)
    u = np.abs(e0 - e1)
    if a <= 0.0:
        return np.zeros(np.shape(t))
    dens = np.exp(np.minimum(math.log(a) + m, HEIGHT_EXPONENT_MAX))
    return dens * t * fog_one_minus_exp_over_x(u)


def fog_height_transmittance(p: ArrayLike, camera: ArrayLike, a: float, b: float,
                             y0: float) -> np.ndarray:
    """Quílez 2010: exp(−τ) of the density a·exp(−b·(y − y0)) from ``camera`` to ``p``
    (:func:`fog_height_optical_depth`)."""
    return np.clip(np.exp(-fog_height_optical_depth(p, camera, a, b, y0)), 0.0, 1.0)


#: samples (rays × steps) of one chunk of :func:`fog_height_reference`
_REFERENCE_SAMPLES = 1 << 17


def fog_height_reference(p: ArrayLike, camera: ArrayLike, a: float, b: float, y0: float,
                         steps: int = 4096) -> np.ndarray:
    """The height fog's transmittance by midpoint integration of the density along the ray (the
    reference the analytic form is tested and charted against)."""
    p = np.asarray(p, np.float64)
    c = np.asarray(camera, np.float64)
    s = (np.arange(steps) + 0.5) / steps
    p, c = np.broadcast_arrays(p, c)
    shape = p.shape[:-1]
    d = (p - c).reshape(-1, 3)
    cy = c[..., 1].reshape(-1)
    mean = np.empty(d.shape[0])
    # the density depends on the height alone: the samples' y, c_y + (p_y − c_y)·s, then
    # a·exp(−b·(y − y0)) and its mean per ray — in place and a few rays at a time (the same
    # operations per sample as the whole (rays, steps) array at once, in a few MB)
    rows = max(1, _REFERENCE_SAMPLES // steps)
    for i in range(0, d.shape[0], rows):
        j = slice(i, i + rows)
        rho = d[j, 1, None] * s
        rho += cy[j, None]
        rho -= y0
        rho *= -b
        np.exp(rho, out=rho)
        rho *= a
        mean[j] = rho.mean(axis=-1)
    t = np.linalg.norm(p - c, axis=-1)
    return np.exp(-mean.reshape(shape) * t)


def fog_apply(colour: ArrayLike, factor: ArrayLike, fog_colour: ArrayLike) -> np.ndarray:
    """lerp(fog colour, colour, f): the lerp with its operands swapped (spec/003 §2.11)."""
    f = np.clip(np.asarray(factor, np.float64), 0.0, 1.0)[..., None]
    return np.asarray(fog_colour, np.float64) * (1.0 - f) + np.asarray(colour, np.float64) * f


def luminance(rgb: ArrayLike) -> float:
    return float(np.dot(np.asarray(rgb, np.float64), LUMINANCE))


def sky_fog_colour(colour: ArrayLike, ambient: ArrayLike | None, tint: float = 0.3,
                   day_luminance: float = DAY_AMBIENT_LUMINANCE) -> tuple[float, float, float]:
    """The fog's colour under the sky (``fog.color_from_sky``): the day colour ``colour``
    scaled by the sky ambient's luminance over the day's (at most 1: the fog never outshines
    its day colour, and at night it is as dark as the sky), and tinted by ``tint`` toward the
    ambient's chromaticity at the same luminance (dusk turns it purple-orange). None: the
    colour unchanged (no sky)."""
    c = np.asarray(colour, np.float64)
    if ambient is None:
        return tuple(float(x) for x in c)
    amb = np.maximum(np.asarray(ambient, np.float64), 0.0)
    y_amb, y_col = luminance(amb), luminance(c)
    bright = min(1.0, y_amb / max(day_luminance, 1e-9))
    chroma = amb / y_amb * y_col if y_amb > 1e-9 else c
    t = min(max(float(tint), 0.0), 1.0)
    out = bright * ((1.0 - t) * c + t * chroma)
    return tuple(float(x) for x in out)


@dataclass(frozen=True)
class FogGenerator:
    """``FogGenerator.cs`` (spec/003 Fig. 124: Fog Intensity 0.324, Speed 0.264, Fog Mode
    Exponential Squared): one intensity drives the global fog and the ground plane (the
    mapping is in this module's docstring). ``density``, ``start``, ``end`` are the Lighting
    window's values at intensity 1 / 0 (Fig. 123's Density 0.1; the repository's end 30) in
    Fracsland's metres; ``scale`` stretches them to this scene's."""

    intensity: float = 0.324
    speed: float = 0.264
    mode: str = "exp2"
    scale: float = 2.0
    density: float = 0.1
    start: float = 0.0
    end: float = 30.0

    def __post_init__(self):
        if self.mode not in MODES:
            raise ValueError(f"fog mode {self.mode!r}: allowed {', '.join(MODES)}")
        _finite("intensity", self.intensity, 0.0, 1.0)
        _finite("speed", self.speed, 0.0)
        _finite("scale", self.scale, 1e-3, what=" (metres here per metre of the thesis)")
        _finite("density", self.density, 0.0, what=" [1/m]")
        _finite("start", self.start, 0.0, what=" [m]")
        _finite("end", self.end, self.start, what=f" [m] (at least the start, {self.start:g})")

    @property
    def on(self) -> bool:
        """The repository's ``fogOn = intensity != 0`` (both fogs)."""
        return self.intensity > 0.0

    def global_density(self) -> float:
        """t of spec/003 eq. 7.28 and spec/003 eq. 7.29 in this scene's metres."""
        return self.density * self.intensity / self.scale

    def linear_range(self) -> tuple[float, float]:
        """(s, e) of spec/003 eq. 7.27 in this scene's metres."""
        s = self.start
        e = s + (self.end - s) * (1.0 - self.intensity)
        return s * self.scale, e * self.scale

    def plane_cutoff(self, time: ArrayLike) -> np.ndarray:
        """The plane's cutoff at ``time`` [s]: saturate((1 − I)·_SinTime.x)."""
        return plane_cutoff(1.0 - self.intensity, time)

    def settings(self, colour=(0.5, 0.55, 0.6), per_pixel: bool = False, height: bool = False,
                 height_density: float = 0.15, height_falloff: float = 0.35,
                 height_base: float = 0.0) -> FogSettings | None:
        """The ``fog`` slot's value (None when the intensity is 0 or the mode off): the height
        fog's density at its base is ``height_density``·I, as the distance fog's is
        ``density``·I/scale."""
        if not self.on or self.mode == "off":
            return None
        s, e = self.linear_range()
        return FogSettings(mode=self.mode, density=self.global_density(), start=s, end=e,
                           colour=tuple(float(c) for c in colour), per_pixel=per_pixel,
                           height=height, height_density=height_density * self.intensity,
                           height_falloff=height_falloff, height_base=height_base)


# ---- the ground fog plane (Custom/Fog, spec/003 §2.11 a) --------------------------------------

def plane_cutoff(cutoff: float, time: ArrayLike) -> np.ndarray:
    """The plane shader's cutoff: saturate(_Cutoff·_SinTime.x), _SinTime.x = sin(t/8) — half of
    each 16π-second period it is 0 (all the texture's alpha shows), the other half it rises to
    ``cutoff`` and back (the fog thins and returns)."""
    t = np.asarray(time, np.float64)
    return np.clip(float(cutoff) * np.sin(t * UNITY_SIN_TIME_X), 0.0, 1.0)


def plane_alpha(texture_alpha: ArrayLike, cutoff: ArrayLike, mask: ArrayLike = 1.0) -> np.ndarray:
    """The plane's opacity: saturate(a − cutoff) (the repository's ``diffuse.a = tex.a −
    cutoff``, clamped as an 8-bit target clamps it), times the ground mask (1 over land that
    lies just below the plane, 0 where the ground drops away: beaches, the sea)."""
    a = np.asarray(texture_alpha, np.float64) - np.asarray(cutoff, np.float64)
    return np.clip(a, 0.0, 1.0) * np.clip(np.asarray(mask, np.float64), 0.0, 1.0)


def plane_scroll(speed: float, time: float, direction=(0.0, 1.0)) -> np.ndarray:
    """UV offset Speed·_Time.x along ``direction`` (the thesis: +v), for a constant speed and
    direction; the effect integrates it frame by frame (a changed speed or wind does not jump)."""
    d = np.asarray(direction, np.float64)
    n = np.linalg.norm(d)
    d = d / n if n > 1e-12 else np.array([0.0, 1.0])
    return d * float(speed) * float(time) * UNITY_TIME_X


def fog_texture(size: int = 256, seed: int = 7, cells: int = 4) -> np.ndarray:
    """The ground fog's RGBA texture (spec/003 Fig. 118: white-grey wisps in RGB, their
    coverage in alpha), generated by code and tileable: a domain-warped periodic Perlin fBm
    (the warp is periodic with the same period, so the warped field tiles too), its wisps
    stretched along u, at most TEXTURE_MAX_ALPHA opaque; (size, size, 4) float32 in [0, 1], row 0
    at v = 0."""
    if not (isinstance(size, (int, np.integer)) and 4 <= size <= 4096):
        raise ValueError(f"fog texture size {size!r}: allowed an integer in [4, 4096]")
    u = (np.arange(size) + 0.5) / size
    x, y = np.meshgrid(u * cells, u * cells, indexing="xy")
    wx = perlin_fbm2_periodic(x, y, cells, octaves=3, seed=seed)
    wy = perlin_fbm2_periodic(x + 0.37 * cells, y + 0.61 * cells, cells, octaves=3, seed=seed + 1)
    n = perlin_fbm2_periodic(x + 0.9 * wx, 2.0 * (y + 0.35 * wy), (cells, 2 * cells),
                             octaves=4, seed=seed + 2)
    shade = perlin_fbm2_periodic(x * 2.0, y * 2.0, 2 * cells, octaves=3, seed=seed + 3)
    n = (n - n.min()) / max(float(n.max() - n.min()), 1e-9)
    t = np.clip((n - 0.3) / 0.6, 0.0, 1.0)
    alpha = TEXTURE_MAX_ALPHA * t * t * (3.0 - 2.0 * t)
    grey = np.clip(0.88 + 0.12 * shade, 0.0, 1.0)
    rgb = np.stack([grey * 0.97, grey * 0.985, grey], axis=-1)
    return np.concatenate([rgb, alpha[..., None]], axis=-1).astype(np.float32)
