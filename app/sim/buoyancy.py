"""Buoyancy of a floating boat: three methods and the water surfaces they are tested on (numpy).

Water surfaces (:class:`app.frame.WaterSurface`: ``water(x, z)`` → an
``app.sim.ocean.WaterQuery`` with ``height``, ``displacement`` and ``normal``; ``time`` and
``query_time``; and ``at(t)``, the same surface at time t — the methods call it when there is one,
so substeps see the sea move): :class:`FlatWater`, :class:`PlaneWater` (a tilted plane),
:class:`SineSea` / :class:`SineWater` (sums of deep-water sines, exact heights) and
:class:`DelayedWater`, the GPU readback lag (spec/000 §1.3: ``AsyncGPUReadback`` answers describe
the sea a few frames ago, held for a frame).

Methods (all vectorised over probes and triangles):

1. :class:`ProbeFloat` — the thesis's ``FloatingObject`` (spec/000 §1.3), **kinematic**:
   ``update(body, water, dt)`` sets the pose itself (no forces): the averaged normal of the
   displaced surface over the floating points (N = (P(p+ẑδ) − P(p)) × (P(p+x̂δ) − P(p)),
   normalised, upward — the digest's fix of the garbled printed formula) and the averaged
   displacement, approached at the Displacement and Rotation Stiffness rates.
2. :class:`ProbeForces` — force-based probes in the manner of Crest's ``BoatProbes``: a spring
   per probe on its submersion, weights summing to the displaced mass, plus drag.
3. :class:`HydrostaticBuoyancy` — Kerner's pressure integration over the hull's triangles
   (J. Kerner, "Water interaction model for boats in video games", Gamasutra, Kerner 2015 and
   its part 2, Kerner 2016): the triangles cut at the waterline, F = −ρ·g·h·A·n per piece, plus
   damping, ITTC-1957 skin friction and pressure drag.

The force methods share ``forces(body, water, t)`` → (F (3,), τ about the centre of mass (3,)),
world frame, for :meth:`app.sim.rigid_body.RigidBody.step` (gravity is the body's).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import RESOURCES
from ..errors import ParamError
from .hull import (
    RHO_SEA,
    HullMesh,
    clip_below_indexed,
    draft_for_mass,
    hull_fingerprint,
    solid_inertia,
    submerged_below_plane,
    waterline_half_beam,
)
from .ocean import WaterQuery, floating_points_pose
from .rigid_body import (
    G,
    Hydrodynamics,
    RigidBody,
    quat_between,
    quat_from_axis_angle,
    quat_multiply,
    quat_slerp,
)
from .vec import cross, length, norm

NU_SEA = 1.19e-6  # kinematic viscosity of sea water at 15 °C [m²/s] (ITTC)


def water_at(water: Any, t: float | None) -> Any:
    """The surface at time t when it can say (``at``), else as it is."""
    if t is None or not hasattr(water, "at"):
        return water
    return water.at(t)


class _Analytic:
    """A surface given by a height field η(x, z, t) without horizontal displacement."""

    time: float = 0.0

    @property
    def query_time(self) -> float:
        return self.time

    def at(self, t: float):
        other = object.__new__(type(self))
        other.__dict__ = dict(self.__dict__)
        other.time = float(t)
        return other

    def _eta(self, x, z):  # (height, dη/dx, dη/dz)
        raise NotImplementedError

    def height(self, x, z) -> np.ndarray:
        return self._eta(np.asarray(x, float), np.asarray(z, float))[0]

    def displacement(self, x, z) -> np.ndarray:
        h = self.height(x, z)
        return np.stack([np.zeros_like(h), h, np.zeros_like(h)], -1)

    def normal(self, x, z) -> np.ndarray:
        return self.water(x, z).normal

    def water(self, x, z, iterations: int | None = None) -> WaterQuery:
        x = np.asarray(x, float)
        z = np.asarray(z, float)
        h, hx, hz = self._eta(x, z)
        shape = np.broadcast(x, z).shape
        h = np.broadcast_to(h, shape)
        # (−∂η/∂x, 1, −∂η/∂z) and (0, η, 0) filled in by component (np.stack of broadcast
        # arrays costs more than the maths)
        n = np.empty(shape + (3,))
        n[..., 0] = -hx
        n[..., 1] = 1.0
        n[..., 2] = -hz
        n = n / norm(n, keepdims=True)
        d = np.zeros(shape + (3,))
        d[..., 1] = h
        return WaterQuery(h, d, n, x, z, [np.zeros(shape)])


class FlatWater(_Analytic):
    """Still water at y = ``level``."""

    def __init__(self, level: float = 0.0, time: float = 0.0):
        self.level = float(level)
        self.time = float(time)

    def _eta(self, x, z):
        h = np.full(np.broadcast(x, z).shape, self.level)
        return h, 0.0, 0.0


class PlaneWater(_Analytic):
    """A still, tilted plane through (0, level, 0) with unit ``normal`` (upward)."""

    def __init__(self, normal=(0.0, 1.0, 0.0), level: float = 0.0, time: float = 0.0):
        n = np.asarray(normal, float)
        if not n[1] > 0:
            raise ParamError(f"PlaneWater normal: {tuple(n)} is not allowed: allowed n.y > 0")
        self.plane_normal = n / np.linalg.norm(n)
        self.level = float(level)
        self.time = float(time)

    @classmethod
    def tilted(cls, slope_x: float = 0.0, slope_z: float = 0.0, level: float = 0.0):
        """The plane y = level + slope_x·x + slope_z·z."""
        return cls((-slope_x, 1.0, -slope_z), level)

    def _eta(self, x, z):
        n = self.plane_normal
        sx, sz = -n[0] / n[1], -n[2] / n[1]
        return self.level + sx * x + sz * z, sx, sz


class SineSea(_Analytic):
    """A sum of deep-water sines η = Σ Aᵢ·sin(kᵢ·(dᵢ·(x, z)) − ωᵢ·t + φᵢ), ω² = g·k (exact
    heights and normals; no horizontal displacement)."""

    def __init__(self, amplitudes, wavelengths, directions, phases=None, time: float = 0.0,
                 level: float = 0.0):
        self.amplitude = np.atleast_1d(np.asarray(amplitudes, float))
        self.wavelength = np.atleast_1d(np.asarray(wavelengths, float))
        self.direction = np.broadcast_to(np.atleast_1d(np.asarray(directions, float)),
                                         self.amplitude.shape).copy()  # radians from +x
        self.phase = (np.zeros_like(self.amplitude) if phases is None
                      else np.broadcast_to(np.asarray(phases, float), self.amplitude.shape).copy())
        if np.any(self.wavelength <= 0) or np.any(self.amplitude < 0):
            raise ParamError("SineSea: wavelengths must be > 0 and amplitudes >= 0")
        self.k = 2.0 * np.pi / self.wavelength
        self.omega = np.sqrt(G * self.k)
        self.kx = self.k * np.cos(self.direction)
        self.kz = self.k * np.sin(self.direction)
        self.level = float(level)
        self.time = float(time)

    @property
    def significant_height(self) -> float:
        """Hs = 4·sqrt(Σ Aᵢ²/2) [m]."""
        return 4.0 * math.sqrt(float(np.sum(self.amplitude ** 2)) / 2.0)

    # The waves are the first axis, (n, ...): the long axis of the points innermost makes each
    # product and the sum over the waves one fast pass (the same products and, below 8 waves,
    # the same additions in the same order as with the waves last).

    def _phase(self, x, z) -> np.ndarray:
        """The sines' arguments kᵢ·(dᵢ·(x, z)) − ωᵢ·t + φᵢ, (n, ...) for points (...)."""
        x = np.asarray(x, float)
        z = np.asarray(z, float)
        nd = max(x.ndim, z.ndim)
        return (_per_wave(self.kx, nd) * x + _per_wave(self.kz, nd) * z
                - _per_wave(self.omega * self.time, nd) + _per_wave(self.phase, nd))

    def _eta(self, x, z):
        f = self._phase(x, z)
        c = np.cos(f)
        nd = f.ndim - 1
        a = self.amplitude
        return (self.level + (_per_wave(a, nd) * np.sin(f)).sum(0),
                (_per_wave(a * self.kx, nd) * c).sum(0), (_per_wave(a * self.kz, nd) * c).sum(0))

    def height(self, x, z) -> np.ndarray:
        # η alone, as _eta has it: without the slopes (their cosines), half the work
        f = self._phase(x, z)
        return self.level + (_per_wave(self.amplitude, f.ndim - 1) * np.sin(f)).sum(0)


def _per_wave(values: np.ndarray, ndim: int) -> np.ndarray:
    """Per-wave values (n,) as a column (n, 1, …) against points of ``ndim`` axes."""
    return values.reshape((-1,) + (1,) * ndim)


class SineWater(SineSea):
    """One sine wave of ``amplitude`` [m] and ``wavelength`` [m] travelling along
    ``direction`` [rad from +x]."""

    def __init__(self, amplitude: float = 1.0, wavelength: float = 60.0, direction: float = 0.0,
                 time: float = 0.0, phase: float = 0.0):
        super().__init__([amplitude], [wavelength], [direction], [phase], time)


def storm_sea(hs: float = 6.0, time: float = 0.0) -> SineSea:
    """A 25 m/s wind sea as four sines (wavelengths 160, 110, 75 and 50 m, spread ±35° about
    +x, steepness k·A ≤ 0.07) scaled to significant height ``hs`` [m]."""
    wl = np.array([160.0, 110.0, 75.0, 50.0])
    a = 0.1 * wl / (2.0 * np.pi) * np.array([1.0, 1.0, 0.85, 0.75])
    a *= hs / (4.0 * math.sqrt(float(np.sum(a * a)) / 2.0))
    return SineSea(a, wl, np.radians([0.0, 25.0, -35.0, 10.0]), [0.0, 1.3, 2.9, 4.4], time)


class DelayedWater:
    """``source`` as a GPU readback sees it: answers describe the sea ``lag_frames`` frames
    earlier, held for a whole frame of ``frame_dt`` (the readback lands once per frame), so
    ``query_time`` = (⌊t/frame_dt⌋ − lag)·frame_dt.  The source must have ``at(t)``."""

    def __init__(self, source: Any, lag_frames: int = 1, frame_dt: float = 1.0 / 60.0,
                 time: float = 0.0, hold: bool = True):
        if not (isinstance(lag_frames, int) and 0 <= lag_frames <= 16):
            raise ParamError(f"lag_frames: {lag_frames!r} is not allowed: allowed 0…16")
        if not hasattr(source, "at"):
            raise ParamError("DelayedWater: the source has no at(t): allowed an analytic surface")
        self.source = source
        self.lag_frames = lag_frames
        self.frame_dt = float(frame_dt)
        self.hold = hold
        self.time = float(time)

    @property
    def query_time(self) -> float:
        frame = math.floor(self.time / self.frame_dt + 1e-9) if self.hold \
            else self.time / self.frame_dt
        return (frame - self.lag_frames) * self.frame_dt

    def at(self, t: float) -> "DelayedWater":
        return DelayedWater(self.source, self.lag_frames, self.frame_dt, t, self.hold)

    def _now(self):
        return self.source.at(self.query_time)

    def height(self, x, z):
        return self._now().height(x, z)

    def displacement(self, x, z):
        return self._now().displacement(x, z)

    def normal(self, x, z):
        return self._now().normal(x, z)

    def water(self, x, z, iterations: int | None = None):
        return self._now().water(x, z, iterations)



def boat_body(mesh: HullMesh, mass: float, com_height: float | None = None,
              rho: float = RHO_SEA, inertia_scale: float = 1.0, hydrodynamics: bool = False,
              **kwargs) -> RigidBody:
    """A rigid body for the hull: the centre of mass on the centreline at ``com_height`` above
    the keel (default 0.35 × depth: ballast low) and straight above the centre of buoyancy of
    the upright hull at its draft for ``mass`` (so that pose is the equilibrium); inertia of the
    hull as a uniform solid of that mass about it (× ``inertia_scale``); placed at that draft
    (origin at y = −draft), at rest.  ``hydrodynamics``: with the hull's added mass and
    radiation damping (:func:`hull_hydrodynamics`).  ``kwargs`` go to :class:`RigidBody`."""
    if hydrodynamics:
        kwargs.setdefault("hydrodynamics", hull_hydrodynamics(mesh, mass))
    draft = draft_for_mass(mesh, mass, rho)
    b = mesh.submerged(draft)
    depth = float(mesh.vertices[:, 1].max())
    if com_height is None:
        com_height = 0.35 * (mesh.params.depth if mesh.params else depth)
    com = np.array([0.0, com_height, b.centre[2]])
    inertia = solid_inertia(mesh, mass, about=com) * inertia_scale
    kwargs.setdefault("position", (0.0, -draft, 0.0))
    return RigidBody(mass, inertia, com=com, **kwargs)


# ---- Added mass and radiation damping (docs/theory/000-maritime.md#added-mass) --------------

#: the committed coefficients, written by ``tools/added_mass.py`` (capytaine)
HYDRODYNAMICS_FILE = RESOURCES / "boat" / "hydrodynamics.json"


def hydrodynamics_table(path: str | Path = HYDRODYNAMICS_FILE) -> dict:
    """The committed table (see tools/added_mass.py): per tabulated mass the frequency-dependent
    coefficients, the coupled reference modes and the constant matrices the runtime applies."""
    try:
        return json.loads(Path(path).read_text())
    except (OSError, ValueError) as e:
        raise ParamError(f"boat hydrodynamics: {path} cannot be read ({e}): allowed the file "
                         "tools/added_mass.py writes") from None


def _row_for(mesh: HullMesh, mass: float, path) -> tuple[dict, dict, float]:
    """The two table rows around ``mass`` and the weight of the upper (clamped at the ends)."""
    table = hydrodynamics_table(str(path))
    if table["hull_fingerprint"] != hull_fingerprint(mesh):
        raise ParamError("boat hydrodynamics: resources/boat/hydrodynamics.json is for another "
                         "hull: allowed the default hull (regenerate with tools/added_mass.py "
                         "after changing app/sim/hull.py)")
    rows = table["masses"]
    masses = [r["mass"] for r in rows]
    k = int(np.clip(np.searchsorted(masses, mass), 1, len(rows) - 1))
    lo, hi = rows[k - 1], rows[k]
    w = float(np.clip((mass - lo["mass"]) / (hi["mass"] - lo["mass"]), 0.0, 1.0))
    return lo, hi, w


def hull_hydrodynamics(mesh: HullMesh, mass: float, path: str | Path = HYDRODYNAMICS_FILE
                       ) -> Hydrodynamics:
    """The frequency-independent added mass and radiation damping of the hull floating
    ``mass`` (heave, pitch, their coupling, roll; 6×6, body axes, about the centre of mass):
    the committed coefficients per unit mass, interpolated linearly between the tabulated
    masses (held at the ends).  Only for the mesh they were computed for (its fingerprint)."""
    lo, hi, w = _row_for(mesh, mass, path)
    out = []
    for key in ("added_mass", "damping"):
        a = np.asarray(lo["constant"][key]) / lo["mass"]
        b = np.asarray(hi["constant"][key]) / hi["mass"]
        out.append(mass * ((1.0 - w) * a + w * b))
    return Hydrodynamics(out[0], out[1], source="capytaine BEM, resources/boat/hydrodynamics.json")


def reference_modes(mesh: HullMesh, mass: float, path: str | Path = HYDRODYNAMICS_FILE) -> dict:
    """The BEM reference: the coupled heave–pitch modes and the roll mode with the
    frequency-dependent added mass and damping, each at its own frequency (tools/added_mass.py),
    {"heave" | "pitch" | "roll": {"period" [s], "zeta"}} interpolated between tabulated masses."""
    lo, hi, w = _row_for(mesh, mass, path)
    return {k: {q: (1.0 - w) * lo["reference"][k][q] + w * hi["reference"][k][q]
                for q in ("period", "zeta")} for k in ("heave", "pitch", "roll")}


def probe_layout(mesh: HullMesh, n: int, draft: float) -> tuple[np.ndarray, np.ndarray]:
    """``n`` probe points (boat frame, on the waterline plane y = draft) spread over the
    waterplane — n_z rows along × n_x across (4 → 2×2, 8 → 4×2, 16 → 8×2, 32 → 8×4; others
    n×1 or n/2×2) — and the waterplane area each stands for.  Across, each probe sits at the
    radius of gyration of its strip, so the springs' roll stiffness matches the waterplane's."""
    if n < 1:
        raise ParamError(f"boat.probes: {n!r} is not allowed: allowed at least 1")
    shape = {1: (1, 1), 2: (2, 1), 4: (2, 2), 8: (4, 2), 16: (8, 2), 32: (8, 4)}
    nz, nx = shape.get(n, (n // 2, 2) if n % 2 == 0 else (n, 1))
    zs = np.linspace(mesh.vertices[:, 2].min(), mesh.vertices[:, 2].max(), 801)
    half = waterline_half_beam(mesh, draft, zs)
    wet = zs[half > 0]
    z_lo, z_hi = float(wet.min()), float(wet.max())
    edges = np.linspace(z_lo, z_hi, nz + 1)
    zc = 0.5 * (edges[:-1] + edges[1:])
    pts, areas = [], []
    for i in range(nz):  # nz ≤ 32 rows: set-up only
        m = (zs >= edges[i]) & (zs <= edges[i + 1])
        if m.sum() > 1:
            b = float(np.mean(half[m]))
            strip = float(np.sum(0.5 * (half[m][1:] + half[m][:-1]) * np.diff(zs[m])))
        else:
            b = float(waterline_half_beam(mesh, draft, zc[i])[0])
            strip = b * (edges[1] - edges[0])
        if nx == 1:
            cols, fr = [0.0], [1.0]
        else:
            k = nx // 2
            bounds = np.linspace(0.0, 1.0, k + 1)
            r = np.sqrt((bounds[:-1] ** 2 + bounds[:-1] * bounds[1:] + bounds[1:] ** 2) / 3.0)
            cols = list(np.concatenate([r, -r]) * b)
            fr = [1.0 / nx] * nx
        for x, f in zip(cols, fr):
            pts.append((x, draft, zc[i]))
            areas.append(2.0 * strip * f)
    return np.array(pts, float), np.array(areas, float)



@dataclass
class ProbeFloat:
    """spec/000 §1.3 ``FloatingObject``, kinematic.  Parameters as in the thesis's inspector:

    * ``simulate_flotation`` — Simulate Flotation: off, ``update`` does nothing;
    * ``floating_points`` — Floating Points (n, 3), boat frame; place them on the waterline:
      the pose puts their mean height on the mean water height;
    * ``displacement_stiffness`` — Displacement Stiffness [1/s]: the rate at which the position
      follows the averaged displacement (height and the x/z sway);
    * ``rotation_stiffness`` — Rotation Stiffness [1/s]: the rate at which the orientation
      follows the averaged normal (the heading is kept);
    * ``probe_distance`` — δ [m], the step to the two extra surface points per floating point
      (the thesis: one unit).

    The thesis's stiffnesses are per-frame lerp factors; here they are rates, applied as the
    factor 1 − exp(−k·dt) so the response does not depend on the frame rate (k·dt ≪ 1: k·dt).
    ``update(body, water, dt)`` sets ``body``'s position and orientation (and its velocity to
    the change over dt, its angular velocity to zero); it applies no forces.
    """

    floating_points: np.ndarray
    simulate_flotation: bool = True
    displacement_stiffness: float = 6.0
    rotation_stiffness: float = 3.0
    probe_distance: float = 1.0
    _sway: np.ndarray = field(default_factory=lambda: np.zeros(2), repr=False)

    def __post_init__(self):
        self.floating_points = np.atleast_2d(np.asarray(self.floating_points, float))
        for name in ("displacement_stiffness", "rotation_stiffness", "probe_distance"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0) or (name == "probe_distance" and v == 0):
                raise ParamError(f"boat.{name}: {v!r} is not allowed: allowed a finite number "
                                 f"{'> 0' if name == 'probe_distance' else '>= 0'}")

    def target(self, body: RigidBody, water: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(averaged normal, averaged displacement, target orientation) at the current pose."""
        p = body.to_world(self.floating_points)
        normal, disp = floating_points_pose(water.water, p[:, 0], p[:, 2], self.probe_distance,
                                            getattr(water, "height", None))
        fwd = body.rotation[:, 2]
        yaw = math.atan2(fwd[0], fwd[2]) if math.hypot(fwd[0], fwd[2]) > 1e-9 else 0.0
        q = quat_multiply(quat_between((0.0, 1.0, 0.0), normal),
                          quat_from_axis_angle((0.0, 1.0, 0.0), yaw))
        return normal, disp, q

    def update(self, body: RigidBody, water: Any, dt: float) -> dict:
        """Move ``body`` toward the pose the water gives; returns the normal and displacement."""
        if not self.simulate_flotation or dt <= 0:
            return {}
        before = body.position
        normal, disp, q = self.target(body, water)
        a_d = 1.0 - math.exp(-self.displacement_stiffness * dt)
        a_r = 1.0 - math.exp(-self.rotation_stiffness * dt)
        body.set_orientation(quat_slerp(body.orientation, q, a_r), keep="origin")
        # height: the floating points' mean on the mean water height
        p = body.to_world(self.floating_points)
        pos = body.position.copy()
        pos[1] += a_d * (disp[1] - float(p[:, 1].mean()))
        # x/z: the applied sway follows the averaged horizontal displacement; motion from
        # elsewhere (navigation) is kept
        sway = self._sway + a_d * (disp[[0, 2]] - self._sway)
        pos[[0, 2]] += sway - self._sway
        self._sway = sway
        body.position = pos
        body.velocity = (body.position - before) / dt
        body.momentum = np.zeros(3)
        return {"normal": normal, "displacement": disp}



@dataclass
class ProbeForces:
    """Force-based probes (after Crest's ``BoatProbes``): probe i at ``points[i]`` (boat frame)
    pushes up with F = wᵢ·g·sᵢ/s₀ at its world position, sᵢ = clamp(η(pᵢ) − yᵢ + s₀, 0, s_max)
    its submersion below the water surface plus the design submersion s₀ = V/A_w (the depth of
    the box of the waterplane's area displacing V), Σwᵢ = the displaced mass.  The heave
    stiffness Σwᵢ·g/s₀ is then ρ·g·A_w, the hydrostatic one.  Each submerged probe adds drag
    −wᵢ·(c_up·v_y, c_h·v_h) on its velocity.  ``weights`` [kg] (n,)."""

    points: np.ndarray
    weights: np.ndarray
    design_submersion: float
    max_submersion: float
    drag_up: float = 2.0  # [1/s]
    drag_horizontal: float = 0.5  # [1/s]
    g: float = G
    last: dict = field(default_factory=dict, repr=False)

    @classmethod
    def for_hull(cls, mesh: HullMesh, mass: float, n: int = 8, rho: float = RHO_SEA,
                 centre_z: float | None = None, **kwargs) -> "ProbeForces":
        """``n`` probes on the waterplane of ``mesh`` floating ``mass`` (:func:`probe_layout`),
        weights ∝ the waterplane area each stands for, tilted linearly along the length so
        their centre lies at ``centre_z`` (default the centre of buoyancy: the same trim as the
        hydrostatic method)."""
        draft = draft_for_mass(mesh, mass, rho)
        sub = mesh.submerged(draft)
        pts, areas = probe_layout(mesh, n, draft)
        w = areas / areas.sum()
        zc = sub.centre[2] if centre_z is None else centre_z
        dz = pts[:, 2] - w @ pts[:, 2]
        var = float(w @ dz ** 2)
        if var > 0:
            alpha = (zc - w @ pts[:, 2]) / var
            lim = 0.9 / max(float(np.abs(dz).max()), 1e-9)
            w = w * (1.0 + np.clip(alpha, -lim, lim) * dz)
            w = w / w.sum()
        s0 = sub.volume / sub.waterplane_area
        smax = s0 * mesh.volume() / sub.volume
        return cls(pts, w * mass, s0, smax, **kwargs)

    def forces(self, body: RigidBody, water: Any, t: float | None = None):
        w = water_at(water, t)
        p = body.to_world(self.points)
        eta = _heights(w, p[:, 0], p[:, 2])
        # np.clip(·, 0, s_max) as the two ufuncs it is (np.clip's argument handling costs more)
        s = np.minimum(np.maximum(eta - p[:, 1] + self.design_submersion, 0.0),
                       self.max_submersion)
        wet = s > 0
        f = np.zeros_like(p)
        f[:, 1] = self.weights * self.g * s / self.design_submersion
        v = body.point_velocity(p)
        drag = -self.weights[:, None] * v * np.array(
            [self.drag_horizontal, self.drag_up, self.drag_horizontal]) * wet[:, None]
        f = f + _limit_drag(drag, v, self.weights, body)
        r = p - body.com_world
        self.last = {"submersion": s, "wet": int(wet.sum())}
        return np.add.reduce(f, 0), np.add.reduce(cross(r, f), 0)  # what .sum(0) calls


def _heights(water: Any, x, z) -> np.ndarray:
    """Water heights at world points: ``height()`` where the surface has it (no normals: half
    the work of ``water()`` on the FFT ocean), else ``water().height``."""
    if hasattr(water, "height"):
        return np.asarray(water.height(x, z), float)
    return np.asarray(water.water(x, z).height, float)


def _limit_drag(drag: np.ndarray, v: np.ndarray, w: np.ndarray, body: RigidBody) -> np.ndarray:
    """Scale drag so that, over the longest substep, it cannot reverse a probe's velocity
    (explicit drag is unstable past c·h = 2)."""
    h = body.max_substep
    rate = norm(drag) * h / np.maximum(w * norm(v), 1e-300)
    return drag * np.minimum(1.0, 1.0 / np.maximum(rate, 1e-300))[:, None]


# ---- 3. Kerner's hydrostatic pressure integration -------------------------------------------


@dataclass
class HydrostaticBuoyancy:
    """Kerner 2015: the hull's vertices get their depth below the water hᵢ = η(xᵢ, zᵢ) − yᵢ;
    every triangle is cut at h = 0 (:func:`app.sim.hull.clip_below`: 0, 1, 2 or 3 corners
    under) and each submerged piece of area A, outward normal n and centroid depth h_c takes
    F = −ρ·g·h_c·A·n.  The torque uses each piece's centre of pressure (exact for a pressure
    linear over the piece: the edge-midpoint rule), not Kerner's centroid, so in flat water the
    force is exactly ρ·g·V up through the exact centre of buoyancy.

    Damping (Kerner 2016, each scaled by the submerged area fraction r, optional):
    F = −c_lin·m·r·v, τ = −c_ang·r·L.  Drag on each submerged piece, from its velocity v
    (still water; the orbital velocity of the waves is not modelled):

    * viscous (skin friction): −½·ρ·C_f·A·|v_t|·v_t on the tangential velocity, with the
      ITTC-1957 line C_f = 0.075/(log₁₀Rn − 2)², Rn = |V|·L/ν (clamped to ≥ 10⁵);
    * pressure drag for faces moving into the water (cos θ = n·v̂ > 0):
      −(C_PD1·u + C_PD2·u²)·A·cos^f_P θ·n, and suction for faces moving away:
      +(C_SD1·u + C_SD2·u²)·A·|cos θ|^f_S·n, u = |v|/v_ref.

    The drag is scaled down where, over the body's longest substep, it would reverse the
    velocity.  ``last`` holds the diagnostics of the latest call: submerged area, its fraction,
    the displaced-volume estimate F_y/(ρ·g), pieces."""

    mesh: HullMesh
    rho: float = RHO_SEA
    g: float = G
    linear_damping: float = 0.0  # c_lin [1/s]
    angular_damping: float = 0.0  # c_ang [1/s]
    viscous: bool = True
    pressure_drag: bool = True
    c_pd1: float = 400.0  # [Pa]
    c_pd2: float = 200.0
    f_p: float = 0.5
    c_sd1: float = 400.0
    c_sd2: float = 200.0
    f_s: float = 0.5
    v_ref: float = 1.0  # [m/s]
    nu: float = NU_SEA
    last: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        self._total_area = self.mesh.area()
        self._length = float(np.ptp(self.mesh.vertices[:, 2]))

    @classmethod
    def undamped(cls, mesh: HullMesh, **kwargs) -> "HydrostaticBuoyancy":
        """Pressure only: no damping, no drag."""
        return cls(mesh, viscous=False, pressure_drag=False, **kwargs)

    def pieces(self, body: RigidBody, water: Any, t: float | None = None):
        """The submerged pieces in world space: (corners (M, 3, 3), depths (M, 3), source)."""
        corners, depths, source = self._pieces(body, water, t)
        return corners.transpose(1, 0, 2), depths.T, source

    def _pieces(self, body: RigidBody, water: Any, t: float | None):
        """:meth:`pieces` corner-major: (corners (3, M, 3), depths (3, M), source)."""
        w = water_at(water, t)
        vw = body.to_world(self.mesh.vertices)
        depth = _heights(w, vw[:, 0], vw[:, 2]) - vw[:, 1]
        return clip_below_indexed(vw, depth, self.mesh.triangles)

    def forces(self, body: RigidBody, water: Any, t: float | None = None):
        # corner-major (3, M, 3): each corner's points contiguous, so the per-corner arithmetic
        # below runs over whole arrays instead of every third row (the same operations on the
        # same numbers; every reduction keeps its operands' order)
        corners, hp, _ = self._pieces(body, water, t)
        com = body.com_world
        m = corners.shape[1]
        if m == 0:
            self.last = {"area": 0.0, "fraction": 0.0, "volume": 0.0, "pieces": 0}
            return np.zeros(3), np.zeros(3)
        p0, p1, p2 = corners[0], corners[1], corners[2]
        av = 0.5 * cross(p1 - p0, p2 - p0)
        area = norm(av)
        rg = self.rho * self.g
        # means over the three corners written out (the additions of .mean(axis=1), in order)
        force = -rg * (((hp[0] + hp[1] + hp[2]) / 3.0) @ av)
        # centre of pressure: ∫h·(x − c) dA by the edge-midpoint rule (exact for quadratics);
        # the corners' successors by an index (np.roll(·, -1, axis=1) costs more)
        mids = 0.5 * (corners + corners.take(_NEXT, axis=0)) - com
        hm = 0.5 * (hp + hp.take(_NEXT, axis=0))
        # Σₖ hₖ·midₖ: einsum("mk,kmd->md")'s sum of products from a zeroed output, in order
        # (measured bit-identical, signs of zero included), without its set-up
        prod = hm[:, :, None] * mids
        lever = (((0.0 + prod[0]) + prod[1]) + prod[2]) / 3.0
        # the per-piece torques (and the drag's forces and torques) side by side, summed over
        # the pieces in one reduction: each column's sum is the sequential one of .sum(0) over
        # its own (M, 3) (measured bit-identical), without a reduction's set-up per quantity
        per_piece = np.empty((m, 3, 3))
        cross(lever, av, out=per_piece[:, 0])
        sub_area = float(np.add.reduce(area))  # what .sum() calls
        frac = sub_area / self._total_area
        self.last = {"area": sub_area, "fraction": frac, "volume": float(force[1] / rg),
                     "pieces": m}
        if self.viscous or self.pressure_drag:
            c = (p0 + p1 + p2) / 3.0
            r = c - com
            v = body.velocity + cross(body.angular_velocity, r)
            n = av / np.maximum(area, 1e-300)[:, None]
            vn = np.einsum("md,md->m", v, n)  # normal velocity, for both drags
            f = per_piece[:, 1]
            f[...] = 0.0
            if self.viscous:
                speed = length(body.velocity)
                rn = max(speed * self._length / self.nu, 1e5)
                cf = 0.075 / (math.log10(rn) - 2.0) ** 2
                vt = v - vn[:, None] * n
                f -= (0.5 * self.rho * cf * area * norm(vt))[:, None] * vt
                self.last["cf"] = cf
            if self.pressure_drag:
                u = norm(v)
                cos = vn / np.maximum(u, 1e-300)
                uu = u / self.v_ref
                abs_cos = np.abs(cos)
                cos_p = abs_cos ** self.f_p
                cos_s = cos_p if self.f_s == self.f_p else abs_cos ** self.f_s
                push = (self.c_pd1 * uu + self.c_pd2 * uu * uu) * cos_p
                pull = (self.c_sd1 * uu + self.c_sd2 * uu * uu) * cos_s
                mag = np.where(cos > 0, -push, pull) * area
                f += mag[:, None] * n
            cross(r, f, out=per_piece[:, 2])
            lever_torque, fd, td = np.add.reduce(per_piece, 0)
        else:
            lever_torque = np.add.reduce(per_piece[:, 0], 0)
            fd = np.zeros(3)
            td = np.zeros(3)
        torque = -rg * lever_torque
        if self.linear_damping or self.angular_damping:
            fd = fd - self.linear_damping * frac * body.mass * body.velocity
            td = td - self.angular_damping * frac * body.momentum
        fd, td = _limit_body_drag(fd, td, body)
        return force + fd, torque + td


#: each corner's successor around a piece (corner k → k + 1 mod 3)
_NEXT = np.array([1, 2, 0])


def _limit_body_drag(fd: np.ndarray, td: np.ndarray, body: RigidBody):
    """Scale the summed drag so one longest substep cannot reverse the momenta (it opposes
    them): |F|·h ≤ m·|v|, |τ|·h ≤ |L| along their own directions."""
    h = body.max_substep
    p = body.mass * body.velocity
    lin = -float(fd @ p) * h
    if lin > float(p @ p) > 0:
        fd = fd * (float(p @ p) / lin)
    ang = -float(td @ body.momentum) * h
    ll = float(body.momentum @ body.momentum)
    if ang > ll > 0:
        td = td * (ll / ang)
    return fd, td



def hydrostatic_energy(mesh: HullMesh, body: RigidBody, rho: float = RHO_SEA, g: float = G,
                       level: float = 0.0) -> dict:
    """Energies [J] of a body floating in still water at y = ``level``: kinetic, gravitational
    (−m·g·x_com) and the buoyancy potential −ρ·g·V·(y_B − level) (the work done lifting the
    displaced water: its gradient is minus the buoyancy force); ``total``."""
    # take: [mesh.triangles] without fancy indexing's general path
    corners = body.to_world(mesh.vertices).take(mesh.triangles, axis=0)
    sub = submerged_below_plane(mesh, (0.0, level, 0.0), (0.0, 1.0, 0.0), corners=corners)
    kin = body.kinetic_energy()
    grav = body.potential_energy()
    buoy = -rho * g * sub.volume * (float(sub.centre[1]) - level)
    return {"kinetic": kin, "gravity": grav, "buoyancy": buoy, "total": kin + grav + buoy,
            "volume": sub.volume}
