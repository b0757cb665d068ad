"""Single scattering in a spherical exponential atmosphere — the CPU twin of the `planet` scene.

Thesis: G. Iniesta Ovejero and J. Pérez Martínez, "Implementación sobre hardware gráfico de la
dispersión de la luz en la atmósfera" (UCM, 2015), digested as spec/002.
This module is numpy only (float64, vectorised over rays, no GL). It is

* the **model** every GPU method shares: constants (§1.3, §7), phase functions (§1.2),
  density and optical depth (§1.3), exposure with the "pupil" (§1.6);
* the **numpy twins** of the GPU code: the atmosphere segment (§2.4 item 2), the optical-depth
  lookup table the thesis calls the "Chapman function" (§1.8) with its exact texture mapping
  (``GLSL_LUT_UV`` is the GLSL twin), and the thesis's midpoint Riemann sums (§1.7, §2.3);
* the **accuracy reference** of ``natura bench planet``: :func:`reference` integrates the same
  single-scattering integral (§1.5) in double precision with exact optical depths and thousands
  of steps.

Units and frames
----------------
Lengths are metres; coefficients are per metre. Positions here are **planet-centred** (the origin
at the Earth's centre). The scene's local frame has its origin on the sea surface with y up and the
planet centre at (0, −R, 0) (§1.3, implied); :func:`local_to_planet` converts. ``sun_dir`` is
the unit vector **toward** the sun — the thesis's ``lightDir`` points from the sun into the scene,
so ``sun_dir = −lightDir`` — and θ, the scattering angle of the phase functions, has
``cos θ = view_dir · sun_dir``: cos θ = 1 looking straight at the sun, where the Mie forward peak
(g > 0) is. Φ is the angle between the local vertical ("Earth normal") at a point and the sun.

The model, its errata and the two accumulation rules are docs/theory/002-atmosphere.md's §1.3,
§1.5, §1.7 and §6: ``optical_depth`` and ``OpticalDepthLut.lookup`` return the density
integrals D_R, D_M without P0 and β (so a change of either does not rebuild the table), and
``pc_rule="midpoint"`` (the default) is the second-order rule, ``"thesis"`` the printed one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Callable, NamedTuple

import numpy as np

from ..errors import ParamError
from ..params import Param
from . import maths
from .maths import normalize
from .optics import phase_mie_cornette_shanks, phase_rayleigh
from .optics import ray_sphere as optics_ray_sphere

#: the unit vector at an elevation and an azimuth (:func:`app.sim.maths.direction`): the sun
direction = maths.direction

SPEC = "spec/002"

#: Earth radius used by the scene (spec/002 §9, a proposed choice; the thesis gives none).
BOTTOM_RADIUS_M = 6_360_000.0
#: Height of the top of the atmosphere above sea level (§9 proposes R + 60 km; a parameter).
TOP_HEIGHT_M = 60_000.0
#: Density integral returned for sun rays that hit the planet (metres of sea-level air). Finite
#: so that float32 GPU code never meets inf·0; with the thesis's coefficients P0·β·1e12 ≥ 4e6,
#: and exp(−4e6) is 0 in float32 and float64 alike.
OPTICAL_DEPTH_GROUND_M = 1.0e12

_RGB = tuple[float, float, float]

#: The ozone layer (beyond the thesis, which has none): a tent profile of relative density, 0 below
#: OZONE_BOTTOM_M, rising linearly to 1 at OZONE_PEAK_M and back to 0 at OZONE_TOP_M — the
#: profile Bruneton 2017 ("Precomputed Atmospheric Scattering: a New Implementation") and
#: Hillaire 2020 use, after Bruneton's fit to the standard atmosphere's ozone number density.
OZONE_BOTTOM_M = 10_000.0
OZONE_PEAK_M = 25_000.0
OZONE_TOP_M = 40_000.0
#: the tent's vertical column ∫ ρ_O dh from the ground: ½ · 30 km · 1 = 15 km (of peak density)
OZONE_COLUMN_M = 0.5 * (OZONE_TOP_M - OZONE_BOTTOM_M)
#: ozone's absorption coefficient at the peak of the tent, RGB, 1/m: the values of Bruneton 2017's
#: demo (ozone absorption cross-sections, from the IUP Bremen reference spectra, at 680, 550 and
#: 440 nm, times the peak number density that makes the tent's column 300 Dobson units), which
#: Hillaire 2020's demo also uses: (0.650, 1.881, 0.085)·1e-6 /m.
#: Ozone absorbs only: it adds to the extinction and scatters nothing.
OZONE_ABSORPTION = (0.650e-6, 1.881e-6, 0.085e-6)


# ==== Constants and parameters (spec/002 §1.3, §7, §9) =======================================

def _rgb(name: str, value) -> _RGB:
    arr = np.broadcast_to(np.asarray(value, dtype=np.float64), (3,)) if np.ndim(value) == 0 \
        else np.asarray(value, dtype=np.float64)
    if arr.shape != (3,):
        raise ParamError(f"atmosphere.{name}={value!r} is not three numbers: "
                         "allowed R, G, B per metre")
    return tuple(float(v) for v in arr)


@dataclass(frozen=True)
class AtmosphereParams:
    """The thesis's constants (spec/002 §1.3, table §7) and the proposed choices of §9.

    All lengths in metres, coefficients per metre (RGB tuples). Frozen and hashable, so a
    lookup table can be cached by the parameters it depends on (:meth:`lut_key`).

    Construction validates the *physical* limits (|g| < 1, positive radii and scale heights,
    non-negative coefficients); the thesis's recommended ranges (§7: P0 ∈ [0.7, 1.3],
    g ∈ [0.70, 0.999], sun intensity ∈ [30, 100]) are the ranges of :func:`params_list`, which
    the UI, presets and ``--set`` enforce. Out-of-limit values raise :class:`ParamError` with one
    line naming the parameter and what is allowed.
    """

    #: planet radius R (§9 proposal; thesis: ``WORLD_RADIUS``, value not given)
    bottom_radius: float = BOTTOM_RADIUS_M
    #: atmosphere thickness (§9: 60 km; criterion 5 holds for 60–100 km; ``ATM_TOP_HEIGHT``)
    top_height: float = TOP_HEIGHT_M
    #: β^scatt_Ray at sea level, RGB (§1.3, §7), 1/m
    beta_rayleigh: _RGB = (5.8e-6, 13.5e-6, 33.1e-6)
    #: β^abs_Ray (§7: 0.0, "negligible"), 1/m
    rayleigh_absorption: _RGB = (0.0, 0.0, 0.0)
    #: β^scatt_Mie at sea level, RGB (§1.3, §7, from Yusov), 1/m
    beta_mie_scatter: _RGB = (2.0e-5, 2.0e-5, 2.0e-5)
    #: β^abs_Mie / β^scatt_Mie (§7: 0.1)
    mie_absorption_ratio: float = 0.1
    #: Rayleigh scale height H_R (§1.3), m
    h_rayleigh: float = 7994.0
    #: Mie scale height H_M (§1.3), m
    h_mie: float = 1200.0
    #: sea-level density scale P0 (§2.2 base 1; §7 range [0.7, 1.3]); scales both particle types
    p0: float = 1.0
    #: Cornette–Shanks asymmetry G (§1.2; §7 range [0.70, 0.999]; |G| < 1 required)
    g: float = 0.76
    #: sun radiance ``lightSun`` (§7 range [30, 100]), white
    sun_intensity: float = 30.0
    #: ozone layer scale (beyond the thesis): 0 = none (the thesis), 1 = the standard layer of
    #: Bruneton 2017 / Hillaire 2020 (tent 10–25–40 km, :data:`OZONE_ABSORPTION` at its peak)
    ozone: float = 0.0

    def __post_init__(self):
        for name in ("beta_rayleigh", "rayleigh_absorption", "beta_mie_scatter"):
            object.__setattr__(self, name, _rgb(name, getattr(self, name)))
        for f in fields(self):
            if f.name not in ("beta_rayleigh", "rayleigh_absorption", "beta_mie_scatter"):
                try:
                    object.__setattr__(self, f.name, float(getattr(self, f.name)))
                except (TypeError, ValueError):
                    raise ParamError(f"atmosphere.{f.name}={getattr(self, f.name)!r} "
                                     "is not a number: allowed a finite number") from None
        self.validate()

    def validate(self) -> "AtmosphereParams":
        """Raise :class:`ParamError` (one line: name, value, what is allowed) or return self."""

        def bad(name, value, allowed):
            return ParamError(f"atmosphere.{name}={value!r} is out of range: allowed {allowed}")

        for f in fields(self):
            v = getattr(self, f.name)
            if not all(math.isfinite(x) for x in (v if isinstance(v, tuple) else (v,))):
                raise ParamError(f"atmosphere.{f.name}={v!r} is not finite: allowed finite numbers")
        if not abs(self.g) < 1.0:
            raise bad("g", self.g, "|g| < 1 (the Cornette–Shanks phase is singular at ±1; "
                                   "thesis range [0.7, 0.999])")
        if self.bottom_radius <= 0.0:
            raise bad("bottom_radius", self.bottom_radius, "a radius > 0 m")
        if self.top_height <= 0.0:
            raise bad("top_height", self.top_height, "a height > 0 m (60 km by default)")
        for name in ("h_rayleigh", "h_mie"):
            if getattr(self, name) <= 0.0:
                raise bad(name, getattr(self, name), "a scale height > 0 m")
        for name in ("beta_rayleigh", "rayleigh_absorption", "beta_mie_scatter"):
            if min(getattr(self, name)) < 0.0:
                raise bad(name, getattr(self, name), "coefficients >= 0 per metre")
        for name in ("mie_absorption_ratio", "p0", "sun_intensity", "ozone"):
            if getattr(self, name) < 0.0:
                raise bad(name, getattr(self, name), "a number >= 0")
        return self

    # -- derived quantities (§1.3) -----------------------------------------------------------
    @property
    def top_radius(self) -> float:
        """R + atmosphere height (``ATM_RADIUS``), m."""
        return self.bottom_radius + self.top_height

    @property
    def scale_heights(self) -> np.ndarray:
        """(H_R, H_M), m."""
        return np.array([self.h_rayleigh, self.h_mie])

    @property
    def beta_rayleigh_scatter(self) -> np.ndarray:
        return np.array(self.beta_rayleigh)

    @property
    def beta_rayleigh_ext(self) -> np.ndarray:
        """β^ext_R = β^scatt_R + β^abs_R = β^scatt_R with the thesis's zero absorption (§1.3)."""
        return np.array(self.beta_rayleigh) + np.array(self.rayleigh_absorption)

    @property
    def beta_mie_absorption(self) -> np.ndarray:
        """β^abs_M = 0.1 · β^scatt_M (§7)."""
        return self.mie_absorption_ratio * np.array(self.beta_mie_scatter)

    @property
    def beta_mie_ext(self) -> np.ndarray:
        """β^ext_M = β^scatt_M + β^abs_M = 1.1 · 2.0e-5 = 2.2e-5 /m (§1.3, as we read it)."""
        return np.array(self.beta_mie_scatter) + self.beta_mie_absorption

    @property
    def beta_ozone(self) -> np.ndarray:
        """Ozone's absorption (= extinction) coefficient at the tent's peak, RGB, 1/m:
        ``ozone`` × :data:`OZONE_ABSORPTION` (0 with the thesis's model)."""
        return self.ozone * np.array(OZONE_ABSORPTION)

    def lut_key(self) -> tuple:
        """What the optical-depth LUT depends on: geometry and scale heights — not P0, β, g or
        the sun (they multiply the looked-up density integrals)."""
        return (self.bottom_radius, self.top_height, self.h_rayleigh, self.h_mie)

    def uniforms(self) -> dict:
        """Values for the uniforms of ``glsl/atmosphere/model.glsl`` (names as the GPU code)."""
        return {
            "uBottomRadius": self.bottom_radius,
            "uTopRadius": self.top_radius,
            "uBetaRayleigh": tuple(self.beta_rayleigh_ext),
            "uBetaMieScatter": tuple(self.beta_mie_scatter),
            "uBetaMieExt": tuple(self.beta_mie_ext),
            "uHRayleigh": self.h_rayleigh,
            "uHMie": self.h_mie,
            "uP0": self.p0,
            "uMieG": self.g,
            "uSunIntensity": self.sun_intensity,
            "uOzoneAbsorption": tuple(float(v) for v in self.beta_ozone),
        }

    def replace(self, **changes) -> "AtmosphereParams":
        """A copy with some fields changed (validated)."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        values.update(changes)
        return AtmosphereParams(**values)


#: UI units: β in 1e-6/m (= per megametre, so the sliders show the thesis's printed 5.8, 13.5,
#: 33.1 and, for Mie, 20 = 2.0e-5 /m); atmosphere height in km; scale heights in m.
BETA_UI_UNIT = 1.0e-6
TOP_HEIGHT_UI_UNIT = 1000.0


def params_list() -> list[Param]:
    """The ``atmosphere.*`` parameters (UI, presets, ``--set``), ranges from spec/002 §7.

    Units: ``top_height`` in km; ``beta_rayleigh`` (RGB) and ``beta_mie`` (grey, the thesis's
    (2, 2, 2)·1e-5) in 1e-6/m; ``mie_absorption`` as a fraction of Mie scattering; scale heights
    in m. :func:`from_params` converts to the SI units of :class:`AtmosphereParams`.
    """
    s = SPEC
    return [
        Param("atmosphere.g", 0.76, 0.70, 0.999,
              "Cornette–Shanks asymmetry G: size of the sun's Mie halo (|G| < 1)", step=0.001,
              section=f"{s} §1.2, §7"),
        Param("atmosphere.p0", 1.0, 0.7, 1.3, "sea-level density scale P0 (Rayleigh and Mie)",
              step=0.01, section=f"{s} §2.2, §7"),
        Param("atmosphere.sun_intensity", 30.0, 30.0, 100.0, "sun radiance lightSun (white)",
              step=0.5, section=f"{s} §7"),
        Param("atmosphere.top_height", TOP_HEIGHT_M / TOP_HEIGHT_UI_UNIT, 10.0, 200.0,
              "height of the top of the atmosphere above sea level", step=1.0, unit="km",
              section=f"{s} §9"),
        Param("atmosphere.h_rayleigh", 7994.0, 1000.0, 20000.0, "Rayleigh scale height H_R",
              step=1.0, unit="m", section=f"{s} §1.3"),
        Param("atmosphere.h_mie", 1200.0, 100.0, 10000.0, "Mie scale height H_M", step=1.0,
              unit="m", section=f"{s} §1.3"),
        Param("atmosphere.beta_rayleigh", (5.8, 13.5, 33.1), 0.0, 200.0,
              "Rayleigh scattering β^scatt_R at sea level, RGB (absorption 0: = β^ext_R)",
              kind="vec3", step=0.1, unit="1e-6/m", section=f"{s} §1.3, §7"),
        Param("atmosphere.beta_mie", 20.0, 0.0, 500.0,
              "Mie scattering β^scatt_M at sea level, grey (thesis 2.0e-5 /m)", step=0.5,
              unit="1e-6/m", section=f"{s} §1.3, §7"),
        Param("atmosphere.mie_absorption", 0.1, 0.0, 1.0,
              "Mie absorption as a fraction of Mie scattering (β^ext_M = (1 + this) β^scatt_M)",
              step=0.01, section=f"{s} §7"),
        Param("atmosphere.ozone", 0.0, 0.0, 3.0,
              "ozone layer (beyond the thesis, which has none: 0): absorption only, a tent "
              "10–25–40 km; 1 = the standard layer (Bruneton 2017, Hillaire 2020), σ_a = "
              "(0.650, 1.881, 0.085)·1e-6 /m at its peak; every method honours it",
              step=0.05, section=f"{s} §10.1"),
    ]


def from_params(paramset) -> AtmosphereParams:
    """Build :class:`AtmosphereParams` from a :class:`~app.params.ParamSet` (UI units → SI).
    Parameters the set does not declare keep their defaults."""
    defaults = {p.name: p.default for p in params_list()}

    def get(name):
        return paramset.get(name, defaults[name]) if hasattr(paramset, "get") else paramset[name]

    mie = get("atmosphere.beta_mie") * BETA_UI_UNIT
    return AtmosphereParams(
        top_height=get("atmosphere.top_height") * TOP_HEIGHT_UI_UNIT,
        beta_rayleigh=tuple(v * BETA_UI_UNIT for v in get("atmosphere.beta_rayleigh")),
        beta_mie_scatter=(mie, mie, mie),
        mie_absorption_ratio=get("atmosphere.mie_absorption"),
        h_rayleigh=get("atmosphere.h_rayleigh"),
        h_mie=get("atmosphere.h_mie"),
        p0=get("atmosphere.p0"),
        g=get("atmosphere.g"),
        sun_intensity=get("atmosphere.sun_intensity"),
        ozone=get("atmosphere.ozone"),
    )


AtmosphereParams.from_params = staticmethod(from_params)  # type: ignore[attr-defined]


# ==== Phase functions (spec/002 §1.2) ========================================================

def phase_mie(mu, g):
    """The Cornette–Shanks phase of :mod:`app.sim.optics` (§1.2) for the atmosphere's g:
    forward/backward ratio ((1+g)/(1−g))³ (394.37 at g = 0.76); the §2.3 code's ``3/8π`` prefix
    is the same constant (1/(4π)·3/2). |g| ≥ 1 raises :class:`ParamError`: at g = ±1 the
    denominator 1 + g² − 2gμ vanishes at μ = g (§1.2) and the factor 1 − g² is 0.
    Rayleigh's phase is :func:`app.sim.optics.phase_rayleigh`.
    """
    g = np.asarray(g, dtype=np.float64)
    if not np.all(np.abs(g) < 1.0):
        raise ParamError(f"atmosphere.g={float(np.max(np.abs(g)))!r} is out of range: "
                         "allowed |g| < 1 (thesis range [0.7, 0.999])")
    return phase_mie_cornette_shanks(mu, g)


# ==== Geometry (spec/002 §1.7, §2.4 item 2; criterion 6) =====================================

def local_to_planet(position, params: AtmosphereParams | None = None) -> np.ndarray:
    """Scene-local position (origin on the sea surface, y up) → planet-centred, m."""
    r = (params or AtmosphereParams()).bottom_radius
    return np.asarray(position, dtype=np.float64) + np.array([0.0, r, 0.0])


def ray_sphere(origin, direction, radius):
    """Distances (near, far) along ``origin + t·direction`` to the sphere |x| = radius about the
    planet centre (:func:`app.sim.optics.ray_sphere` with the centre at the origin); NaN where
    the line misses it."""
    return optics_ray_sphere(origin, direction, (0.0, 0.0, 0.0), radius)


def ground_distance(origin, direction, params: AtmosphereParams):
    """Distance along the ray to the sea-level sphere (the opaque ground), +inf when it misses or
    the sphere is behind; 0 for an origin inside the planet (nothing is seen from there)."""
    origin, direction = np.broadcast_arrays(np.asarray(origin, dtype=np.float64),
                                            np.asarray(direction, dtype=np.float64))
    near, far = ray_sphere(origin, direction, params.bottom_radius)
    inside = np.linalg.norm(origin, axis=-1) < params.bottom_radius
    out = np.where(np.isfinite(near) & (near >= 0.0), near, np.inf)
    return np.where(inside, 0.0, out)


class Segment(NamedTuple):
    """The part of a view ray inside the atmosphere: ``t0 ≤ t ≤ t1`` (m along the unit ray);
    ``hit`` false (and t0 = t1 = 0) where the ray does not cross the atmosphere."""

    t0: np.ndarray
    t1: np.ndarray
    hit: np.ndarray


def atmosphere_segment(cam, dirs, max_dist, params: AtmosphereParams,
                       clip_ground: bool = True) -> Segment:
    """The view segment clipped to the atmosphere (spec/002 §2.4 item 2; criterion 6).

    ``cam`` (3,) or (N, 3) planet-centred, ``dirs`` (N, 3) (normalised here), ``max_dist`` the
    distance to the visible object ((N,), a scalar, or None/inf for the sky). Returns
    :class:`Segment` (t0, t1, hit) with ``t0 = max(entry, 0)`` and
    ``t1 = min(exit, max_dist, ground)``:

    * camera inside, looking up              → (0, exit), |C + exit·d| = R_top;
    * camera inside, target below the top    → (0, target);
    * camera outside, ray misses the sphere  → hit = False (t0 = t1 = 0);
    * camera outside, ray crosses            → (entry, exit);
    * camera outside, target on the ground   → (entry, target).

    With ``clip_ground`` (default) the segment also stops at the sea-level sphere, which is
    opaque, so a sky ray that hits the planet ends there. The thesis's form "(atmosphere point,
    camera)" is the same segment written from the other end.
    """
    cam = np.asarray(cam, dtype=np.float64)
    dirs = normalize(np.asarray(dirs, dtype=np.float64))
    cam_b, dirs = np.broadcast_arrays(cam, dirs)
    near, far = ray_sphere(cam_b, dirs, params.top_radius)
    limit = np.full(near.shape, np.inf) if max_dist is None else \
        np.broadcast_to(np.asarray(max_dist, dtype=np.float64), near.shape)
    if clip_ground:
        limit = np.minimum(limit, ground_distance(cam_b, dirs, params))
    with np.errstate(invalid="ignore"):
        t0 = np.maximum(near, 0.0)
        t1 = np.minimum(far, limit)
        hit = np.isfinite(near) & (far > 0.0) & (t1 > t0)
    return Segment(np.where(hit, t0, 0.0), np.where(hit, t1, 0.0), hit)


# ==== Density and optical depth (spec/002 §1.3, §1.7, §1.8) ==================================

def density(h, H, p0: float = 1.0):
    """ρ(h) = P0 · exp(−h/H) (§1.3); heights below 0 are clamped to sea level (as the GPU's
    ``DensityRM``) so rounding at the ground never adds density."""
    return p0 * np.exp(-np.maximum(np.asarray(h, dtype=np.float64), 0.0) / H)


def ozone_density(h):
    """The ozone layer's relative density (beyond the thesis): the tent 0 below
    :data:`OZONE_BOTTOM_M`, 1 at :data:`OZONE_PEAK_M`, 0 from :data:`OZONE_TOP_M` up (Bruneton
    2017's profile). Its absorption is ``params.beta_ozone`` × this (GLSL ``DensityOzone``)."""
    h = np.asarray(h, dtype=np.float64)
    half = OZONE_PEAK_M - OZONE_BOTTOM_M
    return np.maximum(1.0 - np.abs(h - OZONE_PEAK_M) / half, 0.0)


def ozone_optical_depth(h, cos_phi, params: AtmosphereParams, nodes: int = 8,
                        ground: bool = True):
    """Exact ozone density integral D_O = ∫ ρ_O ds (m) from height ``h`` along cos Φ to the top.

    The perigee form of :func:`_density_integrals` (altitude above the perigee y = z², smooth
    arc element) with the z interval cut where the line crosses 10, 25 and 40 km: on each piece
    the tent is linear in y, so the integrand is smooth and Gauss–Legendre converges spectrally
    (8 nodes per piece: ~1e-13 relative). Rays that hit the planet → +inf (``ground``) or, with
    ground=False, the perigee put on the ground (the LUT's horizon column). Shape of the inputs.
    """
    R = params.bottom_radius
    top = params.top_height
    h = np.clip(np.asarray(h, dtype=np.float64), 0.0, top)
    mu = np.clip(np.asarray(cos_phi, dtype=np.float64), -1.0, 1.0)
    h, mu = np.broadcast_arrays(h, mu)
    shape = h.shape
    h, mu = h.reshape(-1), mu.reshape(-1)
    r = R + h
    k = h * (2.0 * R + h) - r * r * mu * mu
    below = mu < 0.0
    hits = below & (k <= 0.0)
    k = np.where(below, np.maximum(k, 0.0), k)
    r_p = np.sqrt(np.maximum(R * R + k, 0.0))
    h_p = k / (r_p + R)
    z_p = np.sqrt(np.maximum(h - h_p, 0.0))
    z_t = np.sqrt(np.maximum(top - h_p, 0.0))
    x, w = _gauss_legendre(nodes)
    half = OZONE_PEAK_M - OZONE_BOTTOM_M

    def integral(rows, a, b):
        """∫ from z = a to b (a ≤ b per ray) for the rays ``rows``, split at the tent's kinks.
        A piece whose nodes all lie outside the tent adds exactly 0, so it is skipped: the node
        altitudes rise with the node (z ≥ 0, rounding is monotone), so the first and last
        nodes' altitudes, computed as below, bound every node's; the sums are the same."""
        hp, rp = h_p[rows], r_p[rows]
        cuts = [a] + [np.clip(np.sqrt(np.maximum(hk - hp, 0.0)), a, b)
                      for hk in (OZONE_BOTTOM_M, OZONE_PEAK_M, OZONE_TOP_M)] + [b]
        total = np.zeros(a.shape)
        for lo, hi in zip(cuts[:-1], cuts[1:]):
            span = hi - lo
            first, last = lo + span * x[0], lo + span * x[-1]
            live = np.flatnonzero((OZONE_PEAK_M - (hp + last * last) < half)
                                  & ((hp + first * first) - OZONE_PEAK_M < half))
            if live.size == 0:
                continue
            sp = span[live, None]
            z = lo[live, None] + sp * x
            zz = z * z
            fac = sp * (2.0 * w) * (rp[live, None] + zz) / np.sqrt(2.0 * rp[live, None] + zz)
            total[live] += (fac * ozone_density(hp[live, None] + zz)).sum(-1)
        return total

    # only the integrals each ray needs (down to the perigee and up, or up from the point)
    out = np.empty(h.shape)
    up, down = np.flatnonzero(~below), np.flatnonzero(below)
    out[up] = integral(up, z_p[up], z_t[up])
    zero = np.zeros(down.size)
    out[down] = integral(down, zero, z_t[down]) + integral(down, zero, z_p[down])
    if ground:
        out = np.where(hits, np.inf, out)
    return out.reshape(shape)


def sun_ray_hits_ground(h, cos_phi, params: AtmosphereParams):
    """True where the ray from height ``h`` at cos Φ (to the local vertical) hits the planet:
    cos Φ < 0 and r² cos²Φ ≥ r² − R² = h(2R + h). A tangent ray counts as hitting (the GLSL twin
    ``SunRayHitsGround`` uses the same float-safe form)."""
    h = np.maximum(np.asarray(h, dtype=np.float64), 0.0)
    mu = np.asarray(cos_phi, dtype=np.float64)
    R = params.bottom_radius
    r = R + h
    return (mu < 0.0) & (r * r * mu * mu >= h * (2.0 * R + h))


#: rays per chunk of the Gauss–Legendre pieces of :func:`_density_integrals` (their scratch
#: arrays, rays × nodes, stay in the CPU's cache)
_GL_ROWS = 1024


def _gauss_legendre(n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return (x + 1.0) / 2.0, w / 2.0


def _density_integrals(h, mu, params: AtmosphereParams, nodes: int = 24, ground: bool = True):
    """Exact (D_R, D_M) = ∫ exp(−h(s)/H) ds from height ``h`` along cos Φ = ``mu`` to the top.

    Every straight line has a perigee at radius r_p = r·√(1 − μ²) (ahead of the point when μ < 0,
    behind it — possibly deep inside the planet — when μ ≥ 0). Measured from the perigee, the
    radius along the line is r² = r_p² + σ², so with the altitude gain y = z² above the perigee
    the arc element is ``ds = 2 (r_p + z²) / √(2 r_p + z²) dz`` — smooth, with no square-root
    singularity at the perigee — and the integrand is a Gaussian ``exp(−(h_p + z²)/H)`` times
    that smooth factor. Gauss–Legendre in z on [z_P, z_top] (μ ≥ 0), or on [0, z_top] plus
    [0, z_P] (μ < 0: down to the perigee and back up) converges spectrally: 24 nodes per piece
    give ~1e-12 relative against a 2·10⁶-step midpoint sum, grazing rays included.

    ``ground``: rays that hit the planet give +inf. With ground=False they are integrated as if
    the perigee were on the ground (used only for the LUT's exactly tangent horizon column).
    Returns (..., 2) float64.
    """
    R = params.bottom_radius
    top = params.top_height
    h = np.clip(np.asarray(h, dtype=np.float64), 0.0, top)
    mu = np.clip(np.asarray(mu, dtype=np.float64), -1.0, 1.0)
    h, mu = np.broadcast_arrays(h, mu)
    r = R + h
    # r_p² − R² = (r² − R²) − r²μ², without cancellation of the R² terms
    k = h * (2.0 * R + h) - r * r * mu * mu
    below = mu < 0.0
    hits = below & (k <= 0.0)
    if not ground:
        k = np.where(below, np.maximum(k, 0.0), k)
    r_p = np.sqrt(np.maximum(R * R + k, 0.0))
    h_p = k / (r_p + R)
    y_p = np.maximum(h - h_p, 0.0)          # altitude of the point above the perigee
    y_t = np.maximum(top - h_p, 0.0)        # altitude of the top above the perigee
    z_p, z_t = np.sqrt(y_p), np.sqrt(y_t)
    x, w = _gauss_legendre(nodes)
    w2 = w * 2.0            # (b − a)·w·2 == (b − a)·(2w) exactly: doubling is exact
    H = params.scale_heights
    shape = h.shape
    skip = hits if ground else np.zeros_like(hits)   # ground rays: +inf below, not integrated
    r_p, h_p, z_p, z_t, below, skip = (a.reshape(-1) for a in (r_p, h_p, z_p, z_t, below, skip))
    total = np.zeros((r_p.size, 2))

    rows = max(1, min(r_p.size, _GL_ROWS))
    z, fac, e = np.empty((rows, nodes)), np.empty((rows, nodes)), np.empty((rows, nodes))

    def piece(idx, a, b):
        """Gauss–Legendre on [a, b] in z for the rays ``idx`` (only those, so no inf/NaN).
        The operations of ``fac·exp(−alt/H)`` in their order, in three scratch arrays of a few
        rays at a time (no fresh temporaries: cache-sized and no page faults), −alt/H as
        alt/(−H) (IEEE division is sign-symmetric): the same numbers."""
        for c in range(0, idx.size, rows):
            j = idx[c:c + rows]
            m = j.size
            zb, fb, eb = z[:m], fac[:m], e[:m]
            rp, hp = r_p[j, None], h_p[j, None]
            span = (b[c:c + rows] - a[c:c + rows])[:, None]
            np.multiply(span, x, out=zb)
            zb += a[c:c + rows, None]
            zz = np.multiply(zb, zb, out=zb)
            np.multiply(span, w2, out=fb)
            np.add(rp, zz, out=eb)
            fb *= eb
            np.add(2.0 * rp, zz, out=eb)
            fb /= np.sqrt(eb, out=eb)
            alt = np.add(hp, zz, out=zb)
            for i in range(2):
                np.divide(alt, -H[i], out=eb)
                np.exp(eb, out=eb)
                eb *= fb
                total[j, i] += eb.sum(-1)

    up = np.flatnonzero(~below)          # from the point (above its perigee) to the top
    piece(up, z_p[up], z_t[up])
    down = np.flatnonzero(below & ~skip)       # perigee → top, plus perigee → back up to the point
    piece(down, np.zeros(down.size), z_t[down])
    piece(down, np.zeros(down.size), z_p[down])
    total = total.reshape(shape + (2,))
    if ground:
        total = np.where(hits[..., None], np.inf, total)
    return total


def optical_depth(h, cos_phi, params: AtmosphereParams, nodes: int = 24):
    """Exact density integrals ``(D_R, D_M)`` (m) from height ``h`` along a direction at cos Φ to
    the local vertical, up to the top of the atmosphere (§1.3, §1.8).

    ``D = ∫ exp(−h(s)/H) ds`` — **without P0 and β**: the optical depth is
    ``τ = P0 (β^ext_R D_R + β^ext_M D_M)``. Vertically, ``D = H (e^(−h/H) − e^(−Htop/H))``.
    Rays that hit the planet return +inf (the point is in the planet's shadow: no sunlight).
    ``h`` is clamped to [0, top]. Accuracy ~1e-12 relative (see :func:`_density_integrals`).
    Returns a tuple of two arrays shaped like the broadcast inputs.
    """
    d = _density_integrals(h, cos_phi, params, nodes)
    return d[..., 0], d[..., 1]


def _midpoint_columns(h, cos_phi, params: AtmosphereParams, steps: int, densities) -> np.ndarray:
    """Midpoint Riemann sums ∑ ρ_k(alt) ds over ``steps`` equal steps from each point to where
    its ray leaves the atmosphere, one column per function of ``densities`` (altitude → density);
    ground rays → +inf. Shape: the broadcast of (h, cos_phi) + (len(densities),)."""
    R = params.bottom_radius
    h = np.clip(np.asarray(h, dtype=np.float64), 0.0, params.top_height)
    mu = np.clip(np.asarray(cos_phi, dtype=np.float64), -1.0, 1.0)
    h, mu = np.broadcast_arrays(h, mu)
    shape = h.shape
    h, mu = h.reshape(-1), mu.reshape(-1)
    ds = _atmosphere_exit(h, mu, params) / steps
    r = R + h
    frac = np.arange(steps) + 0.5
    out = np.zeros((h.size, len(densities)))
    chunk = max(1, 2_000_000 // steps)           # bound the (rays, steps) temporaries
    for a in range(0, h.size, chunk):
        b = slice(a, a + chunk)
        s = frac * ds[b, None]
        rb, mub = r[b, None], mu[b, None]
        alt = np.sqrt(np.maximum(s * s + 2.0 * rb * mub * s + rb * rb, 0.0)) - R
        for i, density in enumerate(densities):
            out[b, i] = density(alt).sum(-1) * ds[b]
    out = np.where(sun_ray_hits_ground(h, mu, params)[:, None], np.inf, out)
    return out.reshape(shape + (len(densities),))


def optical_depth_midpoint(h, cos_phi, params: AtmosphereParams, steps: int = 1000):
    """The thesis's inner loop (§2.3): a midpoint Riemann sum of exp(−h/H) over ``steps`` equal
    steps from the point to where its ray leaves the atmosphere (the GPU's
    ``SunDepthBruteForce``). Ground rays → +inf. Returns (D_R, D_M), without P0."""
    H = params.scale_heights
    out = _midpoint_columns(h, cos_phi, params, steps,
                            [lambda alt, k=k: np.exp(-np.maximum(alt, 0.0) / H[k])
                             for k in range(2)])
    return out[..., 0], out[..., 1]


def ozone_optical_depth_midpoint(h, cos_phi, params: AtmosphereParams, steps: int = 1000):
    """The brute-force inner loop of :func:`optical_depth_midpoint` for the ozone layer (the
    third component of the GPU's ``SunDepthBruteForce``): ∑ ρ_O ds over ``steps`` equal steps to
    the top. Ground rays → +inf."""
    return _midpoint_columns(h, cos_phi, params, steps, [ozone_density])[..., 0]


def _atmosphere_exit(h, mu, params: AtmosphereParams):
    """Distance from height h along cos Φ = mu to the top sphere (stable for both signs of mu):
    d = −rμ + √(r²μ² + k), k = R_top² − r² = (top − h)(2R + top + h) ≥ 0."""
    R, top = params.bottom_radius, params.top_height
    r = R + h
    k = np.maximum((top - h) * (2.0 * R + top + h), 0.0)
    sq = np.sqrt(r * r * mu * mu + k)
    with np.errstate(divide="ignore", invalid="ignore"):
        pos = k / (r * mu + sq)
    return np.where(mu > 0.0, np.where(np.isfinite(pos), pos, 0.0), sq - r * mu)


# ==== The optical-depth lookup table — the thesis's "Chapman function" (spec/002 §1.8) =======
#
# What a texel holds. The thesis stores, per particle type, the density integral D(h, Φ) from the
# point to the top of the atmosphere. Stored as is, D varies like exp(−h/H) along the height axis,
# and bilinear filtering of an exponential over a 256-row table misses Mie (H_M = 1200 m) by ~2 %
# (99th percentile; ~10 % near the horizon in optical depth). So the table stores the density
# integral **divided by the vertical column at the lowest point of the ray** — a Chapman function
# in its classical sense (slant column / vertical column):
#
#     C_x(h, Φ) = D_x(h, Φ) / (H_x · exp(−h_low / H_x)),     D_x = C_x · H_x · exp(−h_low / H_x)
#
# with h_low the lowest altitude between the point and the top: h itself when cos Φ ≥ 0, the
# perigee altitude h_p = r·sin Φ − R when cos Φ < 0 (the ray first descends; rays in the table
# never hit the ground, so h_p ≥ 0). C is a slowly varying function (1 − e^(−(top−h)/H) for the
# vertical, ~√(πr/2H) on the horizon), and the lookup restores the exponential exactly:
# ``OpticalDepthToSun`` (GLSL) and :meth:`OpticalDepthLut.lookup` return D, the thesis's quantity.
# Against exact integrals, a 256×256 table then errs < 0.3 % (R) and < 0.5 % (M) relative below
# the top 2 km, and < 6e-4 in optical depth everywhere, the grazing band included.
#
# Layout. One RGB32F texture (the thesis used one RGBA8-packed texture per particle type; bilinear
# filtering of packed bytes is wrong, §1.8): R = C_R, G = C_M (dimensionless), B = the ozone
# layer's density integral D_O / 15 km (beyond the thesis; read only when the layer is on).
# numpy ``table[row, column, channel]`` has shape (n_height, n_angle, 3) and is uploaded as a
# (width = n_angle, height = n_height) texture: **rows = height (v), columns = cos Φ (u)**, as the
# thesis. Row 0 (v near 0) is sea level; column 0 (u near 0) is the horizon.
#
# Parametrisation (Bruneton 2017, ``GetTransmittanceTextureUvFromRMu``, with u reversed so u grows
# with cos Φ). With r = R + h, H_top = √(R_top² − R²) (the distance to the top along the horizontal
# at sea level), ρ = √(r² − R²) = √(h(2R + h)) (distance to the horizon) and d the distance from the
# point to the top along the ray:
#
#     x_h = ρ / H_top                                  ∈ [0, 1]   (0 at sea level, 1 at the top)
#     x_Φ = (d_max − d) / (d_max − d_min),  d_min = R_top − r, d_max = ρ + H_top
#                                                      ∈ [0, 1]   (0 on the horizon, 1 at zenith)
#     (u, v) = ((0.5 + x_Φ (W − 1)) / W, (0.5 + x_h (Hgt − 1)) / Hgt)      texel centres at the ends
#
# Why this one: (1) the horizon, whose cos Φ = −ρ/r depends on height, is always the first column,
# so the table holds only rays that leave the atmosphere and bilinear filtering never blends a
# "ground" texel into a sky texel; (2) x_h ∝ √h near the ground puts rows where the grazing depth
# changes fastest (like √h on the horizon, smoothly in ρ); (3) x_Φ spends columns near the horizon.
# The texel-centre mapping makes x = 0 and x = 1 exact texel centres, so with LINEAR filtering and
# CLAMP_TO_EDGE a lookup never extrapolates.
#
# Rays toward the sun that hit the planet are not in the table: the lookup tests
# ``SunRayHitsGround`` first and returns OPTICAL_DEPTH_GROUND_M (1e12 m) → transmittance 0.
# Heights are clamped to [0, top] and cos Φ to [−1, 1].
#
# GPU precision: r² − R² is written h(2R + h), R_top² − r² as (top − h)(2R + top + h), d without
# cancellation for cos Φ > 0 and h_p from r_p² − R² = h(2R + h) − r² cos²Φ, so float32 keeps
# ~1e-6 in (u, v) and millimetres in h_p at planet scale. GL's LINEAR filter on most hardware uses
# 8-bit fractional weights (up to ~1/512 of the difference of neighbouring texels); the numpy
# lookup here uses exact weights.

def _glsl_lut_source() -> str:
    """The GPU side of the table, ``glsl/atmosphere/optical_depth_lut.glsl`` (one source: the
    scene's shaders include that file; tests compile it and compare it with this module)."""
    from .. import DEFAULT_SHADER_ROOT

    return (DEFAULT_SHADER_ROOT / "atmosphere" / "optical_depth_lut.glsl").read_text(
        encoding="utf-8")


#: The GLSL of the table: the sampler declaration and ``SunRayHitsGround``, ``OpticalDepthLutUv``,
#: ``OpticalDepthLowestHeight``, ``OpticalDepthToSun`` (they use the model's uniforms uBottomRadius,
#: uTopRadius, uHRayleigh, uHMie and uP0 from ``glsl/atmosphere/model.glsl``).
GLSL_LUT_UV = _glsl_lut_source()


def lut_coordinates(h, cos_phi, params: AtmosphereParams):
    """(x_Φ, x_h) ∈ [0, 1]² of the LUT parametrisation (before the texel-centre mapping)."""
    R, top = params.bottom_radius, params.top_height
    h = np.clip(np.asarray(h, dtype=np.float64), 0.0, top)
    mu = np.clip(np.asarray(cos_phi, dtype=np.float64), -1.0, 1.0)
    h, mu = np.broadcast_arrays(h, mu)
    h_top = math.sqrt(top * (2.0 * R + top))
    rho = np.sqrt(h * (2.0 * R + h))
    d = _atmosphere_exit(h, mu, params)
    d_min = top - h
    d_max = rho + h_top
    x_phi = np.clip((d_max - d) / (d_max - d_min), 0.0, 1.0)
    x_h = np.clip(rho / h_top, 0.0, 1.0)
    return x_phi, x_h


def lut_uv(h, cos_phi, params: AtmosphereParams, size=(256, 256)):
    """Texture coordinates (u, v) of (h, cos Φ) — the numpy twin of ``OpticalDepthLutUv``.
    ``size`` = (width = n_angle, height = n_height) as the texture. Returns (..., 2)."""
    x_phi, x_h = lut_coordinates(h, cos_phi, params)
    w, hgt = size
    return np.stack([(0.5 + x_phi * (w - 1)) / w, (0.5 + x_h * (hgt - 1)) / hgt], axis=-1)


def lut_inverse(x_phi, x_h, params: AtmosphereParams):
    """(h, cos Φ) of table coordinates (x_Φ, x_h) — inverse of :func:`lut_coordinates`."""
    R, top = params.bottom_radius, params.top_height
    x_phi = np.asarray(x_phi, dtype=np.float64)
    x_h = np.asarray(x_h, dtype=np.float64)
    h_top = math.sqrt(top * (2.0 * R + top))
    rho = h_top * x_h
    h = rho * rho / (R + np.sqrt(R * R + rho * rho))   # ρ² = h(2R + h), without cancellation
    r = R + h
    d_min = top - h
    d_max = rho + h_top
    d = d_max - x_phi * (d_max - d_min)
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(d > 0.0, (h_top * h_top - rho * rho - d * d) / (2.0 * r * d), 1.0)
    return h, np.clip(mu, -1.0, 1.0)


def lowest_height(h, cos_phi, params: AtmosphereParams):
    """h_low: the lowest altitude on the ray from (h, cos Φ) to the top — h for cos Φ ≥ 0, the
    perigee altitude for cos Φ < 0 (0 for rays that hit the ground). Twin of
    ``OpticalDepthLowestHeight``."""
    R = params.bottom_radius
    h = np.clip(np.asarray(h, dtype=np.float64), 0.0, params.top_height)
    mu = np.asarray(cos_phi, dtype=np.float64)
    r = R + h
    k = np.maximum(h * (2.0 * R + h) - r * r * mu * mu, 0.0)
    return np.where(mu >= 0.0, h, k / (np.sqrt(R * R + k) + R))


def vertical_column(h_low, params: AtmosphereParams) -> np.ndarray:
    """H_x · exp(−h_low / H_x) for x = R, M: the normalisation of the LUT texels. (..., 2)."""
    H = params.scale_heights
    return H * np.exp(-np.asarray(h_low, dtype=np.float64)[..., None] / H)


class OpticalDepthLut:
    """The thesis's "Chapman function" table (spec/002 §1.8), built at start and when
    :meth:`AtmosphereParams.lut_key` changes (P0, β, g and the sun are applied after lookup).

    ``table`` is float32 (n_height, n_angle, 3) of Chapman ratios C = D / (H exp(−h_low/H)) for
    Rayleigh and Mie and, third, the ozone density integral D_O / :data:`OZONE_COLUMN_M` (stored
    as is: the tent has no exponential to factor out) — upload as an RGB32F texture of size
    (n_angle, n_height) with LINEAR filtering and CLAMP_TO_EDGE and read it through
    ``OpticalDepthToSun`` (``GLSL_LUT_UV``). ``densities`` holds the texels' density integrals
    D (float64, m). Every texel is exact (:func:`optical_depth`,
    ~1e-12), so the table's only error is interpolation.
    """

    def __init__(self, params: AtmosphereParams, n_height: int = 256, n_angle: int = 256,
                 nodes: int = 24):
        if n_height < 2 or n_angle < 2:
            raise ParamError(f"optical-depth LUT size {n_angle}x{n_height} is too small: "
                             "allowed at least 2x2")
        self.params = params
        self.n_height = int(n_height)
        self.n_angle = int(n_angle)
        self.key = params.lut_key() + (self.n_height, self.n_angle)
        x_phi = np.linspace(0.0, 1.0, self.n_angle)
        x_h = np.linspace(0.0, 1.0, self.n_height)
        h, mu = lut_inverse(x_phi[None, :], x_h[:, None], params)
        #: texel heights and cosines (n_height, n_angle)
        self.heights, self.cos_phi = h, mu
        #: density integrals D at the texels (n_height, n_angle, 2), float64, m
        self.densities = _density_integrals(h, mu, params, nodes, ground=False)
        #: the texture: Chapman ratios and ozone, float32 (n_height, n_angle, 3)
        #: ozone density integrals D_O at the texels (n_height, n_angle), float64, m
        self.ozone = ozone_optical_depth(h, mu, params, ground=False)
        column = vertical_column(lowest_height(h, mu, params), params)
        self.table = np.concatenate([self.densities / column,
                                     (self.ozone / OZONE_COLUMN_M)[..., None]],
                                    axis=-1).astype(np.float32)

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) of the texture = (n_angle, n_height)."""
        return (self.n_angle, self.n_height)

    def uv(self, h, cos_phi):
        return lut_uv(h, cos_phi, self.params, self.size)

    def sample(self, uv) -> np.ndarray:
        """GL ``texture()`` with LINEAR filtering and CLAMP_TO_EDGE on the float32 table:
        texel centres at (i + 0.5)/W, exact (not 8-bit) weights. Returns (..., 2) float64."""
        uv = np.asarray(uv, dtype=np.float64)
        tab = self.table.astype(np.float64)
        x = uv[..., 0] * self.n_angle - 0.5
        y = uv[..., 1] * self.n_height - 0.5
        x0 = np.floor(x)
        y0 = np.floor(y)
        fx = (x - x0)[..., None]
        fy = (y - y0)[..., None]
        i0 = np.clip(x0.astype(np.int64), 0, self.n_angle - 1)
        i1 = np.clip(x0.astype(np.int64) + 1, 0, self.n_angle - 1)
        j0 = np.clip(y0.astype(np.int64), 0, self.n_height - 1)
        j1 = np.clip(y0.astype(np.int64) + 1, 0, self.n_height - 1)
        row0 = tab[j0, i0] * (1.0 - fx) + tab[j0, i1] * fx
        row1 = tab[j1, i0] * (1.0 - fx) + tab[j1, i1] * fx
        return row0 * (1.0 - fy) + row1 * fy

    def optical_depth_to_sun(self, h, cos_phi, p0: float | None = None) -> np.ndarray:
        """Twin of GLSL ``OpticalDepthToSun``: (P0·D_R, P0·D_M, D_O) in m by bilinear lookup
        (the ozone integral D_O has no P0), or OPTICAL_DEPTH_GROUND_M (without P0) for rays that
        hit the planet. Returns (..., 3)."""
        p0 = self.params.p0 if p0 is None else p0
        column = vertical_column(lowest_height(h, cos_phi, self.params), self.params)
        texel = self.sample(self.uv(h, cos_phi))
        d = np.concatenate([p0 * column * texel[..., :2], OZONE_COLUMN_M * texel[..., 2:3]],
                           axis=-1)
        ground = sun_ray_hits_ground(h, cos_phi, self.params)
        return np.where(ground[..., None], OPTICAL_DEPTH_GROUND_M, d)

    def lookup(self, h, cos_phi):
        """(D_R, D_M) at (h, cos Φ) by bilinear lookup, without P0 — the tabulated "optical
        depth" of the thesis; rays that hit the planet → :data:`OPTICAL_DEPTH_GROUND_M`. Same
        shapes as :func:`optical_depth`."""
        d = self.optical_depth_to_sun(h, cos_phi, 1.0)
        return d[..., 0], d[..., 1]

# ==== Exposure (spec/002 §1.6) ===============================================================

def pupil(cos_gamma):
    """The thesis's variable exposure ``clamp(1 − cos γ / 4, 0, 1)`` with
    cos γ = camera_forward · sun_dir: 0.75 looking at the sun, 1 at 90° and beyond."""
    return np.clip(1.0 - np.asarray(cos_gamma, dtype=np.float64) / 4.0, 0.0, 1.0)


def final_colour(x, pupil=1.0):
    """``1 − exp(−pupil · x)`` (§1.6; O'Neil's exposure): maps radiance x ≥ 0 into [0, 1)."""
    return 1.0 - np.exp(-np.asarray(pupil, dtype=np.float64) * np.asarray(x, dtype=np.float64))


# ==== Single scattering (spec/002 §1.5, §1.7, §2.3–2.5) and the reference ====================

class Scattering(NamedTuple):
    """Per ray, linear RGB (N, 3): in-scattered radiance (the thesis's "in-scattering on black"),
    transmittance e^(−τ(C O)) of the whole segment ("out-scattering on white") and
    ``radiance = surface_colour · transmittance + in_scatter`` (Color_out + Color_in, before the
    exposure of :func:`final_colour`)."""

    in_scatter: np.ndarray
    transmittance: np.ndarray
    radiance: np.ndarray


SunDepth = Callable[[np.ndarray, np.ndarray], np.ndarray]

#: sample points (rays × samples) of one block of :func:`_integrate`: its per-point work is done
#: a block at a time (one ``sun_depth`` call for many samples, a few MB of temporaries)
_BLOCK_POINTS = 1 << 15


def _integrate(cam, dirs, sun_dir, params: AtmosphereParams, max_dist, surface_colour, steps: int,
               sun_depth: SunDepth, visibility, pc_rule: str, clip_ground: bool) -> Scattering:
    """Midpoint sum of the in-scattering integral over the clipped view segment, vectorised over
    rays and blocks of samples (memory O(:data:`_BLOCK_POINTS`) beside O(rays)); the running
    sums go sample by sample, so the result is the plain per-sample loop's, bit for bit."""
    if pc_rule not in ("midpoint", "thesis"):
        raise ParamError(f"pc_rule={pc_rule!r} is not a rule: allowed midpoint, thesis")
    if steps < 1:
        raise ParamError(f"steps={steps!r} is out of range: allowed an integer >= 1")
    dirs = normalize(np.atleast_2d(np.asarray(dirs, dtype=np.float64)))
    n = dirs.shape[0]
    cam = np.broadcast_to(np.asarray(cam, dtype=np.float64), (n, 3))
    sun = normalize(np.asarray(sun_dir, dtype=np.float64))
    seg = atmosphere_segment(cam, dirs, max_dist, params, clip_ground=clip_ground)
    ds = (seg.t1 - seg.t0) / steps
    R = params.bottom_radius
    H = params.scale_heights
    p0 = params.p0
    b_r_ext = params.beta_rayleigh_ext
    b_m_ext = params.beta_mie_ext
    # with the ozone layer on, a third component: the ozone density integral (no P0), whose
    # absorption b_o adds to the extinction only (off: two components, the thesis's sums exactly)
    ozone = params.ozone > 0.0
    b_o = params.beta_ozone
    width = 3 if ozone else 2
    acc = np.zeros((n, width))      # P0-scaled density integral camera → current position
    sum_r = np.zeros((n, 3))
    sum_m = np.zeros((n, 3))
    # the samples' geometry, densities and τ(AP) are per point, so they are computed for a
    # block of samples at once (one sun_depth call per block, not per sample: the same
    # element-wise operations on more elements, so the same numbers); only τ(PC) and the sums
    # run sample after sample, in the order of the plain loop
    block = max(1, min(steps, _BLOCK_POINTS // max(n, 1)))
    for k0 in range(0, steps, block):
        ks = np.arange(k0, min(steps, k0 + block), dtype=np.float64)
        m = ks.size
        t = seg.t0 + (ks[:, None] + 0.5) * ds                          # (m, n)
        P = cam + t[..., None] * dirs                                  # (m, n, 3)
        r = np.linalg.norm(P, axis=-1)
        h = r - R
        rho = p0 * np.exp(-np.maximum(h, 0.0)[..., None] / H)          # (m, n, 2)
        if ozone:
            rho = np.concatenate([rho, ozone_density(h)[..., None]], axis=-1)
        step = rho * ds[:, None]
        cos_phi = np.einsum("ij,j->i", P.reshape(-1, 3), sun).reshape(m, n) \
            / np.where(r > 0.0, r, 1.0)
        tau_ap = sun_depth(h.reshape(-1), cos_phi.reshape(-1)).reshape(m, n, width)  # P0 incl.
        # acc before each sample: acc, acc + s0, (acc + s0) + s1, ... (an accumulate adds in
        # sequence, as the loop's acc += step)
        before = np.add.accumulate(np.concatenate([acc[None], step]), axis=0)
        acc = before[-1]
        tau_pc = before[1:] if pc_rule == "thesis" else before[:-1] + 0.5 * step
        lit = np.isfinite(tau_ap[..., 0]) & (tau_ap[..., 0] < OPTICAL_DEPTH_GROUND_M)
        tau = np.where(lit[..., None], tau_ap, 0.0) + tau_pc
        ext = np.exp(-(b_r_ext * tau[..., 0:1] + b_m_ext * tau[..., 1:2]
                       + (b_o * tau[..., 2:3] if ozone else 0.0)))
        ext = np.where(lit[..., None], ext, 0.0)
        if visibility is not None:
            ext = ext * np.stack([np.asarray(visibility(P[j]), dtype=np.float64).reshape(n, 1)
                                  for j in range(m)])
        sum_r = np.add.accumulate(np.concatenate([sum_r[None], rho[..., 0:1] * ext
                                                  * ds[:, None]]), axis=0)[-1]
        sum_m = np.add.accumulate(np.concatenate([sum_m[None], rho[..., 1:2] * ext
                                                  * ds[:, None]]), axis=0)[-1]
    cos_theta = dirs @ sun
    in_scatter = params.sun_intensity * (
        sum_r * params.beta_rayleigh_scatter * phase_rayleigh(cos_theta)[:, None]
        + sum_m * np.array(params.beta_mie_scatter) * phase_mie(cos_theta, params.g)[:, None])
    transmittance = np.exp(-(b_r_ext * acc[:, 0:1] + b_m_ext * acc[:, 1:2]
                             + (b_o * acc[:, 2:3] if ozone else 0.0)))
    surface = np.zeros((n, 3)) if surface_colour is None else \
        np.broadcast_to(np.asarray(surface_colour, dtype=np.float64), (n, 3))
    return Scattering(in_scatter, transmittance, surface * transmittance + in_scatter)


def single_scattering(cam, dirs, sun_dir, params: AtmosphereParams, max_dist=None,
                      surface_colour=None, steps: int = 30, inner_steps: int | None = None,
                      lut: OpticalDepthLut | None = None,
                      visibility: Callable[[np.ndarray], np.ndarray] | None = None,
                      pc_rule: str = "midpoint", clip_ground: bool = True) -> Scattering:
    """The thesis's midpoint Riemann sums (§1.7, §2.3) with the errata fixed — the numpy twin of
    the GPU methods 1–3.

    ``cam`` (3,) or (N, 3) and ``dirs`` (N, 3) planet-centred; ``sun_dir`` (3,) toward the sun;
    ``max_dist`` the distance to the visible surface per ray (None: sky, the segment ends at the
    top of the atmosphere or the ground); ``surface_colour`` its colour L0 (RGB, per ray or one).
    The view segment is clipped to the atmosphere (§2.4 item 2) and split into ``steps`` equal
    steps sampled at their midpoints (s = 0.5 … N − 0.5). At each sample P:

    * density ρ_x = P0 exp(−h/H_x);
    * τ(AP) toward the sun — ``lut`` given: the LUT lookup (second approximation, §2.4);
      otherwise a nested midpoint sum of ``inner_steps`` steps (default ``steps``, as the
      thesis's code; first approximation, §2.3); a sun ray that hits the planet → no light;
    * τ(PC) accumulated along the outer loop (``pc_rule``, see the module notes);
    * V(P) = ``visibility(P)`` for points (N, 3) → (N,) in [0, 1] (final approximation, §2.5).

    Returns :class:`Scattering` (in_scatter, transmittance, radiance), each (N, 3).
    """
    ozone = params.ozone > 0.0
    if lut is not None:
        def sun_depth(h, cos_phi):
            d = lut.optical_depth_to_sun(h, cos_phi, params.p0)
            return d if ozone else d[..., :2]
    else:
        inner = steps if inner_steps is None else int(inner_steps)

        def sun_depth(h, cos_phi):
            d = params.p0 * np.stack(optical_depth_midpoint(h, cos_phi, params, inner), axis=-1)
            if ozone:
                d = np.concatenate([d, ozone_optical_depth_midpoint(h, cos_phi, params, inner)
                                    [..., None]], axis=-1)
            return d
    return _integrate(cam, dirs, sun_dir, params, max_dist, surface_colour, steps, sun_depth,
                      visibility, pc_rule, clip_ground)


def reference(cam, dirs, sun_dir, params: AtmosphereParams, max_dist=None, surface_colour=None,
              steps: int = 4096, nodes: int = 16,
              visibility: Callable[[np.ndarray], np.ndarray] | None = None,
              clip_ground: bool = True) -> Scattering:
    """The accuracy reference of ``natura bench planet``: the single-scattering integral (§1.5)
    in float64 with ``steps`` (4096) midpoint samples on the view segment, τ(PC) by the
    second-order midpoint rule, and τ(AP) **exact** at every sample (Gauss–Legendre on the
    perigee form, ``nodes`` per piece: 16 → ~1e-8 relative). Same arguments and result as
    :func:`single_scattering`. Cost ~ rays × steps × 4·nodes exponentials: about 1 s per 100
    rays at the defaults — use a few thousand rays (a subsampled image), not a full frame.
    """
    def sun_depth(h, cos_phi):
        d = params.p0 * _density_integrals(h, cos_phi, params, nodes)
        if params.ozone > 0.0:
            d = np.concatenate([d, ozone_optical_depth(h, cos_phi, params)[..., None]], axis=-1)
        return d

    return _integrate(cam, dirs, sun_dir, params, max_dist, surface_colour, steps, sun_depth,
                      visibility, "midpoint", clip_ground)


def convergence(cam, dirs, sun_dir, params: AtmosphereParams, ns=(10, 20, 30), n_ref: int = 1024,
                max_dist=None, lut: OpticalDepthLut | None = None,
                pc_rule: str = "midpoint") -> dict:
    """Criterion 8: error of the thesis's midpoint sum at N steps (outer and inner, as §2.3)
    against the same sum at ``n_ref`` steps, per N: the largest relative error over the rays and
    RGB channels of the in-scattered radiance. Returns {N: error}."""
    ref = single_scattering(cam, dirs, sun_dir, params, max_dist=max_dist, steps=n_ref, lut=lut,
                            pc_rule=pc_rule).in_scatter
    scale = np.maximum(np.abs(ref), 1e-300)
    out = {}
    for n in ns:
        got = single_scattering(cam, dirs, sun_dir, params, max_dist=max_dist, steps=n, lut=lut,
                                pc_rule=pc_rule).in_scatter
        out[int(n)] = float(np.max(np.abs(got - ref) / scale))
    return out


#
# The thesis lights surfaces with the sun and a constant ambient k_a × texture colour (§3.3).
# The sky's own light on a surface of normal n is the irradiance E(n) = ∫ L_sky(ω) max(n·ω, 0) dω
# over the sphere of directions ω. The sky here is the scene's single-scattering integral seen
# from 2 m above the scene's origin (the city and the mountains lie within a few tens of km of it,
# under the same sky); below the horizon, the air between the eye and the dark ground (no ground
# reflection: the thesis has none). E(n) is smooth in n, so a small table over the normal's
# directions, filtered bilinearly, holds it: IRRADIANCE_SIZE texels of (azimuth, polar angle),
# each the quadrature of the sky's radiance on a sphere_grid. The surfaces' direct term is
# albedo · k_d · (n·l) · T_sun for a sun of unit strength, so the table holds E(n) / lightSun and
# the sky's term is albedo · k_d · E(n) / lightSun.

#: (width = azimuth, height = polar angle) of the irradiance table
IRRADIANCE_SIZE = (32, 17)


def sphere_grid(n_theta: int):
    """Midpoint grid over the sphere: (directions (N, 3), solid angles (N,)) with n_theta rows
    of polar angle (from +y) and 2·n_theta columns of azimuth (0 = −z, 90° = +x, as
    :func:`direction`); the solid angles sum to 4π exactly (each row's band split evenly)."""
    edges = np.linspace(0.0, math.pi, n_theta + 1)
    theta = 0.5 * (edges[:-1] + edges[1:])
    band = 2.0 * math.pi * (np.cos(edges[:-1]) - np.cos(edges[1:]))
    n_phi = 2 * n_theta
    phi = (np.arange(n_phi) + 0.5) * (2.0 * math.pi / n_phi)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    dirs = np.stack([np.sin(t) * np.sin(p), np.cos(t), -np.sin(t) * np.cos(p)], axis=-1)
    weights = np.repeat(band / n_phi, n_phi)
    return dirs.reshape(-1, 3), weights


def irradiance_normals(size=IRRADIANCE_SIZE) -> np.ndarray:
    """The table's texel-centre normals, (height, width, 3): row i at polar angle
    i·π/(height − 1) from +y (the first and last rows are the poles), column j at azimuth
    (j + ½)·2π/width."""
    w, h = size
    theta = np.arange(h) * (math.pi / (h - 1))
    phi = (np.arange(w) + 0.5) * (2.0 * math.pi / w)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    return np.stack([np.sin(t) * np.sin(p), np.cos(t), -np.sin(t) * np.cos(p)], axis=-1)


def sky_radiance(dirs, sun_dir, params: AtmosphereParams, steps: int = 30,
                 lut: OpticalDepthLut | None = None, height: float = 2.0) -> np.ndarray:
    """The single-scattering sky (in-scattered radiance, (N, 3)) seen from ``height`` above the
    scene's origin, by the methods' midpoint sum (the LUT when given)."""
    cam = local_to_planet((0.0, height, 0.0), params)
    return single_scattering(cam, dirs, sun_dir, params, steps=steps, lut=lut).in_scatter


def irradiance_from_radiance(normals, dirs, weights, radiance, sun_intensity: float):
    """E(n) / lightSun = Σ L(ω) max(n·ω, 0) dω / lightSun for normals (..., 3)."""
    normals = np.asarray(normals, dtype=np.float64)
    cosines = np.maximum(normals.reshape(-1, 3) @ dirs.T, 0.0) * weights       # (M, N)
    scale = sun_intensity if sun_intensity > 0.0 else 1.0
    return (cosines @ radiance / scale).reshape(normals.shape[:-1] + (3,))


def sky_irradiance_table(sun_dir, params: AtmosphereParams, n_theta: int = 48, steps: int = 30,
                         lut: OpticalDepthLut | None = None, size=IRRADIANCE_SIZE) -> np.ndarray:
    """The irradiance table, float32 (height, width, 3): E(n) / lightSun at
    :func:`irradiance_normals`, from the sky's radiance on an ``n_theta`` × 2·``n_theta``
    :func:`sphere_grid` (``steps`` samples per ray, the LUT when given). Upload as an RGB32F
    texture (width, height), LINEAR, repeating in u only; GLSL ``SkyIrradiance`` reads it."""
    dirs, w = sphere_grid(n_theta)
    L = sky_radiance(dirs, sun_dir, params, steps, lut)
    return irradiance_from_radiance(irradiance_normals(size), dirs, w, L,
                                    params.sun_intensity).astype(np.float32)


def irradiance_uv(normals, size=IRRADIANCE_SIZE) -> np.ndarray:
    """(u, v) of normals in the table (twin of ``SkyIrradianceUv``): u = azimuth / 2π,
    v on the texel centres of the rows, (½ + (polar angle / π)·(height − 1)) / height."""
    n = np.asarray(normals, dtype=np.float64)
    h = size[1]
    phi = np.mod(np.arctan2(n[..., 0], -n[..., 2]), 2.0 * math.pi)
    theta = np.arccos(np.clip(n[..., 1], -1.0, 1.0))
    return np.stack([phi / (2.0 * math.pi), (0.5 + theta / math.pi * (h - 1)) / h], axis=-1)


def sample_irradiance(table, normals) -> np.ndarray:
    """GL LINEAR lookup of the table at normals (u repeats, v clamps). Returns (..., 3)."""
    tab = np.asarray(table, dtype=np.float64)
    h, w = tab.shape[:2]
    uv = irradiance_uv(normals, (w, h))
    x = uv[..., 0] * w - 0.5
    y = np.clip(uv[..., 1] * h - 0.5, 0.0, h - 1.0)
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    i0 = np.mod(x0.astype(np.int64), w)
    i1 = np.mod(x0.astype(np.int64) + 1, w)
    j0 = y0.astype(np.int64)
    j1 = np.minimum(j0 + 1, h - 1)
    row0 = tab[j0, i0] * (1.0 - fx) + tab[j0, i1] * fx
    row1 = tab[j1, i0] * (1.0 - fx) + tab[j1, i1] * fx
    return row0 * (1.0 - fy) + row1 * fy
