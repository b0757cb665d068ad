"""The sails' and the flag's cloth — numpy twin of ``glsl/boat/cloth.glsl`` (spec/000 §1.5).

The thesis animates its sails and its pennant with one vertex shader that displaces the
vertices by time-varying Perlin noise (a mass–spring cloth was tried and rejected), with the
parameters TimeStep, TimeOffset, WaveHeight, WaveSpeed, WaveSize and GradientWeight (a vector:
one weight per local axis, so one shader serves the sails and the flag), and an Alpha and a
Pattern texture (``app.sim.rigging``). The thesis gives no formula; this is ours.

The cloth patch
---------------
Every cloth mesh is a bilinear patch in its own local frame (``app.sim.rigging.ClothMesh``):
x along the chord or the flag's length (u grows along it), y up the luff or the hoist (v), z the
flat cloth's normal. With the corners P00 (tack / hoist foot), P10 (clew / fly foot),
P01 (head / hoist top) and P11 (the head again for a triangle; the fly top for the flag)::

    P(u, v) = lerp(lerp(P00, P01, v), lerp(P10, P11, v), u)          u, v in [0, 1]

The pinned weight w(u, v) in [0, 1] holds the edges the cloth is tied to (0 there, 1 in free
cloth): per edge e in (u = 0, v = 0, u = 1, v = 1) with band b_e (0: the edge is free) and
distance d_e to it in uv, r = clamp(d_e / b_e, 0, 1) and the factor 1 − (1 − r)² (a hinge:
the cloth may leave a held edge at an angle, and reaches its full freedom with zero slope).
w is the product of the factors.

The displacement
----------------
Scene time t [s] becomes the cloth's time ``T = TimeStep · t + TimeOffset`` (TimeStep the
animation speed, TimeOffset the thesis's de-synchronising shift; so the displacement at
(t, TimeOffset = o) is the one at (t + o / TimeStep, 0)). With n̂ the flat normal (local z)::

    phase  = 2π (WaveSize · u − WaveSpeed · T)               ripples travelling toward u = 1
    ripple = WaveHeight · sin(phase) · n̂
    q      = (WaveSize · u − WaveSpeed · T, WaveSize · v, T)
    noise  = GradientWeight ⊙ (N(q + o_x), N(q + o_y), N(q + o_z)) / PERLIN3_BOUND
    a      = mix(1, Taut, Fill)                               a full sail is taut and flaps less
    belly  = Side · Fill · Camber · c(v) · 4u(1 − u) · w · n̂   c(v) = |P(1, v) − P(0, v)|
    D      = w · a · (ripple + noise) + belly

N is Perlin's improved noise (``app.sim.noise.gradient.perlin3``, GLSL ``PerlinNoise3``,
Perlin's reference permutation), o_x, o_y, o_z fixed offsets that decorrelate the three axes.
WaveSize is the number of ripples (and noise cells) across the mesh, WaveSpeed ripples per unit
of T passing a point. The belly is a parabolic camber across each chord (from the luff u = 0 to
the leech u = 1) of depth Camber × chord at mid-chord, on the side ``Side`` = ±1 (the side the
wind fills, given by the sailing model) and scaled by ``Fill`` in [0, 1] (0: luffing, no belly
and the full flapping; 1: full, the flapping reduced to ``Taut``).

Bound (spec/000 §6 criterion 35): since |sin| ≤ 1, |N| ≤ PERLIN3_BOUND and w, a ∈ [0, 1], the
noise part never moves a vertex farther than WaveHeight + |GradientWeight|; the belly adds at
most Camber × the longest chord (and is 0 on a flag, whose Fill is 0).

Normals
-------
The displaced surface S(u, v) = P(u, v) + D(u, v) is differentiated along the patch's two
parameter directions: ∂S/∂u = ∂P/∂u (exact, the patch is bilinear) + central difference of D
with the step ``FD_STEP`` = 1/1024 in u (and likewise v) — about 3 mm across the mainsail's
foot, under 1 mm on the flag. The normal is normalize(∂S/∂u × ∂S/∂v), turned to the side of
the flat normal; where the cross product vanishes (the collapsed head row of a triangle) it is
the flat normal. The weight at the neighbours is the vertex's own plus the change of the
analytic w, so a mesh whose weights were edited keeps consistent normals.

Failure cases guarded: the head of a triangle sail (all its vertices at one point) stays
together because w = 0 along v = 1 (a sail's band there is non-zero); a vanishing tangent
falls back to the flat normal (no NaN); TimeStep 0 freezes the cloth; a negative WaveSize or
Camber is refused by the parameter ranges. Precision is the caller's: T is float32 on the GPU,
smooth for |T| up to ~10⁴ (past that the ripple's phase loses its fraction).
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from ..colour import srgb_to_linear
from ..params import Param
from .noise.gradient import PERLIN3_BOUND, perlin3

SECTION = "spec/000 §1.5"
#: finite-difference step of the normals, in uv
FD_STEP = 1.0 / 1024.0
#: noise offsets of the three local axes (lattice units; not integers, so the three noises
#: are not zero together)
NOISE_OFFSETS = np.array([(0.37, 0.61, 0.13), (19.71, 43.29, 7.77), (57.13, 11.83, 29.41)])

#: the cloth parameters (short names) and their shader uniforms
UNIFORMS = {
    "time_step": "uTimeStep",
    "time_offset": "uTimeOffset",
    "wave_height": "uWaveHeight",
    "wave_speed": "uWaveSpeed",
    "wave_size": "uWaveSize",
    "gradient_weight": "uGradientWeight",
    "camber": "uCamber",
    "taut": "uTaut",
    "translucency": "uTranslucency",
    "color_a": "uColorA",
    "color_b": "uColorB",
}

#: defaults for the sails: small ripples, a belly, a taut cloth when full
SAIL_DEFAULTS: dict[str, Any] = {
    "time_step": 1.0,
    "time_offset": 0.0,
    "wave_height": 0.03,
    "wave_speed": 0.6,
    "wave_size": 3.0,
    "gradient_weight": (0.02, 0.02, 0.08),
    "holes": 0.0,
    "camber": 0.10,
    "taut": 0.3,
    "translucency": 0.35,
    "color_a": (0.93, 0.92, 0.88),   # sailcloth (sRGB)
    "color_b": (0.10, 0.22, 0.55),   # the stripes
}
#: defaults for the flag: large ripples along its length, no belly
FLAG_DEFAULTS: dict[str, Any] = {
    **SAIL_DEFAULTS,
    "wave_height": 0.06,
    "wave_speed": 1.6,
    "wave_size": 2.0,
    "gradient_weight": (0.05, 0.02, 0.08),
    "camber": 0.0,
    "taut": 1.0,
    "translucency": 0.5,
    "color_a": (0.80, 0.08, 0.10),   # field (sRGB)
    "color_b": (0.95, 0.95, 0.95),   # the cross
}


def cloth_params(prefix: str, defaults: Mapping[str, Any] | None = None) -> list[Param]:
    """The cloth's parameters named ``f"{prefix}{short}"`` (e.g. prefix ``"boat.sail_"``):
    the thesis's six (spec/000 §1.5) and the Alpha holes, the two Pattern colours (sRGB, the
    panel's colour pickers), and beyond the thesis the camber, the tautness of a full sail and
    the translucency. ``defaults`` overrides :data:`SAIL_DEFAULTS` per short name."""
    d = dict(SAIL_DEFAULTS)
    if defaults:
        unknown = set(defaults) - set(d)
        if unknown:
            raise ValueError(f"unknown cloth parameters {sorted(unknown)}: allowed {sorted(d)}")
        d.update(defaults)
    s = SECTION
    beyond = "beyond the thesis (spec/000 §1.5 cloth)"
    return [
        Param(f"{prefix}time_step", d["time_step"], 0.0, 10.0, "TimeStep: animation speed "
              "(cloth time T = TimeStep·t + TimeOffset)", step=0.01, unit="×", section=s),
        Param(f"{prefix}time_offset", d["time_offset"], -1000.0, 1000.0, "TimeOffset: shifts "
              "the cloth's time so that nearby flags do not move in sync", step=0.1, unit="s",
              section=s),
        Param(f"{prefix}wave_height", d["wave_height"], 0.0, 2.0, "WaveHeight: ripple height "
              "along the cloth's normal", step=0.005, unit="m", section=s),
        Param(f"{prefix}wave_speed", d["wave_speed"], -20.0, 20.0, "WaveSpeed: ripples per "
              "unit of cloth time passing a point, travelling toward the free edge", step=0.05,
              unit="1/s", section=s),
        Param(f"{prefix}wave_size", d["wave_size"], 0.0, 64.0, "WaveSize: number of ripples "
              "(and noise cells) across the mesh", step=0.1, unit="per mesh", section=s),
        Param(f"{prefix}gradient_weight", d["gradient_weight"], 0.0, 2.0, "GradientWeight: "
              "amplitude of the Perlin-noise deformation along the cloth's local x (length), "
              "y (height) and z (normal)", kind="vec3", step=0.005, unit="m", section=s),
        Param(f"{prefix}holes", d["holes"], 0.0, 1.0, "Alpha: amount of holes and tears cut "
              "into the cloth's alpha texture (0: intact)", step=0.01, section=s),
        Param(f"{prefix}color_a", d["color_a"], 0.0, 1.0, "Pattern: first colour (the "
              "pattern texture's white)", kind="color", section=s, srgb=True),
        Param(f"{prefix}color_b", d["color_b"], 0.0, 1.0, "Pattern: second colour (the "
              "pattern texture's black)", kind="color", section=s, srgb=True),
        Param(f"{prefix}camber", d["camber"], 0.0, 0.3, "belly depth at mid-chord as a fraction "
              "of the chord, when the sail is full", step=0.005, section=beyond),
        Param(f"{prefix}taut", d["taut"], 0.0, 1.0, "share of the ripple and noise left on a "
              "full sail (a luffing sail flaps fully)", step=0.01, section=beyond),
        Param(f"{prefix}translucency", d["translucency"], 0.0, 1.0, "share of the main light "
              "the cloth transmits to its unlit side", step=0.01, section=beyond),
    ]


def cloth_uniforms(params: Any, prefix: str) -> dict[str, Any]:
    """The shader uniforms of the cloth parameters ``prefix…`` from ``params`` (an
    ``app.params.ParamSet`` or any mapping ``name -> value``): ``uTimeStep``, ``uTimeOffset``,
    ``uWaveHeight``, ``uWaveSpeed``, ``uWaveSize``, ``uGradientWeight``, ``uCamber``,
    ``uTaut``, ``uTranslucency``, and ``uColorA``/``uColorB`` converted to linear values.
    ``holes`` is not a uniform: it selects the alpha texture."""
    out: dict[str, Any] = {}
    for short, uniform in UNIFORMS.items():
        value = params[f"{prefix}{short}"]
        if short.startswith("color_"):
            value = tuple(float(v) for v in srgb_to_linear(np.asarray(value, dtype=np.float64)))
        elif isinstance(value, (tuple, list)):
            value = tuple(float(v) for v in value)
        else:
            value = float(value)
        out[uniform] = value
    return out


def defaults_values(defaults: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The cloth's values by short name (:data:`SAIL_DEFAULTS` updated by ``defaults``), the
    ``params`` the functions below take."""
    out = dict(SAIL_DEFAULTS)
    out.update(defaults or {})
    return out


def patch(corners: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """P(u, v) of the bilinear patch with ``corners`` (4, 3) in the order P00, P10, P01, P11;
    ``uv`` (..., 2). Returns (..., 3)."""
    c = np.asarray(corners, dtype=np.float64)
    u = np.asarray(uv, dtype=np.float64)[..., 0:1]
    v = np.asarray(uv, dtype=np.float64)[..., 1:2]
    left = c[0] + v * (c[2] - c[0])
    right = c[1] + v * (c[3] - c[1])
    return left + u * (right - left)


def patch_derivatives(corners: np.ndarray, uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(∂P/∂u, ∂P/∂v) of the patch at ``uv``, exact."""
    c = np.asarray(corners, dtype=np.float64)
    u = np.asarray(uv, dtype=np.float64)[..., 0:1]
    v = np.asarray(uv, dtype=np.float64)[..., 1:2]
    left = c[0] + v * (c[2] - c[0])
    right = c[1] + v * (c[3] - c[1])
    dv = (c[2] - c[0]) + u * ((c[3] - c[1]) - (c[2] - c[0]))
    return right - left, dv


def pinned_weight(uv: np.ndarray, band: Any) -> np.ndarray:
    """w(u, v): 0 on the held edges, 1 in free cloth. ``band`` (4,): the width in uv of the
    hold at the edges u = 0, v = 0, u = 1, v = 1 (0: that edge is free)."""
    uv = np.asarray(uv, dtype=np.float64)
    b = np.asarray(band, dtype=np.float64)
    dist = np.stack([uv[..., 0], uv[..., 1], 1.0 - uv[..., 0], 1.0 - uv[..., 1]], axis=-1)
    w = np.ones(uv.shape[:-1])
    for e in range(4):
        if b[e] > 0.0:
            r = np.clip(dist[..., e] / b[e], 0.0, 1.0)
            w = w * (1.0 - (1.0 - r) ** 2)
    return w


def cloth_time(t: Any, params: Mapping[str, Any]) -> Any:
    """T = TimeStep · t + TimeOffset."""
    return float(params["time_step"]) * np.asarray(t, dtype=np.float64) + \
        float(params["time_offset"])


def _displacement(uv: np.ndarray, w: np.ndarray, chord: np.ndarray, T: float,
                  params: Mapping[str, Any], side: float, fill: float) -> np.ndarray:
    """D in the local frame (..., 3), the flat normal being local +z."""
    u, v = uv[..., 0], uv[..., 1]
    size, speed = float(params["wave_size"]), float(params["wave_speed"])
    s = size * u - speed * T
    ripple = float(params["wave_height"]) * np.sin(2.0 * math.pi * s)
    gw = np.asarray(params["gradient_weight"], dtype=np.float64)
    q = (s, size * v, np.full_like(u, T))
    noise = np.stack([perlin3(q[0] + o[0], q[1] + o[1], q[2] + o[2]) for o in NOISE_OFFSETS],
                     axis=-1) * (gw / PERLIN3_BOUND)
    fill = float(np.clip(fill, 0.0, 1.0))
    a = 1.0 + fill * (float(params["taut"]) - 1.0)
    d = noise * (w * a)[..., None]
    belly = side * fill * float(params["camber"]) * chord * 4.0 * u * (1.0 - u) * w
    d[..., 2] += w * a * ripple + belly
    return d


def _chord(corners: np.ndarray, v: np.ndarray) -> np.ndarray:
    c = np.asarray(corners, dtype=np.float64)
    vv = np.asarray(v, dtype=np.float64)[..., None]
    left = c[0] + vv * (c[2] - c[0])
    right = c[1] + vv * (c[3] - c[1])
    return np.linalg.norm(right - left, axis=-1)


def displacement(uv: Any, pinned: Any, t: float, params: Mapping[str, Any], corners: Any,
                 side: float = 1.0, fill: float = 0.0) -> np.ndarray:
    """D (V, 3) in the local frame at scene time ``t`` for vertices with ``uv`` (V, 2) and
    weights ``pinned`` (V,); ``params`` by short name (:func:`defaults_values`), ``corners``
    the patch's (``ClothMesh.corners``)."""
    uv = np.asarray(uv, dtype=np.float64)
    w = np.asarray(pinned, dtype=np.float64)
    return _displacement(uv, w, _chord(corners, uv[..., 1]), float(cloth_time(t, params)),
                         params, float(side), float(fill))


def displace(positions_local: Any, uv: Any, pinned: Any, t: float, params: Mapping[str, Any],
             corners: Any, side: float = 1.0, fill: float = 0.0) -> np.ndarray:
    """Displaced positions (V, 3), local frame: ``positions_local + displacement(...)``
    (twin of GLSL ``ClothSurface``'s position)."""
    return np.asarray(positions_local, dtype=np.float64) + displacement(
        uv, pinned, t, params, corners, side, fill)


def displaced_normals(uv: Any, pinned: Any, t: float, params: Mapping[str, Any], corners: Any,
                      pin_band: Any, side: float = 1.0, fill: float = 0.0,
                      flat_normal: Any = (0.0, 0.0, 1.0), step: float = FD_STEP) -> np.ndarray:
    """Unit normals (V, 3) of the displaced surface, local frame (twin of GLSL
    ``ClothSurface``'s normal): central differences of D with ``step`` in uv, the patch's
    exact tangents, turned toward ``flat_normal``."""
    uv = np.asarray(uv, dtype=np.float64)
    w0 = np.asarray(pinned, dtype=np.float64)
    base = pinned_weight(uv, pin_band)
    T = float(cloth_time(t, params))
    side, fill = float(side), float(fill)

    def d_at(offset):
        q = uv + offset
        w = np.clip(w0 + pinned_weight(q, pin_band) - base, 0.0, 1.0)
        return _displacement(q, w, _chord(corners, q[..., 1]), T, params, side, fill)

    h = float(step)
    pu, pv = patch_derivatives(corners, uv)
    su = pu + (d_at(np.array([h, 0.0])) - d_at(np.array([-h, 0.0]))) / (2.0 * h)
    sv = pv + (d_at(np.array([0.0, h])) - d_at(np.array([0.0, -h]))) / (2.0 * h)
    n = np.cross(su, sv)
    flat = np.broadcast_to(np.asarray(flat_normal, dtype=np.float64), n.shape)
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    ok = length > 1e-12
    n = np.where(ok, n / np.where(ok, length, 1.0), flat)
    n = np.where(np.sum(n * flat, axis=-1, keepdims=True) < 0.0, -n, n)
    return n
