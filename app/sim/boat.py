"""The sailing boat as one simulation (numpy only): the hull (``app.sim.hull``) on a rigid body
(``app.sim.rigid_body``) floated by one of three buoyancy methods (``app.sim.buoyancy``),
driven by the navigation, the sail, the keel and the hull resistance of ``app.sim.sailing`` on
the scene's one wind, leaving a wake (``app.sim.wake``) — spec/000 §1.3 and §1.4.

Buoyancy methods (``method``), switchable between steps:

* ``probes`` — the thesis's FloatingObject (spec/000 §1.3), kinematic: the pose follows the
  floating points' averaged displacement and normal at the two stiffness rates; the body only
  carries the horizontal motion (surge, sway and yaw from the sails and the navigation);
* ``probe_forces`` — force probes after Crest's BoatProbes: springs at the probes, a full
  rigid body;
* ``hydrostatic`` — Kerner 2015's pressure integration over the clipped hull triangles, with
  Kerner 2016's drag, a full rigid body.

Added mass and radiation damping (``hydrodynamics``, on by default; off reproduces the body
alone): the force methods' rigid body accelerates as (M + A)⁻¹·(f − B·ν) with the hull's
frequency-independent coefficients (``app.sim.buoyancy.hull_hydrodynamics``, computed by a
boundary-element solver in tools/added_mass.py).  The kinematic floating points place the boat
without forces or inertia, so the coefficients have nothing to act on there: that method stays
the thesis's.

Who resists what (nothing counted twice): the surge is resisted by the hull resistance of
``app.sim.sailing.Hull`` (ITTC-1957 friction plus the residuary, wave-making part calibrated on
the hull speed), so the buoyancy methods' own drag is computed without the surge component of
the velocity; sway, heave, roll, pitch and yaw keep their drag (and the keel's lift resists the
sway).

The boat frame is the hull's: +y up, +z toward the bow, y = 0 at the keel; a proper rotation
then puts body +x on *port* (bow × up = starboard), which only names the side: the hull is
symmetric. Headings are compass bearings of the bow (``app.sim.sailing``: 0 = north = −z,
clockwise), wind directions the direction the wind blows toward.

The query lag: the FFT ocean answers with the sea of the previous frame (its readback), so the
forces are those of water 1/60 s old at 60 fps; with ``DelayedWater`` the bench and the
stability tests add up to 3 frames of lag.
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Iterator

import numpy as np

from ..errors import ParamError
from . import sailing as sl
from .buoyancy import (
    HydrostaticBuoyancy,
    ProbeFloat,
    ProbeForces,
    boat_body,
    hull_hydrodynamics,
    probe_layout,
)
from .hull import HullMesh, HullParams, draft_for_mass, make_hull, waterline_length
from .rigid_body import Hydrodynamics, RigidBody, quat_from_axis_angle
from .vec import cross
from .wake import WakeParams, WakeTrail

METHODS = ("probes", "probe_forces", "hydrostatic")
#: the rudder and skeg as one fin at the stern: area [m²] and aspect ratio
SKEG_AREA = 0.5
SKEG_ASPECT = 1.5
#: the dry volume's bulwark: how far above the deck the water is kept out [m]
BULWARK = 1.2


@dataclass
class Controls:
    """The captain's inputs, each clamped to [−1, 1] (spec/000 §1.4, criterion 12): helm
    (NavigableObject's Direction: +1 turns the bow to starboard), throttle and the sails
    (SailObject's Sails Direction)."""

    helm: float = 0.0
    throttle: float = 0.0
    sails: float = 0.5


def rotation_for_heading(psi: float) -> np.ndarray:
    """Quaternion turning the boat frame's bow (+z) to the compass heading ψ [rad]: bow =
    (sin ψ, 0, −cos ψ), i.e. a turn of π − ψ about +y from +z."""
    return quat_from_axis_angle((0.0, 1.0, 0.0), math.pi - psi)


class BoatSim:
    """One boat. ``step(dt, water, wind_xz, t)`` advances it; ``water`` answers
    ``water(x, z)`` queries (the frame's ``water`` slot or an ``app.sim.buoyancy`` surface)."""

    def __init__(self, mass: float = 2500.0, method: str = "hydrostatic", probes: int = 4,
                 hull: HullParams | None = None, heading_deg: float = 0.0,
                 max_substep: float = 1.0 / 120.0, navigation_mode: str = "rudder",
                 sail_mode: str = "lift", displacement_stiffness: float = 6.0,
                 rotation_stiffness: float = 3.0, probe_distance: float = 1.0,
                 wake: WakeParams | None = None, hydrodynamics: bool | None = None):
        if method not in METHODS:
            raise ParamError(f"boat.buoyancy: {method!r} is not a method: allowed "
                             f"{', '.join(METHODS)}")
        self.mesh: HullMesh = make_hull(hull)
        self.mass = float(mass)
        self.draft = draft_for_mass(self.mesh, self.mass)
        self.body: RigidBody = boat_body(self.mesh, self.mass, max_substep=max_substep)
        self._hydrodynamics: Hydrodynamics | None = None
        self.hydrodynamics = hydrodynamics
        self.body.set_orientation(rotation_for_heading(math.radians(heading_deg)))
        self.method = method
        self.probes = int(probes)
        self._thesis = (displacement_stiffness, rotation_stiffness, probe_distance)
        self._methods: dict[tuple, Any] = {}
        p = self.mesh.params or HullParams()
        sub = self.mesh.submerged(self.draft)
        # the waterline's length at the displacement, from the mesh (it was 0.88 × LOA)
        lwl = waterline_length(self.mesh, self.draft)
        self.sailing = sl.Boat(
            hull=sl.Hull(lwl=lwl, displacement=self.mass, wetted_area=max(sub.wetted_area, 0.1)),
            sail=sl.Sail(mode=sail_mode),
            navigation=sl.Navigation(mode=navigation_mode, mass=self.mass,
                                     yaw_inertia=float(self.body.inertia_body[1, 1])))
        self.controls = Controls()
        self.wake = WakeTrail(params=wake or WakeParams(), beam=p.beam)
        self.stern_z = float(self.mesh.vertices[:, 2].min())

    @property
    def hydrodynamics(self) -> bool:
        """Whether the body has the hull's added mass and radiation damping."""
        return self.body.hydrodynamics is not None

    @hydrodynamics.setter
    def hydrodynamics(self, on: bool | None) -> None:
        """True: on (a ParamError for a hull the committed coefficients are not for); False:
        off; None: on when the committed coefficients are for this hull."""
        if on is not False and self._hydrodynamics is None:
            try:
                self._hydrodynamics = hull_hydrodynamics(self.mesh, self.mass)
            except ParamError:
                if on:
                    raise
        on = self._hydrodynamics is not None if on is None else bool(on)
        if on != self.hydrodynamics:
            self.body.hydrodynamics = self._hydrodynamics if on else None

    def buoyancy(self):
        """The object of the current method (made once per method and probe count)."""
        key = (self.method, self.probes)
        if key not in self._methods:
            if self.method == "hydrostatic":
                self._methods[key] = HydrostaticBuoyancy(self.mesh)
            elif self.method == "probe_forces":
                self._methods[key] = ProbeForces.for_hull(self.mesh, self.mass, n=self.probes)
            else:
                points, _ = probe_layout(self.mesh, self.probes, self.draft)
                ds, rs, pd = self._thesis
                self._methods[key] = ProbeFloat(points, displacement_stiffness=ds,
                                                rotation_stiffness=rs, probe_distance=pd)
        return self._methods[key]

    def set_thesis_parameters(self, displacement_stiffness: float, rotation_stiffness: float,
                              probe_distance: float) -> None:
        self._thesis = (displacement_stiffness, rotation_stiffness, probe_distance)
        for key, m in self._methods.items():
            if key[0] == "probes":
                m.displacement_stiffness, m.rotation_stiffness = (displacement_stiffness,
                                                                  rotation_stiffness)
                m.probe_distance = probe_distance

    @property
    def heading(self) -> float:
        """Compass heading of the bow [rad]."""
        return float(sl.heading_of(self.body.rotation[:, 2]))

    def state(self, body: RigidBody | None = None) -> sl.BoatState:
        b = self.body if body is None else body
        return sl.BoatState(b.velocity, float(sl.heading_of(b.rotation[:, 2])),
                            b.angular_velocity, b.rotation[:, 1])

    def speed(self) -> float:
        """Speed through the water along the bow [m/s]."""
        return float(self.state().surge)

    def sail_state(self, wind_xz) -> sl.SailState:
        return sl.sail_state(self.sailing.sail, _wind(wind_xz), self.state())

    def model_matrix(self) -> np.ndarray:
        """Boat frame → world (4×4, float64)."""
        m = np.identity(4)
        m[:3, :3] = self.body.rotation
        m[:3, 3] = self.body.position
        return m

    def dry_volume(self) -> np.ndarray:
        """Vertices of the dry volume: the hull with its deck raised by :data:`BULWARK` (same
        triangles as ``mesh``, so it stays closed)."""
        v = self.mesh.vertices.copy()
        deck = np.unique(self.mesh.triangles[self.mesh.deck])
        v[deck, 1] += BULWARK
        return v

    def _apply_controls(self) -> None:
        c = self.controls
        nav = self.sailing.navigation
        nav.direction, nav.throttle = c.helm, c.throttle
        self.sailing.sail.sails_direction = c.sails
        c.helm, c.throttle, c.sails = nav.direction, nav.throttle, self.sailing.sail.sails_direction

    def _sail_forces(self, body: RigidBody, wind: sl.Wind) -> tuple[np.ndarray, np.ndarray]:
        """Sails, keel, hull resistance and navigation: force and torque about the centre of
        mass (app.sim.sailing gives torques about the waterline reference point)."""
        force, torque = self.sailing.forces(self.state(body), wind)
        ref = body.to_world(np.array([0.0, self.draft, 0.0]))
        torque = torque + cross(ref - body.com_world, force)
        fs, ts = self._skeg(body)
        return force + fs, torque + ts

    def _skeg(self, body: RigidBody) -> tuple[np.ndarray, np.ndarray]:
        """The rudder and skeg as a fin at the stern: lift against the flow angle there
        (β = atan2(sideways, forward) of the water past it), ½·ρ·|v|²·A·C_L(β) with
        C_L = 2π·AR/(AR + 2)·β up to ±1 — the weathervane stability that keeps a boat with the
        helm amidships on its course (Prandtl's lifting line for the slope)."""
        p = body.to_world(np.array([0.0, max(self.draft - 0.4, 0.05), self.stern_z + 0.4]))
        v = body.point_velocity(p)
        bow, stbd = body.rotation[:, 2], -body.rotation[:, 0]
        u, w = float(v @ bow), float(v @ stbd)
        speed2 = u * u + w * w
        if speed2 < 1e-8:
            return np.zeros(3), np.zeros(3)
        slope = 2.0 * math.pi * SKEG_ASPECT / (SKEG_ASPECT + 2.0)
        cl = max(-1.0, min(1.0, slope * math.atan2(w, abs(u))))
        f = -0.5 * sl.RHO_WATER * speed2 * SKEG_AREA * cl * stbd
        return f, cross(p - body.com_world, f)

    def step(self, dt: float, water: Any, wind_xz, t: float) -> None:
        """Advance ``dt`` seconds at scene time ``t`` (the end of the step)."""
        if not (math.isfinite(dt) and dt > 0):
            return
        self._apply_controls()
        wind = _wind(wind_xz)
        method = self.buoyancy()
        body = self.body
        if self.method == "probes":
            gravity = body.gravity
            body.gravity = np.zeros(3)

            def horizontal(b, time):
                f, tau = self._sail_forces(b, wind)
                return np.array([f[0], 0.0, f[2]]), np.array([0.0, tau[1], 0.0])
            try:
                body.step(dt, horizontal, hydrodynamics=False)  # kinematic: nothing to act on
            finally:
                body.gravity = gravity
            v, yaw = body.velocity.copy(), float(body.angular_velocity[1])
            method.update(body, water, dt)
            body.velocity = np.array([v[0], body.velocity[1], v[2]])
            body.angular_velocity = np.array([0.0, yaw, 0.0])
        else:
            def forces(b, time):
                with _without_surge(b):
                    fb, tb = method.forces(b, water, time)
                fs, ts = self._sail_forces(b, wind)
                return fb + fs, tb + ts
            body.step(dt, forces)
        if not body.finite():  # never hand a NaN to the renderer: back to rest, upright
            self.reset(self.heading if math.isfinite(self.heading) else 0.0)
        stern = body.to_world(np.array([0.0, self.draft, self.stern_z]))
        self.wake.record(t, stern[[0, 2]], body.velocity[[0, 2]])

    def reset(self, heading: float = 0.0, position=(0.0, 0.0)) -> None:
        """Upright at rest at the equilibrium draft, bow to ``heading`` [rad]."""
        b = boat_body(self.mesh, self.mass, max_substep=self.body.max_substep,
                      hydrodynamics=False)
        b.hydrodynamics = self.body.hydrodynamics
        b.set_orientation(rotation_for_heading(heading))
        b.position = (position[0], -self.draft, position[1])
        self.body = b
        self.wake.clear()

    def spin_up(self, water: Any, wind_xz, t_end: float, seconds: float = 25.0,
                dt: float = 1.0 / 30.0) -> None:
        """Sail the last ``seconds`` before ``t_end`` at once (a single rendered frame then shows
        a boat under way with its wake behind it); the water is queried as it is given."""
        steps = max(1, int(round(seconds / dt)))
        keep = self.body.max_substep
        self.body.max_substep = max(keep, dt)  # one substep a step: stable (ω·h ≈ 0.2 in heave)
        try:
            for i in range(steps):
                self.step(dt, water, wind_xz, t_end - seconds + (i + 1) * dt)
        finally:
            self.body.max_substep = keep


@contextmanager
def _without_surge(body: RigidBody) -> Iterator[None]:
    """The body's velocity without its component along the bow, for the buoyancy methods'
    drag (the hull resistance of app.sim.sailing resists the surge)."""
    v = body.velocity
    bow = body.rotation[:, 2]
    body.velocity = v - float(v @ bow) * bow
    try:
        yield
    finally:
        body.velocity = v


def _wind(wind_xz) -> sl.Wind:
    if wind_xz is None:
        return sl.Wind(0.0, 90.0)
    vx, vz = (float(v) for v in wind_xz)
    return sl.Wind(math.hypot(vx, vz), math.degrees(math.atan2(vx, -vz)) % 360.0)
