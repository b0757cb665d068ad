"""Lighting and toon models of the shading lab (spec/003 §2.1, spec/003 §2.12): the numpy twin
of ``glsl/common/lighting.glsl``, one function per GLSL function (snake case), float64 and
vectorised over the leading axes of the (..., 3) direction arrays. See the GLSL file's header for
the equations, the toon modes, the forward light sum and the guards (the same here).

The ``// @param`` uniforms of the GLSL are the fields of :class:`Shading` (defaults equal to the
annotations'); the material and light uniforms are the arguments and :class:`Lights`.
:meth:`Shading.uniforms` and :meth:`Lights.uniforms` give the GLSL names, so a test or an
effect sets a program from the same values the twin evaluates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .staircase import soft_staired_value

Array = NDArray[np.float64]

#: lighting models (uLightingModel) and toon modes (uToon), by their uniform values
LIGHTING_MODELS = ("lambert", "phong", "blinn_phong")
TOON_MODES = ("none", "flat", "stepped", "ramp")
#: the most point lights the shader sums
MAX_POINT_LIGHTS = 4
SPEC_MIN_EXPONENT = 1e-3
#: the Stepped levels (both tables): 0.2 is the thesis's built-in ambient floor
STEPPED_LEVELS = (0.2, 0.5, 0.7, 1.0)
#: the document's thresholds on the remapped n·l, and the repository's on saturate(n·l)·atten
STEPPED_DOCUMENT_THRESHOLDS = (0.45, 0.55, 0.65)
STEPPED_REPOSITORY_THRESHOLDS = (0.0, 0.15, 0.30)
#: f(t) of the flicker: (amplitude, frequency in Hz, phase) of its three sines, after ½
FLICKER_SINES = ((0.25, 1.3, 0.0), (0.15, 3.7, 1.1), (0.1, 7.9, 2.3))


@dataclass
class Shading:
    """The model and toon choices: the ``// @param`` uniforms of lighting.glsl and surface.vert."""

    lighting_model: int = 2
    phong_exponent: float = 60.0
    blinn_exponent: float = 120.0
    rim: bool = False
    rim_power: float = 2.0
    rim_color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    toon: int = 0
    stepped_repository: bool = False
    specularity: float = 0.168
    smoothness: float = 0.841
    emission_color: tuple[float, float, float] = (1.0, 0.75, 0.35)
    flicker: float = 0.0
    gouraud: bool = False

    def uniforms(self) -> dict[str, Any]:
        return {"uLightingModel": int(self.lighting_model),
                "uPhongExponent": float(self.phong_exponent),
                "uBlinnExponent": float(self.blinn_exponent), "uRim": bool(self.rim),
                "uRimPower": float(self.rim_power), "uRimColor": tuple(map(float, self.rim_color)),
                "uToon": int(self.toon), "uSteppedRepository": bool(self.stepped_repository),
                "uSpecularity": float(self.specularity), "uSmoothness": float(self.smoothness),
                "uEmissionColor": tuple(map(float, self.emission_color)),
                "uFlicker": float(self.flicker), "uGouraud": bool(self.gouraud)}


@dataclass
class Lights:
    """The lights of one frame: the sun (ForwardBase), up to four point lights and one spot
    (ForwardAdd), the ambient. Point lists may be shorter than four."""

    sun_dir: tuple[float, float, float] = (0.0, 1.0, 0.0)
    sun_radiance: tuple[float, float, float] = (1.0, 1.0, 1.0)
    ambient: tuple[float, float, float] = (0.0, 0.0, 0.0)
    point_pos: list[tuple[float, float, float]] = field(default_factory=list)
    point_radiance: list[tuple[float, float, float]] = field(default_factory=list)
    point_range: list[float] = field(default_factory=list)
    spot_on: bool = False
    spot_pos: tuple[float, float, float] = (0.0, 2.0, 0.0)
    spot_dir: tuple[float, float, float] = (0.0, -1.0, 0.0)
    spot_radiance: tuple[float, float, float] = (1.0, 1.0, 1.0)
    spot_cos: tuple[float, float] = (0.95, 0.9)
    spot_range: float = 0.0

    def uniforms(self) -> dict[str, Any]:
        """Scalars and vectors; the arrays are :meth:`arrays` (``Program.set_array``)."""
        return {"uSunDir": tuple(map(float, self.sun_dir)),
                "uSunRadiance": tuple(map(float, self.sun_radiance)),
                "uAmbient": tuple(map(float, self.ambient)),
                "uPointCount": min(len(self.point_pos), MAX_POINT_LIGHTS),
                "uSpotOn": bool(self.spot_on), "uSpotPos": tuple(map(float, self.spot_pos)),
                "uSpotDir": tuple(map(float, self.spot_dir)),
                "uSpotRadiance": tuple(map(float, self.spot_radiance)),
                "uSpotCos": tuple(map(float, self.spot_cos)), "uSpotRange": float(self.spot_range)}

    def arrays(self) -> dict[str, list[Any]]:
        return {"uPointPos": [tuple(map(float, p)) for p in self.point_pos],
                "uPointRadiance": [tuple(map(float, p)) for p in self.point_radiance],
                "uPointRange": [float(r) for r in self.point_range]}


def _v(x: ArrayLike) -> Array:
    return np.asarray(x, dtype=np.float64)


def _dot(a: ArrayLike, b: ArrayLike) -> Array:
    return np.sum(_v(a) * _v(b), axis=-1)


def safe_normalize(x: ArrayLike, fallback: ArrayLike) -> Array:
    """x/‖x‖, or ``fallback`` where ‖x‖² ≤ 1e-20."""
    xa = _v(x)
    len2 = _dot(xa, xa)[..., None]
    fb = np.broadcast_to(_v(fallback), np.broadcast_shapes(xa.shape, np.shape(fallback)))
    return np.where(len2 > 1e-20, xa / np.sqrt(np.maximum(len2, 1e-300)), fb)


def lambert_term(n: ArrayLike, l: ArrayLike) -> Array:  # noqa: E741 - the thesis's name
    """Lambert's k_diff = max(0, n·l) (spec/003 §2.1)."""
    return np.maximum(_dot(n, l), 0.0)


def half_vector(l: ArrayLike, v: ArrayLike) -> Array:  # noqa: E741
    """spec/003 eq. 2.1: h = (l + v)/‖l + v‖ (zero when l = −v)."""
    return safe_normalize(_v(l) + _v(v), np.zeros(3))


def blinn_phong_term(n: ArrayLike, h: ArrayLike, m: float) -> Array:
    """spec/003 eq. 2.2: k_spec = max(0, n·h)^m."""
    return np.power(np.maximum(_dot(n, h), 0.0), max(float(m), SPEC_MIN_EXPONENT))


def reflect(i: ArrayLike, n: ArrayLike) -> Array:
    """GLSL's reflect: i − 2(n·i)n."""
    return _v(i) - 2.0 * _dot(n, i)[..., None] * _v(n)


def phong_term(n: ArrayLike, v: ArrayLike, l: ArrayLike, e: float) -> Array:  # noqa: E741
    """Phong's k_spec = max(0, r·v)^n, r = reflect(−l, n) (spec/003 §2.1)."""
    r = reflect(-_v(l), n)
    return np.power(np.maximum(_dot(r, v), 0.0), max(float(e), SPEC_MIN_EXPONENT))


def rim_term(n: ArrayLike, v: ArrayLike, m: float) -> Array:
    """The rim k_rim = (1 − max(0, n·v))^m (spec/003 §2.1)."""
    return np.power(1.0 - np.maximum(_dot(n, v), 0.0), max(float(m), SPEC_MIN_EXPONENT))


def remapped_ndotl(ndotl: ArrayLike) -> Array:
    """spec/003 eq. 8.1: x = ½(n·l) + ½."""
    return 0.5 * _v(ndotl) + 0.5


def _table(x: Array, thresholds: tuple[float, float, float]) -> Array:
    a, b, c = thresholds
    l0, l1, l2, l3 = STEPPED_LEVELS
    return np.where(x <= a, l0, np.where(x <= b, l1, np.where(x <= c, l2, l3)))


def stepped_document(x: ArrayLike) -> Array:
    """The document's Stepped table on the remapped n·l (spec/003 §2.12)."""
    return _table(_v(x), STEPPED_DOCUMENT_THRESHOLDS)


def stepped_repository(y: ArrayLike) -> Array:
    """The public repository's Stepped table on saturate(n·l)·atten (spec/003 Appendix A)."""
    return _table(_v(y), STEPPED_REPOSITORY_THRESHOLDS)


def flat_edge(y: ArrayLike, smoothness: float) -> Array:
    """Flat's edge smoothstep(½ − w, ½ + w, y), w = 0.25·(1 − smoothness)."""
    w = 0.25 * (1.0 - min(max(float(smoothness), 0.0), 1.0))
    t = np.clip((_v(y) - (0.5 - w)) / max(2.0 * w, 1e-6), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def flat_diffuse(ndotl: ArrayLike, smoothness: float) -> Array:
    """Flat's diffuse 0.25 + 0.75·E(½(n·l) + ½): one cut at the terminator (spec/003 §2.12)."""
    return 0.25 + 0.75 * flat_edge(remapped_ndotl(ndotl), smoothness)


def stepped_specular(k: ArrayLike, smoothness: float) -> Array:
    """Stepped's specular: the soft staircase of saturate(4k − 1.5), step 0.25."""
    s = min(max(float(smoothness), 0.0), 1.0)
    return soft_staired_value(np.clip(4.0 * _v(k) - 1.5, 0.0, 1.0), 0.25, 0.1 * (1.0 - s))


def ramp_sample(ramp: ArrayLike, x: ArrayLike, nearest: bool = True) -> Array:
    """A W × 1 texture of texels ``ramp`` (W, 3) read at u = x (v = ½) with clamp-to-edge, as
    GL filters it: NEAREST texel floor(u·W), or LINEAR between the texel centres."""
    r = _v(ramp)
    w = r.shape[0]
    u = np.clip(_v(x), 0.0, 1.0) * w
    if nearest:
        return r[np.clip(np.floor(u).astype(int), 0, w - 1)]
    s = u - 0.5
    i0 = np.floor(s)
    f = (s - i0)[..., None]
    a = r[np.clip(i0.astype(int), 0, w - 1)]
    b = r[np.clip(i0.astype(int) + 1, 0, w - 1)]
    return a * (1.0 - f) + b * f


def ramp_color(ramp: ArrayLike, ndotl: ArrayLike, nearest: bool = True) -> Array:
    """The ramp of Toon = Ramp at ½(n·l) + ½ (spec/003 eq. 8.1)."""
    return ramp_sample(ramp, np.clip(remapped_ndotl(ndotl), 0.0, 1.0), nearest)


def specular_term(n: ArrayLike, v: ArrayLike, l: ArrayLike, s: Shading) -> Array:  # noqa: E741
    """The lighting model's specular, only where n·l > 0 (0 for Lambert)."""
    lit = _dot(n, l) > 0.0
    if s.lighting_model == 0:
        k = np.zeros(lit.shape)
    elif s.lighting_model == 1:
        k = phong_term(n, v, l, s.phong_exponent)
    else:
        k = blinn_phong_term(n, half_vector(l, v), s.blinn_exponent)
    return np.where(lit, k, 0.0)


def shade_light(n: ArrayLike, v: ArrayLike, l: ArrayLike, radiance: ArrayLike,  # noqa: E741
                atten: ArrayLike, albedo: ArrayLike, spec_mask: ArrayLike, s: Shading,
                ramp: ArrayLike | None = None, nearest: bool = True) -> Array:
    """One light: radiance·atten·(albedo·D + Specularity·specMask·S) for the toon mode."""
    ndotl = _dot(n, l)
    k = specular_term(n, v, l, s)
    alb = _v(albedo)
    if s.toon == 1:
        diffuse = alb * flat_diffuse(ndotl, s.smoothness)[..., None]
        spec = flat_edge(k, s.smoothness)
    elif s.toon == 2:
        if s.stepped_repository:
            level = stepped_repository(np.clip(ndotl, 0.0, 1.0) * _v(atten))
        else:
            level = stepped_document(remapped_ndotl(ndotl))
        diffuse = alb * level[..., None]
        spec = stepped_specular(k, s.smoothness)
    elif s.toon == 3:
        if ramp is None:
            raise ValueError("Toon = Ramp needs the ramp's texels")
        diffuse = alb * ramp_color(ramp, ndotl, nearest)
        spec = k
    else:
        diffuse = alb * lambert_term(n, l)[..., None]
        spec = k
    spec_w = (s.specularity * _v(spec_mask) * spec)[..., None]
    return _v(radiance) * _v(atten)[..., None] * (diffuse + spec_w)


def flicker_wave(t: ArrayLike) -> Array:
    """f(t) = ½ + Σ aᵢ·sin(2π fᵢ t + φᵢ) ∈ [0, 1] (FLICKER_SINES)."""
    ta = _v(t)
    out = np.full(ta.shape, 0.5)
    for a, f, phase in FLICKER_SINES:
        out = out + a * np.sin(2.0 * math.pi * f * ta + phase)
    return out


def flicker_factor(t: ArrayLike, amount: float) -> Array:
    """The emission factor 1 − Flickering·f(t)."""
    return 1.0 - min(max(float(amount), 0.0), 1.0) * np.clip(flicker_wave(t), 0.0, 1.0)


def point_attenuation(d: ArrayLike, range_: float) -> Array:
    """(saturate(1 − (d/R)²))², 1 for R ≤ 0."""
    da = _v(d)
    if range_ <= 0.0:
        return np.ones(da.shape)
    x = np.clip(1.0 - (da / range_) ** 2, 0.0, 1.0)
    return x * x


def spot_cone(cos_angle: ArrayLike, cos_inner_outer: tuple[float, float]) -> Array:
    """The spot's cone: 0 outside the outer cosine, 1 inside the inner one (a smoothstep)."""
    inner, outer = cos_inner_outer
    t = np.clip((_v(cos_angle) - outer) / max(inner - outer, 1e-6), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def shade_forward_base_shadowed(n: ArrayLike, v: ArrayLike, albedo: ArrayLike,
                                spec_mask: ArrayLike, emission_mask: ArrayLike, s: Shading,
                                lights: Lights, sun_visibility: ArrayLike = 1.0,
                                time: float = 0.0, ramp: ArrayLike | None = None,
                                nearest: bool = True) -> Array:
    """ForwardBase: ambient·albedo + the sun (its shadow visibility as its attenuation) + the
    rim + the emission, once per surface."""
    na = _v(n)
    c = _v(lights.ambient) * _v(albedo) * np.ones(na.shape)
    sun = safe_normalize(lights.sun_dir, (0.0, 1.0, 0.0))
    vis = np.clip(np.broadcast_to(_v(sun_visibility), na.shape[:-1]), 0.0, 1.0)
    c = c + shade_light(na, v, np.broadcast_to(sun, na.shape), lights.sun_radiance,
                        vis, albedo, spec_mask, s, ramp, nearest)
    if s.rim:
        c = c + _v(s.rim_color) * rim_term(na, v, s.rim_power)[..., None]
    return c + _v(s.emission_color) * (_v(emission_mask)
                                       * flicker_factor(time, s.flicker))[..., None]


def shade_forward_base(n: ArrayLike, v: ArrayLike, albedo: ArrayLike, spec_mask: ArrayLike,
                       emission_mask: ArrayLike, s: Shading, lights: Lights, time: float = 0.0,
                       ramp: ArrayLike | None = None, nearest: bool = True) -> Array:
    """ForwardBase with the sun unshadowed."""
    return shade_forward_base_shadowed(n, v, albedo, spec_mask, emission_mask, s, lights, 1.0,
                                       time, ramp, nearest)


def shade_forward_add(p: ArrayLike, n: ArrayLike, v: ArrayLike, albedo: ArrayLike,
                      spec_mask: ArrayLike, s: Shading, lights: Lights,
                      ramp: ArrayLike | None = None, nearest: bool = True) -> Array:
    """ForwardAdd: each point light (at most four), then the spot, added."""
    na = _v(n)
    pa = _v(p)
    c = np.zeros(na.shape)
    count = min(len(lights.point_pos), MAX_POINT_LIGHTS)
    for i in range(count):
        d = _v(lights.point_pos[i]) - pa
        l = safe_normalize(d, na)  # noqa: E741
        att = point_attenuation(np.linalg.norm(d, axis=-1), float(lights.point_range[i]))
        c = c + shade_light(na, v, l, lights.point_radiance[i], att, albedo, spec_mask, s, ramp,
                            nearest)
    if lights.spot_on:
        d = _v(lights.spot_pos) - pa
        l = safe_normalize(d, na)  # noqa: E741
        axis = safe_normalize(lights.spot_dir, (0.0, -1.0, 0.0))
        att = spot_cone(_dot(-l, axis), lights.spot_cos) * point_attenuation(
            np.linalg.norm(d, axis=-1), float(lights.spot_range))
        c = c + shade_light(na, v, l, lights.spot_radiance, att, albedo, spec_mask, s, ramp,
                            nearest)
    return c


def shade_surface(p: ArrayLike, n: ArrayLike, v: ArrayLike, albedo: ArrayLike,
                  spec_mask: ArrayLike, emission_mask: ArrayLike, s: Shading, lights: Lights,
                  time: float = 0.0, ramp: ArrayLike | None = None,
                  nearest: bool = True) -> Array:
    """The whole surface: ForwardBase + ForwardAdd."""
    return (shade_forward_base(n, v, albedo, spec_mask, emission_mask, s, lights, time, ramp,
                               nearest)
            + shade_forward_add(p, n, v, albedo, spec_mask, s, lights, ramp, nearest))


def shade_surface_shadowed(p: ArrayLike, n: ArrayLike, v: ArrayLike, albedo: ArrayLike,
                           spec_mask: ArrayLike, emission_mask: ArrayLike, s: Shading,
                           lights: Lights, sun_visibility: ArrayLike = 1.0, time: float = 0.0,
                           ramp: ArrayLike | None = None, nearest: bool = True) -> Array:
    """The whole surface with the sun's shadow visibility (the other lights cast none)."""
    return (shade_forward_base_shadowed(n, v, albedo, spec_mask, emission_mask, s, lights,
                                        sun_visibility, time, ramp, nearest)
            + shade_forward_add(p, n, v, albedo, spec_mask, s, lights, ramp, nearest))
