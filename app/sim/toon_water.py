"""The toon village's water (spec/003 §2.10, the thesis's Custom/Nature/Water) — the numpy twin
of ``glsl/toon_water/water.glsl`` (one function per GLSL function, snake case, float64 and
vectorised) and what the effect generates by code: the tileable wave normal map
(:func:`wave_normal_map`) and the Fresnel ramp texture (:func:`fresnel_ramp`, the thesis's
Fig. 110, which it painted in GIMP from spec/003 eq. 7.22).

Equations and guards: see the GLSL file's header; the choices where the document and the
public repository differ are documented on the effect (``app/effects/toon_water/effect.py``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .maths import saturate
from .optics import schlick_fresnel
from .staircase import staired_value

Array = NDArray[np.float64]

#: ((1 − 1.31)/(1 + 1.31))², rounded as the thesis writes spec/003 eq. 7.22
WATER_F0 = 0.018
#: the exact value before the thesis's rounding
WATER_F0_EXACT = ((1.0 - 1.31) / (1.0 + 1.31)) ** 2
REPOSITORY_FOG_FACTOR = 31.0
UNITY_TIME_X = 0.05
#: the depth fog's methods (toon_water.fog_method), in uFogMethod's order
FOG_METHODS = ("document", "repository", "thickness")
#: the width of the baked Fresnel ramp (texels)
RAMP_WIDTH = 256
#: the wave normal map's size (texels per side)
NORMAL_MAP_SIZE = 128
#: the water plane's polar grid: rings of doubling radius, segments around
PLANE_RINGS = 14
PLANE_SEGMENTS = 24


def _f(x: ArrayLike) -> Array:
    return np.asarray(x, dtype=np.float64)


def screen_uv(frag_coord: ArrayLike, viewport: ArrayLike, flip_y: bool) -> Array:
    """``ScreenUV``: fragCoord/viewport, y flipped when ``flip_y`` (the thesis's render-texture
    flip; off in GL)."""
    uv = _f(frag_coord) / np.maximum(_f(viewport), 1.0)
    if flip_y:
        uv = uv.copy()
        uv[..., 1] = 1.0 - uv[..., 1]
    return uv


def tide_level(sea_level: float, tide_height: float, t: ArrayLike) -> Array:
    """``TideLevel``: sea level + Tide Height·sin t (the repository's _TideHeight·_SinTime.w)."""
    return sea_level + tide_height * np.sin(_f(t))


def wave_uvs(world_xz: ArrayLike, t: float, tile: float, scale: float,
             speed: float) -> tuple[Array, Array]:
    """``WaveUVs``: uv = (x, −z)/tile; (uv + s)·scale and uv − s, s = speed·t/20."""
    xz = _f(world_xz)
    uv = np.stack([xz[..., 0], -xz[..., 1]], axis=-1) / max(tile, 1e-3)
    s = speed * t * UNITY_TIME_X
    return (uv + s) * scale, uv - s


def wave_normal(tex1: ArrayLike, tex2: ArrayLike, intensity: float) -> Array:
    """``WaveNormal``: spec/003 eq. 3.1 on the two texels' average (x, y scaled by Wave
    Intensity) and spec/003 eq. 3.4's z, carried to world (t = +x, b = −z, n = +y)."""
    xy = (2.0 * (0.5 * (_f(tex1)[..., :2] + _f(tex2)[..., :2])) - 1.0) * intensity
    z = np.maximum(1.0 - 0.5 * np.sum(xy * xy, axis=-1), 0.0)
    n = np.stack([xy[..., 0], z, -xy[..., 1]], axis=-1)
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    return np.where(length > 1e-10, n / np.maximum(length, 1e-300), [0.0, 1.0, 0.0])


def view_depth(d: ArrayLike, near: float, far: float) -> Array:
    """``ViewDepth``: metres along the camera's axis of a GL window depth d,
    nf/(f·(1 − d) + n·d)."""
    dd = np.clip(_f(d), 0.0, 1.0)
    return near * far / np.maximum(far * (1.0 - dd) + near * dd, 1e-12)


def window_depth(z: ArrayLike, near: float, far: float) -> Array:
    """The inverse of :func:`view_depth`: the GL window depth of a point ``z`` metres along
    the camera's axis (what a test writes into a depth texture)."""
    z = _f(z)
    zn = (far + near) / (far - near) - 2.0 * far * near / ((far - near) * z)
    return 0.5 * zn + 0.5


def fog_weight_document(raw_depth: ArrayLike, intensity: float) -> Array:
    """``FogWeightDocument``: the document's lerp(refraction, waterColor, depth) weight, the
    raw depth texture value times Water Fog Intensity."""
    return saturate(_f(raw_depth) * intensity)


def fog_weight_repository(linear01: ArrayLike, intensity: float) -> Array:
    """``FogWeightRepository``: saturate(Linear01Depth·fogInt·31)."""
    return saturate(_f(linear01) * intensity * REPOSITORY_FOG_FACTOR)


def fog_weight_thickness(metres: ArrayLike, intensity: float) -> Array:
    """``FogWeightThickness``: 1 − exp(−I·L) of the water's thickness L along the view ray."""
    return 1.0 - np.exp(-np.clip(intensity * np.maximum(_f(metres), 0.0), 0.0, 80.0))


def water_refraction(refraction: ArrayLike, colour: ArrayLike, alpha: float,
                     w: ArrayLike) -> Array:
    """``WaterRefraction``: mix(mix(colour, refraction, α), colour, w)."""
    a = float(np.clip(alpha, 0.0, 1.0))
    w = np.clip(_f(w), 0.0, 1.0)[..., None]
    c = _f(colour)
    base = c + (_f(refraction) - c) * a
    return base + (c - base) * w


def simple_band(n_dot_v: ArrayLike) -> Array:
    """``SimpleBand``: the Simple type's v·n in 3 bands, StairedValue(1 − saturate(n·v), 1/3)
    (spec/003 eq. 7.18, spec/003 eq. 7.19, spec/003 eq. 7.20)."""
    return staired_value(1.0 - saturate(n_dot_v), 1.0 / 3.0)


def toon_reflection(reflection: ArrayLike, toon_value: float) -> Array:
    """``ToonReflection``: the reflection discretised per channel with Toon Value
    (spec/003 eq. 7.18, spec/003 eq. 7.19, spec/003 eq. 7.20)."""
    return staired_value(np.maximum(_f(reflection), 0.0), toon_value)


def reflection_direction(v: ArrayLike, n: ArrayLike) -> Array:
    """``ReflectionDirection``: reflect(−v, n) with its y made positive, normalised."""
    v, n = _f(v), _f(n)
    r = -v + 2.0 * np.sum(v * n, axis=-1, keepdims=True) * n
    r[..., 1] = np.abs(r[..., 1])
    return r / np.linalg.norm(r, axis=-1, keepdims=True)


def fresnel_water(u: ArrayLike) -> Array:
    """spec/003 eq. 7.21 and spec/003 eq. 7.22: u = cos θ = n·v, F = 0.018 + 0.982·(1 − u)^5
    (``FresnelWaterPow5``)."""
    return schlick_fresnel(WATER_F0, u)


def fresnel_ramp(width: int = RAMP_WIDTH, bits: int | None = None) -> NDArray[np.float32]:
    """The ramp texture of spec/003 eq. 7.22 (the thesis's Fig. 110, "to avoid the 5th
    power"): ``width`` texels, texel i holding F at u = i/(width − 1), as float32 — or rounded
    to ``bits`` bits (8: an image painted from the formula, as the thesis's GIMP ramp; read
    through llvmpipe's 8-bit filter it comes within 0.96/255 of the formula, too near the
    criterion's 1/255, hence the float texture)."""
    if int(width) < 2:
        raise ValueError(f"Fresnel ramp width {width!r}: allowed an integer ≥ 2")
    u = np.arange(int(width)) / (int(width) - 1.0)
    f = fresnel_water(u)
    if bits is not None:
        levels = 2.0 ** int(bits) - 1.0
        f = np.round(f * levels) / levels
    return f.astype(np.float32)


def ramp_coordinate(u: ArrayLike, width: int) -> Array:
    """The texture coordinate ``FresnelWaterRamp`` samples at: (u·(W − 1) + ½)/W."""
    return (saturate(u) * (width - 1.0) + 0.5) / width


def fresnel_water_ramp(ramp: ArrayLike, u: ArrayLike) -> Array:
    """``FresnelWaterRamp``: the ``ramp`` (W,) read linearly at u (clamped to its end texels,
    as GL_CLAMP_TO_EDGE)."""
    values = _f(ramp)
    w = len(values)
    x = ramp_coordinate(u, w) * w - 0.5
    return np.interp(x, np.arange(w), values)


def toon_highlight(n: ArrayLike, v: ArrayLike, to_light: ArrayLike, exponent: float,
                   step_x: float) -> Array:
    """``ToonHighlight``: h = (l + v)/‖l + v‖ (spec/003 eq. 2.1), (n·h)^m (spec/003 eq. 2.2),
    staired with step_x; 0 with the light below the horizon."""
    n, v, lt = _f(n), _f(v), _f(to_light)
    h = lt + v
    length = np.linalg.norm(h, axis=-1, keepdims=True)
    h = np.where(length > 1e-10, h / np.maximum(length, 1e-300), n)
    k = np.maximum(np.sum(n * h, axis=-1), 0.0) ** max(exponent, 1.0)
    return np.where(lt[..., 1] > 0.0, staired_value(k, step_x), 0.0)


def water_light(colour: ArrayLike, to_light: ArrayLike, radiance: ArrayLike,
                ambient: ArrayLike) -> Array:
    """``WaterLight``: colour·(radiance·max(l_y, 0) + ambient), l toward the light."""
    return _f(colour) * (_f(radiance) * max(float(_f(to_light)[1]), 0.0) + _f(ambient))


def depth_fog_weight(method: str, raw_depth: ArrayLike, z_water: ArrayLike,
                     ray_per_depth: ArrayLike, intensity: float, near: float,
                     far: float) -> Array:
    """water.frag's ``DepthFogWeight`` (fog on): the weight of ``method`` for the scene's raw
    depth behind a water fragment at view depth ``z_water``, whose ray is ``ray_per_depth``
    metres long per metre of view depth."""
    if method not in FOG_METHODS:
        raise ValueError(f"toon water fog method {method!r}: allowed {', '.join(FOG_METHODS)}")
    if method == "document":
        return fog_weight_document(raw_depth, intensity)
    z_scene = view_depth(raw_depth, near, far)
    if method == "repository":
        return fog_weight_repository(z_scene / far, intensity)
    return fog_weight_thickness((z_scene - _f(z_water)) * _f(ray_per_depth), intensity)


def wave_normal_map(size: int = NORMAL_MAP_SIZE, seed: int = 3, waves: int = 28,
                    rms_slope: float = 0.35) -> NDArray[np.float32]:
    """The tileable normal map of the waves, generated by code: a height field that is a sum of
    ``waves`` cosines whose wave vectors are whole numbers of cycles per tile (so it wraps
    seamlessly), amplitudes falling as |k|^−1.5, random directions and phases; its normals
    from the exact gradient, scaled so the slopes' RMS is ``rms_slope``, stored 0.5·n + 0.5
    in RGB (x along +u, y along +v, z out of the surface), alpha 1. (size, size, 4) float32,
    row j at v = (j + ½)/size."""
    if int(size) < 4:
        raise ValueError(f"wave normal map size {size!r}: allowed an integer ≥ 4")
    rng = np.random.default_rng(seed)
    coords = (np.arange(size) + 0.5) / size
    u, v = np.meshgrid(coords, coords)  # [j, i]: row j is v
    hx = np.zeros((size, size))
    hy = np.zeros((size, size))
    seen: set[tuple[int, int]] = set()
    while len(seen) < waves:
        radius = rng.uniform(1.0, 7.0)
        angle = rng.uniform(0.0, 2.0 * math.pi)
        k = (int(round(radius * math.cos(angle))), int(round(radius * math.sin(angle))))
        if k == (0, 0) or k in seen or (-k[0], -k[1]) in seen:
            continue
        seen.add(k)
        amp = math.hypot(*k) ** -1.5
        phase = 2.0 * math.pi * (k[0] * u + k[1] * v) + rng.uniform(0.0, 2.0 * math.pi)
        # ∂/∂u and ∂/∂v of amp·cos(phase), per tile
        hx += -amp * 2.0 * math.pi * k[0] * np.sin(phase)
        hy += -amp * 2.0 * math.pi * k[1] * np.sin(phase)
    rms = math.sqrt(float(np.mean(hx * hx + hy * hy)))
    hx *= rms_slope / rms
    hy *= rms_slope / rms
    n = np.stack([-hx, -hy, np.ones_like(hx)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    out = np.ones((size, size, 4), np.float32)
    out[..., :3] = 0.5 * n + 0.5
    return out


def plane_mesh(rings: int = PLANE_RINGS, segments: int = PLANE_SEGMENTS
               ) -> tuple[NDArray[np.float32], NDArray[np.int32]]:
    """The water plane around the camera: a polar grid of ``rings`` rings of doubling radius
    (the outermost at 1, the innermost at 2^(1 − rings)) and ``segments`` segments, plus the
    centre — (vertices (n, 2) in units of the plane's reach, triangle indices (m, 3)). The
    outer polygon circumscribes the unit circle (its vertices at 1/cos(π/segments)), so the
    plane covers every point within its reach. Small triangles near the camera keep the
    rasteriser's depth interpolation exact there (two triangles of several kilometres put it
    1 cm off at 35 m on llvmpipe); the tide moves the plane as a whole and needs none."""
    if int(rings) < 1 or int(segments) < 3:
        raise ValueError(f"water plane mesh {rings!r} rings × {segments!r} segments: allowed "
                         "at least 1 ring and 3 segments")
    rings, segments = int(rings), int(segments)
    radius = 2.0 ** (np.arange(rings) + 1 - rings) / math.cos(math.pi / segments)
    phi = 2.0 * math.pi * np.arange(segments) / segments
    ring_xy = radius[:, None, None] * np.stack([np.cos(phi), np.sin(phi)], -1)[None]
    vertices = np.concatenate([np.zeros((1, 2)), ring_xy.reshape(-1, 2)]).astype(np.float32)
    s = np.arange(segments)
    s1 = (s + 1) % segments
    tris = [np.stack([np.zeros(segments, int), 1 + s, 1 + s1], -1)]
    for k in range(rings - 1):
        a, b = 1 + k * segments, 1 + (k + 1) * segments
        tris.append(np.stack([a + s, b + s, b + s1], -1))
        tris.append(np.stack([a + s, b + s1, a + s1], -1))
    return vertices, np.concatenate(tris).astype(np.int32)
