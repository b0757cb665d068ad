"""Navigation, wind and sails — the numpy model of spec/000 §1.4 (``NavigableObject.cs``,
``Wind.cs``, ``SailObject.cs``), and beyond the thesis a lift/drag sail on the apparent wind, a
keel and a hull resistance, and the speed polar they give.

Conventions
-----------
* **World**: right-handed, y up; north is −z, east is +x (the ocean's frame, app/sim/ocean.py).
* **Heading** ψ [rad] is a compass bearing of the bow: ψ = 0 bow toward north (−z), ψ = π/2
  toward east (+x), increasing clockwise seen from above::

      bow(ψ) = (sin ψ, 0, −cos ψ)        starboard(ψ) = bow × up = (cos ψ, 0, sin ψ)

  It is the same angle convention as the ocean's wind direction (below), so the wind angle
  seen from the boat is simply ``wind direction − heading`` (spec/000 §2, criterion 36:
  ``relative_wind_angle``). A positive yaw rate r = dψ/dt turns the bow to starboard; it is a
  rotation about **−y**: ω_y = −r (torques below are world vectors, so a turn to starboard is
  a torque along −y). ``heading_of`` takes a bow vector (from a rigid body's orientation) back
  to ψ.
* **Wind direction** [degrees] is exactly ``ocean.wind_direction`` and
  ``app.effects.ocean.params.wind_vector``: the compass direction the wind blows **toward**,
  0 = north (−z), 90 = east (+x): ``wind_vector(speed, d) = speed·(sin d, 0, −cos d)``. One
  ``Wind`` drives the ocean spectrum, the clouds, the sails and the flag. Sailors' angles are
  measured to where the wind comes **from**: the true wind angle (TWA) and the apparent wind
  angle (AWA) are angles off the bow of the wind's source, in (−180°, 180°], positive when the
  wind comes over the starboard side (0 = head to wind, 180 = dead downwind).
* **Boat axes** in this module are world vectors built from ψ (bow, starboard, up); no body
  rotation matrix is assumed. (Note: a rotation taking body +z to the bow and body +y up takes
  body +x to *port*, since bow × up = starboard; a body frame "+x starboard, +y up, +z bow" is
  left-handed.)
* Units: metres, seconds, kilograms, newtons, radians (degrees only where a name says so:
  ``direction`` of the wind, ``*_deg`` arguments, ``twa`` in the polar's report).

Each class's docstring says what it implements (docs/theory/000-maritime.md §1.4 the thesis's
part and Natura's): ``Navigation``, ``Wind``, ``Sail`` (the thesis's thrust and the lift/drag
sail), ``Hull`` (resistance and keel), ``speed_polar`` and ``sail_state`` (the cloth's view).

Parameters are checked by ``app.params.Param`` (``sailing_params`` lists them): a bad value is a
one-line ``ParamError`` naming it and what is allowed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

from ..params import Param
from .maths import smoothstep as _smoothstep
from .maths import wrap_degrees
from .vec import cross, norm

G = 9.81
RHO_AIR = 1.225  # kg/m³, 15 °C at sea level
RHO_WATER = 1025.0  # kg/m³, seawater
NU_WATER = 1.19e-6  # m²/s, seawater at 15 °C (ITTC)
#: hull speed as a Froude number: 1.34 kn/√ft = 1.248 m/s/√m = 0.399·√g
HULL_SPEED_FROUDE = 0.4
KNOT = 1852.0 / 3600.0
UP = np.array([0.0, 1.0, 0.0])

SECTION = "spec/000 §1.4"
#: name → (default, lo, hi, unit, doc, section); the constructors check against this table
_TABLE: dict[str, tuple[float, float, float, str, str, str]] = {
    # Navigation (NavigableObject.cs)
    "sailing.max_turn_speed": (math.radians(20.0), 1e-3, 10.0, "rad/s",
                               "Max. Turn Speed: the largest yaw rate", SECTION),
    "sailing.max_speed": (3.0, 1e-3, 100.0, "m/s", "Max. Speed: the motor's top speed", SECTION),
    "sailing.mass": (2500.0, 1.0, 1e7, "kg", "the boat's mass (servo forces)", ""),
    "sailing.yaw_inertia": (10000.0, 1e-3, 1e10, "kg·m²", "moment of inertia about up", ""),
    "sailing.response_time": (1.5, 1e-3, 100.0, "s", "time constant of the servo forces", ""),
    "sailing.rudder_area": (0.3, 1e-3, 100.0, "m²", "rudder area", ""),
    "sailing.rudder_lever": (3.0, 1e-2, 100.0, "m", "rudder distance aft of the centre", ""),
    "sailing.rudder_cl": (1.0, 1e-2, 2.0, "", "rudder lift coefficient at full Direction", ""),
    # Sail (SailObject.cs and the lift/drag model)
    "sailing.max_angle": (math.radians(85.0), 0.0, math.pi / 2, "rad",
                          "Max. Angle Sails: the boom's largest angle off the centreline",
                          SECTION),
    "sailing.min_angle": (math.radians(8.0), 0.0, math.pi / 4, "rad",
                          "the closest the sheet can pull the boom to the centreline", ""),
    "sailing.sail_area": (30.0, 1e-3, 1e4, "m²", "sail area", ""),
    "sailing.ce_height": (3.8, 0.0, 100.0, "m", "centre of effort above the waterline", ""),
    "sailing.cl_max": (1.4, 0.1, 3.0, "", "largest lift coefficient (attached flow)", ""),
    "sailing.stall_aoa": (math.radians(20.0), math.radians(5.0), math.radians(45.0), "rad",
                          "angle of attack of the largest lift", ""),
    "sailing.stall_width": (math.radians(15.0), math.radians(1.0), math.radians(45.0), "rad",
                            "angle over which the lift falls to the flat plate's", ""),
    "sailing.luff_aoa": (math.radians(7.0), 0.0, math.radians(30.0), "rad",
                         "angle of attack below which the sail luffs (no lift)", ""),
    "sailing.cd0": (0.04, 0.0, 1.0, "", "profile drag coefficient", ""),
    "sailing.k_induced": (0.12, 0.0, 1.0, "", "drag due to lift: C_D = C_D0 + k·C_L²", ""),
    "sailing.c_plate": (1.3, 0.1, 3.0, "", "normal-force coefficient of the stalled sail", ""),
    "sailing.windage": (3.5, 0.0, 1e3, "m²", "C_D·A of the hull and rig above water", ""),
    # Hull
    # the default hull's (app/sim/hull.py) waterline at 2.5 t, cut from the mesh
    # (hull.waterline_length: 7.269 m; it was 7.0, and app/sim/boat.py took 0.88 × LOA = 7.04)
    "sailing.lwl": (7.27, 0.1, 500.0, "m", "waterline length", ""),
    "sailing.displacement": (2500.0, 1.0, 1e8, "kg", "displacement (mass)", ""),
    "sailing.wetted_area": (13.0, 1e-2, 1e5, "m²", "wetted area of hull and appendages", ""),
    "sailing.keel_area": (1.0, 1e-3, 1e4, "m²", "keel lateral area", ""),
    "sailing.keel_aspect": (2.0, 0.1, 20.0, "", "keel effective aspect ratio", ""),
    "sailing.keel_cl_max": (1.0, 0.1, 2.0, "", "keel's largest lift coefficient (stall)", ""),
    "sailing.clr_depth": (0.6, 0.0, 50.0, "m", "centre of lateral resistance below the waterline",
                          ""),
    "sailing.gm": (1.0, 1e-2, 20.0, "m", "metacentric height (righting moment Δ·g·GM·sin φ)", ""),
    "sailing.max_heel": (math.radians(30.0), math.radians(5.0), math.radians(80.0), "rad",
                         "largest heel the trim allows", ""),
    "sailing.residuary": (0.0045, 0.0, 1.0, "", "residuary resistance / weight at Fn 0.3", ""),
    "sailing.wave_exponent": (10.0, 6.0, 30.0, "", "residuary ∝ Fn^n above the hull speed", ""),
    # Wind (Wind.cs)
    "sailing.wind_speed": (8.0, 0.0, 60.0, "m/s", "true wind speed", SECTION),
    "sailing.wind_direction": (90.0, -360.0, 720.0, "°", "direction the wind blows toward: "
                               "0 = north (−z), 90 = east (+x), as ocean.wind_direction",
                               SECTION),
}


def sailing_params() -> list[Param]:
    """Every parameter of this module as an ``app.params.Param`` (defaults of an 8 m boat)."""
    return [Param(name, d, lo, hi, doc, unit=unit, section=section)
            for name, (d, lo, hi, unit, doc, section) in _TABLE.items()]


def _check(key: str, value) -> float:
    """``value`` as a float, or the one-line ParamError of ``sailing.<key>``."""
    _, lo, hi, unit, doc, _ = _TABLE["sailing." + key]
    return float(Param("sailing." + key, value, lo, hi, doc, unit=unit).default)


def clamp_input(value) -> float:
    """A control input (Direction, Throttle, Sails Direction) clamped to [−1, 1]
    (spec/000 §1.4, criterion 12); NaN reads as 0 (centred), ±inf as ±1."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return 0.0
    if math.isnan(x):
        return 0.0
    return min(1.0, max(-1.0, x))


class _ClampedInput:
    """A control input attribute: :func:`clamp_input` on every assignment."""

    def __set_name__(self, owner, name: str) -> None:
        self.name = "_" + name

    def __get__(self, obj, objtype=None) -> float:
        return getattr(obj, self.name) if obj is not None else self  # type: ignore[return-value]

    def __set__(self, obj, value) -> None:
        setattr(obj, self.name, clamp_input(value))


def _horizontal(x, z) -> np.ndarray:
    """The world vectors (x, 0, z) (…, 3) of float64 components of one shape: np.stack([x,
    zeros, z], axis=-1) filled in by component (np.stack's checks cost more than the maths)."""
    out = np.empty(np.shape(x) + (3,))
    out[..., 0] = x
    out[..., 1] = 0.0
    out[..., 2] = z
    return out


def heading_vector(psi) -> np.ndarray:
    """The bow's world direction (…, 3) for heading ψ [rad]: (sin ψ, 0, −cos ψ)."""
    psi = np.asarray(psi, dtype=np.float64)
    return _horizontal(np.sin(psi), -np.cos(psi))


def starboard_vector(psi) -> np.ndarray:
    """The starboard direction (…, 3) for heading ψ: bow × up = (cos ψ, 0, sin ψ)."""
    psi = np.asarray(psi, dtype=np.float64)
    return _horizontal(np.cos(psi), np.sin(psi))


def heading_of(vector) -> np.ndarray | float:
    """The heading ψ ∈ (−π, π] of a world direction (its horizontal part): atan2(x, −z)."""
    v = np.asarray(vector, dtype=np.float64)
    out = np.arctan2(v[..., 0], -v[..., 2])
    return float(out) if out.ndim == 0 else out


def wind_vector(speed, direction) -> np.ndarray:
    """The wind's world velocity (…, 3) [m/s]: ``speed`` toward compass ``direction`` [degrees],
    0 = north (−z), 90 = east (+x) — ``app.effects.ocean.params.wind_vector`` times the speed,
    with y = 0."""
    a = np.radians(np.asarray(direction, dtype=np.float64))
    s = np.asarray(speed, dtype=np.float64)
    return _horizontal(s * np.sin(a), -s * np.cos(a))


def relative_wind_angle(direction, psi):
    """The HUD's wind indicator (spec/000 §2, criterion 36): the wind's direction [degrees,
    toward] minus the boat's heading, in (−180, 180]; 0 = the wind blows the way the bow points
    (dead downwind), 90 = it blows toward starboard."""
    return wrap_degrees(np.asarray(direction, dtype=np.float64) - np.degrees(psi))


def wind_angle(wind_velocity, psi):
    """TWA or AWA [rad] ∈ (−π, π] of a wind velocity (…, 3) off the bow of heading ψ: the angle
    of where the wind comes **from**, positive over the starboard side, 0 = head to wind."""
    src = -np.asarray(wind_velocity, dtype=np.float64)
    s, c = _sin_cos(psi)
    out = np.arctan2(_dot_starboard(src, s, c), _dot_bow(src, s, c))
    return float(out) if np.ndim(out) == 0 else out


# The dot products of world vectors (…, 3) with starboard_vector(ψ) = (cos ψ, 0, sin ψ) and
# heading_vector(ψ) = (sin ψ, 0, −cos ψ), written out from sin ψ and cos ψ: the products and the
# additions of np.sum(v * vector, axis=-1), in its order, without building the vectors.  The
# y term is zero but kept: it can decide the sign of a sum that is exactly zero, which atan2
# reads.

def _sin_cos(psi) -> tuple[np.ndarray, np.ndarray]:
    psi = np.asarray(psi, dtype=np.float64)
    return np.sin(psi), np.cos(psi)


def _dot_starboard(v: np.ndarray, s, c) -> np.ndarray:
    return v[..., 0] * c + v[..., 1] * 0.0 + v[..., 2] * s


def _dot_bow(v: np.ndarray, s, c) -> np.ndarray:
    return v[..., 0] * s + v[..., 1] * 0.0 + v[..., 2] * -c


def apparent_wind(true_wind, boat_velocity) -> np.ndarray:
    """V_a = V_true − v_boat (horizontal: the y components are dropped)."""
    va = np.asarray(true_wind, dtype=np.float64) - np.asarray(boat_velocity, dtype=np.float64)
    va = np.array(va, copy=True)
    va[..., 1] = 0.0
    return va


def _cw90(v: np.ndarray) -> np.ndarray:
    """A horizontal world vector turned 90° clockwise seen from above (bow → starboard)."""
    return _horizontal(-v[..., 2], v[..., 0])


@dataclass(frozen=True)
class Wind:
    """The global wind (``Wind.cs``, spec/000 §1.4): ``speed`` [m/s] toward ``direction``
    [degrees, the ocean's convention]."""

    speed: float = _TABLE["sailing.wind_speed"][0]
    direction: float = _TABLE["sailing.wind_direction"][0]

    def __post_init__(self):
        object.__setattr__(self, "speed", _check("wind_speed", self.speed))
        object.__setattr__(self, "direction", _check("wind_direction", self.direction))

    def vector(self) -> np.ndarray:
        """World velocity (3,) [m/s] (made once: the sail reads it every substep)."""
        v = self.__dict__.get("_vector")
        if v is None:
            v = wind_vector(self.speed, self.direction)
            object.__setattr__(self, "_vector", v)
        return v.copy()

    def xz(self) -> tuple[float, float]:
        """(x, z) [m/s], the form of the frame's ``wind`` slot."""
        v = self.vector()
        return float(v[0]), float(v[2])


@dataclass
class BoatState:
    """What the force models read: world velocity (3,) [m/s], heading ψ [rad], world angular
    velocity (3,) [rad/s] (yaw rate r = −ω_y), and the boat's up vector (3,) for the torque arms
    (world y when upright)."""

    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    heading: float = 0.0
    angular_velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    up: np.ndarray = field(default_factory=lambda: UP.copy())

    def __post_init__(self):
        self.velocity = np.asarray(self.velocity, dtype=np.float64).reshape(3)
        self.angular_velocity = np.asarray(self.angular_velocity, dtype=np.float64).reshape(3)
        self.up = np.asarray(self.up, dtype=np.float64).reshape(3)
        self.heading = float(self.heading)

    @property
    def bow(self) -> np.ndarray:
        return self._axes()[0].copy()

    @property
    def starboard(self) -> np.ndarray:
        return self._axes()[1].copy()

    def _axes(self) -> tuple[np.ndarray, np.ndarray]:
        """(bow, starboard) of the heading, made once per heading (the force models read them
        eight times a substep; the key keeps the sign of a zero heading, which the bow's x
        component has)."""
        psi = self.heading
        key = (psi, math.copysign(1.0, psi))
        held = self.__dict__.get("_axes_held")
        if held is None or held[0] != key:  # a NaN heading is never equal: made every time
            held = (key, heading_vector(psi), starboard_vector(psi))
            self.__dict__["_axes_held"] = held
        return held[1], held[2]

    @property
    def surge(self) -> float:
        """Forward speed u = v·bow."""
        return float(self.velocity @ self._axes()[0])

    @property
    def sway(self) -> float:
        """Sideways speed w = v·starboard."""
        return float(self.velocity @ self._axes()[1])

    @property
    def yaw_rate(self) -> float:
        """r = dψ/dt = −ω_y."""
        return -float(self.angular_velocity[1])

    @property
    def heel(self) -> float:
        """Heel angle [rad] of the up vector from the vertical."""
        n = float(np.linalg.norm(self.up))
        return math.acos(max(-1.0, min(1.0, float(self.up[1]) / n))) if n > 0 else 0.0


def _yaw_torque(n: float) -> np.ndarray:
    """A world torque turning the bow to starboard by ``n`` [N·m] (about −y)."""
    return np.array([0.0, -n, 0.0])


NAVIGATION_MODES = ("thesis", "rudder")


class Navigation:
    """The thesis's NavigableObject (spec/000 §1.4): rudder ``direction`` and ``throttle`` in
    [−1, 1] (clamped on every assignment, criterion 12), ``max_turn_speed`` [rad/s],
    ``max_speed`` [m/s]. Direction +1 turns the bow to starboard (ψ grows)."""

    def __init__(self, max_turn_speed: float = _TABLE["sailing.max_turn_speed"][0],
                 max_speed: float = _TABLE["sailing.max_speed"][0], direction: float = 0.0,
                 throttle: float = 0.0, mode: str = "thesis",
                 mass: float = _TABLE["sailing.mass"][0],
                 yaw_inertia: float = _TABLE["sailing.yaw_inertia"][0],
                 response_time: float = _TABLE["sailing.response_time"][0],
                 rudder_area: float = _TABLE["sailing.rudder_area"][0],
                 rudder_lever: float = _TABLE["sailing.rudder_lever"][0],
                 rudder_cl: float = _TABLE["sailing.rudder_cl"][0]):
        self.max_turn_speed = _check("max_turn_speed", max_turn_speed)
        self.max_speed = _check("max_speed", max_speed)
        self.mass = _check("mass", mass)
        self.yaw_inertia = _check("yaw_inertia", yaw_inertia)
        self.response_time = _check("response_time", response_time)
        self.rudder_area = _check("rudder_area", rudder_area)
        self.rudder_lever = _check("rudder_lever", rudder_lever)
        self.rudder_cl = _check("rudder_cl", rudder_cl)
        self.mode = Param("sailing.navigation", mode, kind="choice",
                          choices=NAVIGATION_MODES).default
        self.direction = direction
        self.throttle = throttle

    direction = _ClampedInput()
    throttle = _ClampedInput()

    # the thesis's kinematic form
    def yaw_rate(self) -> float:
        """The thesis's yaw rate: Direction·Max. Turn Speed [rad/s]."""
        return self.direction * self.max_turn_speed

    def target_speed(self) -> float:
        """Throttle·Max. Speed [m/s] (negative: astern)."""
        return self.throttle * self.max_speed

    def step(self, heading: float, speed: float, dt: float) -> tuple[float, float]:
        """One kinematic step (spec/000 §1.4): ψ += yaw rate·dt, the speed relaxing toward
        Throttle·Max. Speed with ``response_time`` (exact exponential, so it never overshoots),
        clamped to ±Max. Speed. Returns (heading wrapped to (−π, π], speed)."""
        dt = max(0.0, float(dt))
        psi = math.remainder(float(heading) + self.yaw_rate() * dt, 2.0 * math.pi)
        if psi <= -math.pi:
            psi += 2.0 * math.pi
        s = float(speed) if math.isfinite(float(speed)) else 0.0
        s = s + (self.target_speed() - s) * (1.0 - math.exp(-dt / self.response_time))
        return psi, min(self.max_speed, max(-self.max_speed, s))

    # forces for a rigid body
    def forces(self, state: BoatState) -> tuple[np.ndarray, np.ndarray]:
        """(force (3,), torque (3,)) in world axes, about the boat's centre.

        Motor: a push along the bow of mass/response_time·(Throttle·max speed − u), only while
        it pushes toward that target (never past it, never braking). Yaw, ``"thesis"`` mode: a
        servo torque I/response_time·(Direction·max turn speed − r). ``"rudder"`` mode: the rudder
        lift Y = ½·ρ_w·u|u|·A_r·C_L·Direction, pushing the stern to port for Direction > 0, with
        a hull yaw damping −(k·|u| + I/(10·response_time))·r whose k makes the steady full-rudder
        rate at max speed the max turn speed. Either way a yaw rate beyond the max turn speed
        gets no torque that would raise it and a servo torque back to it."""
        u = state.surge
        r = state.yaw_rate
        bow, stbd = state.bow, state.starboard
        tau = self.response_time
        push = self.mass / tau * (self.target_speed() - u)
        if self.throttle == 0.0 or push * self.throttle < 0.0:
            push = 0.0
        force = push * bow
        i = self.yaw_inertia
        if self.mode == "thesis":
            n = i / tau * (self.yaw_rate() - r)
        else:
            q_area = 0.5 * RHO_WATER * self.rudder_area * self.rudder_cl
            lift = q_area * u * abs(u) * self.direction
            n_rudder = lift * self.rudder_lever
            n_full = q_area * self.max_speed ** 2 * self.rudder_lever
            k = n_full / (self.max_speed * self.max_turn_speed)
            n = n_rudder - (k * abs(u) + i / (10.0 * tau)) * r
            force = force - lift * stbd  # the rudder pushes the stern sideways
        limit = self.max_turn_speed
        if abs(r) >= limit:
            if n * r > 0.0:
                n = 0.0
            n += -i / tau * (r - math.copysign(limit, r))
        return force, _yaw_torque(n)


@dataclass(frozen=True)
class Hull:
    """Hull and keel of a displacement boat (defaults: an 8 m cruiser, LWL 7.27 m, 2.5 t, keel
    1 m² of effective aspect ratio 2, chosen with the sail's so that the polar has a cruiser's
    no-go zone, ≈ 32–35°, and best VMG angle, ≈ 42–46°). The residuary resistance is of the
    order of the Delft Systematic Yacht Hull Series (Gerritsma, Keuning & Onnink 1993); the
    keel's lift slope is Prandtl's lifting line for an elliptic wing."""

    lwl: float = _TABLE["sailing.lwl"][0]
    displacement: float = _TABLE["sailing.displacement"][0]
    wetted_area: float = _TABLE["sailing.wetted_area"][0]
    keel_area: float = _TABLE["sailing.keel_area"][0]
    keel_aspect: float = _TABLE["sailing.keel_aspect"][0]
    keel_cl_max: float = _TABLE["sailing.keel_cl_max"][0]
    clr_depth: float = _TABLE["sailing.clr_depth"][0]
    gm: float = _TABLE["sailing.gm"][0]
    max_heel: float = _TABLE["sailing.max_heel"][0]
    residuary: float = _TABLE["sailing.residuary"][0]
    wave_exponent: float = _TABLE["sailing.wave_exponent"][0]

    def __post_init__(self):
        for f in fields(self):
            object.__setattr__(self, f.name, _check(f.name, getattr(self, f.name)))

    @property
    def hull_speed(self) -> float:
        """1.34·√(LWL in ft) knots = 0.4·√(g·LWL) m/s (≈ 1.25·√(LWL in m))."""
        return HULL_SPEED_FROUDE * math.sqrt(G * self.lwl)

    @property
    def keel_slope(self) -> float:
        """Lift slope per radian 2π·AR/(AR + 2)."""
        return 2.0 * math.pi * self.keel_aspect / (self.keel_aspect + 2.0)

    def froude(self, u):
        return np.abs(np.asarray(u, dtype=np.float64)) / math.sqrt(G * self.lwl)

    def frictional(self, u):
        """ITTC 1957: ½·ρ_w·u²·S·0.075/(log₁₀Re − 2)² [N]."""
        u = np.abs(np.asarray(u, dtype=np.float64))
        re = np.maximum(u * self.lwl / NU_WATER, 1e5)
        cf = 0.075 / (np.log10(re) - 2.0) ** 2
        return 0.5 * RHO_WATER * u * u * self.wetted_area * cf

    def residuary_resistance(self, u):
        """Wave-making: W·r₀·(Fn/0.3)^6 up to Fn 0.4, then ×(Fn/0.4)^n [N]."""
        fn = self.froude(u)
        w = self.displacement * G
        base = self.residuary * (np.minimum(fn, HULL_SPEED_FROUDE) / 0.3) ** 6
        wall = (np.maximum(fn, HULL_SPEED_FROUDE) / HULL_SPEED_FROUDE) ** self.wave_exponent
        return w * base * wall

    def resistance(self, u):
        """Upright resistance R(u) = frictional + residuary [N], ≥ 0."""
        return self.frictional(u) + self.residuary_resistance(u)

    def keel_cl(self, leeway):
        """Keel lift coefficient on the leeway angle [rad] (sign kept): a·λ up to C_Lmax, then
        toward a flat plate sideways, C_Lmax + (1.2 − C_Lmax)·sin²λ."""
        lam = np.asarray(leeway, dtype=np.float64)
        s = np.abs(np.sin(lam))
        attached = self.keel_slope * s
        stalled = self.keel_cl_max + (1.2 - self.keel_cl_max) * s * s
        return np.sign(lam) * np.minimum(attached, stalled)

    def forces(self, state: BoatState) -> tuple[np.ndarray, np.ndarray]:
        """Water forces on the moving hull: resistance against the surge, keel lift against the
        sway (at ``clr_depth`` below the waterline reference, so it heels the boat against the
        sail) and its induced drag against the motion. (force, torque) in world axes."""
        u, w = state.surge, state.sway
        bow, stbd = state.bow, state.starboard
        speed2 = u * u + w * w
        force = -np.sign(u) * float(self.resistance(u)) * bow
        if speed2 > 0.0:
            lam = math.atan2(w, abs(u))
            cl = float(self.keel_cl(lam))
            q = 0.5 * RHO_WATER * speed2 * self.keel_area
            lateral = -cl * q * stbd
            induced = q * cl * cl / (math.pi * self.keel_aspect)
            vh = np.array([state.velocity[0], 0.0, state.velocity[2]])
            force = force + lateral - induced * vh / math.sqrt(speed2)
            torque = cross(-self.clr_depth * state.up, lateral)
        else:
            torque = np.zeros(3)
        return force, torque


SAIL_MODES = ("lift", "thesis")


@dataclass
class SailState:
    """What the cloth renderer reads: ``boom`` [rad] off the centreline (+ = to starboard),
    ``side`` +1 if the belly bulges to starboard, −1 to port, ``fill`` 0 (luffing) … 1 (full),
    and the angle of attack ``aoa`` [rad] and the apparent wind angle ``awa`` [rad]."""

    boom: float
    side: int
    fill: float
    aoa: float
    awa: float


def _clip(x, lo: float, hi: float):
    """np.clip(x, lo, hi) as the two ufuncs it is (np.clip's argument handling costs more)."""
    return np.minimum(np.maximum(x, lo), hi)


class Sail:
    """The thesis's SailObject (spec/000 §1.4) and, beyond it, a lift/drag sail on the apparent
    wind whose boom the sheet lets out (``trim``, ``coefficients``, ``aero_force``).
    ``sails_direction`` in [−1, 1] is clamped on every assignment (criterion 12)."""

    def __init__(self, sails_direction: float = 0.5,
                 max_angle: float = _TABLE["sailing.max_angle"][0],
                 min_angle: float = _TABLE["sailing.min_angle"][0],
                 area: float = _TABLE["sailing.sail_area"][0],
                 ce_height: float = _TABLE["sailing.ce_height"][0],
                 cl_max: float = _TABLE["sailing.cl_max"][0],
                 stall_aoa: float = _TABLE["sailing.stall_aoa"][0],
                 stall_width: float = _TABLE["sailing.stall_width"][0],
                 luff_aoa: float = _TABLE["sailing.luff_aoa"][0],
                 cd0: float = _TABLE["sailing.cd0"][0],
                 k_induced: float = _TABLE["sailing.k_induced"][0],
                 c_plate: float = _TABLE["sailing.c_plate"][0],
                 windage: float = _TABLE["sailing.windage"][0], mode: str = "lift"):
        self.max_angle = _check("max_angle", max_angle)
        self.min_angle = _check("min_angle", min_angle)
        if self.min_angle > self.max_angle:
            Param("sailing.min_angle", min_angle, 0.0, self.max_angle)  # raises the ParamError
        self.area = _check("sail_area", area)
        self.ce_height = _check("ce_height", ce_height)
        self.cl_max = _check("cl_max", cl_max)
        self.stall_aoa = _check("stall_aoa", stall_aoa)
        self.stall_width = _check("stall_width", stall_width)
        self.luff_aoa = _check("luff_aoa", luff_aoa)
        if self.luff_aoa >= self.stall_aoa:
            Param("sailing.luff_aoa", luff_aoa, 0.0, self.stall_aoa - 1e-6)  # the ParamError
        self.cd0 = _check("cd0", cd0)
        self.k_induced = _check("k_induced", k_induced)
        self.c_plate = _check("c_plate", c_plate)
        self.windage = _check("windage", windage)
        self.mode = Param("sailing.sail_mode", mode, kind="choice", choices=SAIL_MODES).default
        self.sails_direction = sails_direction

    sails_direction = _ClampedInput()

    # the thesis's mode
    def thesis_boom(self) -> float:
        """Sails Direction × Max. Angle Sails [rad] (+ = boom to starboard)."""
        return self.sails_direction * self.max_angle

    def thesis_alignment(self, wind, psi):
        """|cos| of the angle between the wind and the sail's normal (1: the sail square to the
        wind) for the boom at ``thesis_boom`` — ``wind`` a world vector (…, 3)."""
        b = self.thesis_boom()
        normal = (math.sin(b) * heading_vector(psi) + math.cos(b) * starboard_vector(psi))
        w = np.asarray(wind, dtype=np.float64)
        n = np.linalg.norm(w, axis=-1)
        c = np.sum(w * normal, axis=-1) / np.where(n > 0, n, 1.0)
        return np.abs(c)

    def thesis_thrust(self, wind, psi):
        """spec/000 §1.4: thrust along the bow [N], larger the more perpendicular the sail is to
        the wind: ½·ρ_air·|V|²·A·|cos(wind, sail normal)| (criterion 13)."""
        w = np.asarray(wind, dtype=np.float64)
        q = 0.5 * RHO_AIR * np.sum(w * w, axis=-1)
        return q * self.area * self.thesis_alignment(w, psi)

    # the lift/drag sail
    def sheet(self) -> float:
        """The sheet's limit on the boom angle [rad]: |Sails Direction|·max angle, no closer in
        than min angle."""
        return max(self.min_angle, abs(self.sails_direction) * self.max_angle)

    def coefficients(self, aoa, flat=1.0):
        """(C_L, C_D) against the angle of attack [rad] (≥ 0): attached flow C_L =
        C_Lmax·sin(½π·(α − α_luff)/(α_stall − α_luff)) between the luffing angle and the stall,
        C_D = C_D0 + k·C_L², blended past the stall (smoothstep over ``stall_width``) into the
        flat plate C_L = C_N·sin α·cos α, C_D = C_D0 + C_N·sin²α (never below the attached
        C_D): the shapes of measured sail curves (Marchaj 1979), typical numbers. ``flat`` ∈
        [0, 1] scales the attached-flow lift (a flattened, twisted sail: less lift,
        less drag due to lift), not the stalled plate's."""
        a = _clip(np.abs(np.asarray(aoa, dtype=np.float64)), 0.0, math.pi)
        rise = _clip((a - self.luff_aoa) / (self.stall_aoa - self.luff_aoa), 0.0, 1.0)
        att_cl = np.asarray(flat, dtype=np.float64) * self.cl_max * np.sin(0.5 * math.pi * rise)
        att_cd = self.cd0 + self.k_induced * att_cl * att_cl
        sin_a = np.sin(a)
        plate_cl = self.c_plate * sin_a * np.cos(a)
        # past the stall the drag never falls below the attached flow's (C_D grows with α)
        plate_cd = np.maximum(self.cd0 + self.c_plate * sin_a ** 2, att_cd)
        w = _smoothstep(self.stall_aoa, self.stall_aoa + self.stall_width, a)
        attached = 1.0 - w
        return attached * att_cl + w * plate_cl, attached * att_cd + w * plate_cd

    def trim(self, awa, sheet=None):
        """(boom angle [rad] ≥ 0 off the centreline, angle of attack [rad] ≥ 0, leeward side
        ±1) for an apparent wind angle [rad]: boom = min(sheet, |AWA|) on the side away from
        the wind (side −1 = port when the wind comes over starboard), α = |AWA| − boom."""
        g = np.asarray(awa, dtype=np.float64)
        sheet = self.sheet() if sheet is None else np.asarray(sheet, dtype=np.float64)
        boom = np.minimum(sheet, np.abs(g))
        side = np.where(g >= 0.0, -1, 1)
        return boom, np.abs(g) - boom, side

    def aero_force(self, apparent, psi, sheet=None, flat=1.0, heel=0.0, windage: bool = True):
        """The lift/drag force (…, 3) [N] of the sail (plus the windage unless ``windage`` is
        false) on an apparent wind (…, 3), for heading ψ [rad]; ``sheet`` the boom limit [rad]
        (default ``sheet()``), ``flat`` as in ``coefficients``; the sail's part is scaled by
        cos²(heel)."""
        q, e_d, c_sail = self._aero(apparent, psi, sheet, flat)
        return self._aero_total(q, e_d, c_sail, heel, windage)

    def _aero(self, apparent, psi, sheet, flat):
        """The parts of ``aero_force`` that do not depend on the heel: (dynamic pressure q (…, 1),
        the flow's direction ê_D (…, 3), the sail's force coefficient vector C_L·ê_L + C_D·ê_D)."""
        va = np.asarray(apparent, dtype=np.float64)
        speed = norm(va, keepdims=True)
        e_d = va / np.where(speed > 0.0, speed, 1.0)
        boom, aoa, side = self.trim(wind_angle(va, psi), sheet)
        cl, cd = self.coefficients(aoa, flat)
        # lift perpendicular to the flow, toward the leeward side: e_D turned 90° clockwise
        # (seen from above) when the wind comes over starboard (side = −1), else anticlockwise
        e_l = -np.asarray(side, dtype=np.float64)[..., None] * _cw90(e_d)
        q = 0.5 * RHO_AIR * speed * speed
        return q, e_d, cl[..., None] * e_l + cd[..., None] * e_d

    def _aero_total(self, q, e_d, c_sail, heel, windage: bool):
        """``aero_force`` from the parts of ``_aero``, the sail's part scaled by cos²(heel)."""
        k = np.cos(np.asarray(heel, dtype=np.float64))[..., None] ** 2
        total = self.area * c_sail * k
        if windage:
            total = total + self.windage * e_d
        return q * total

    def state(self, apparent, psi) -> SailState:
        """The renderer's view (``SailState``) for an apparent wind (3,) and heading ψ."""
        va = np.asarray(apparent, dtype=np.float64).reshape(3)
        speed = float(np.linalg.norm(va[[0, 2]]))
        if self.mode == "thesis":
            boom = self.thesis_boom()
            g = float(wind_angle(va, psi)) if speed > 0 else 0.0
            normal = (math.sin(boom) * heading_vector(psi) + math.cos(boom) *
                      starboard_vector(psi))
            push = float(va @ normal)
            side = 1 if push >= 0.0 else -1
            align = float(self.thesis_alignment(va, psi))
            fill = align * float(_smoothstep(0.0, 1.5, speed))
            return SailState(boom, side, fill, math.asin(min(1.0, align)), g)
        if speed == 0.0:
            return SailState(0.0, 1, 0.0, 0.0, 0.0)
        g = float(wind_angle(va, psi))
        boom, aoa, side = self.trim(g)
        fill = float(_smoothstep(0.0, math.radians(10.0), aoa) * _smoothstep(0.0, 1.5, speed))
        return SailState(float(side) * float(boom), int(side), fill, float(aoa), g)

    def forces(self, state: BoatState, wind: Wind) -> tuple[np.ndarray, np.ndarray]:
        """(force, torque) in world axes: ``"lift"`` — ``aero_force`` on the apparent wind at the
        centre of effort ``ce_height``·up above the waterline reference (the heel torque);
        ``"thesis"`` — ``thesis_thrust`` along the bow, no torque."""
        if self.mode == "thesis":
            return float(self.thesis_thrust(wind.vector(), state.heading)) * state.bow, \
                np.zeros(3)
        va = apparent_wind(wind.vector(), state.velocity)
        f = self.aero_force(va, state.heading, heel=state.heel)
        return f, cross(self.ce_height * state.up, f)


def sail_state(sail: Sail, wind: Wind, state: BoatState) -> SailState:
    """Boom angle, belly side and fill for the renderer, on the apparent wind of ``state``."""
    return sail.state(apparent_wind(wind.vector(), state.velocity), state.heading)


@dataclass
class Boat:
    """A hull, a sail and a navigation (motor and rudder) together."""

    hull: Hull = field(default_factory=Hull)
    sail: Sail = field(default_factory=Sail)
    navigation: Navigation = field(default_factory=lambda: Navigation(mode="rudder"))

    def forces(self, state: BoatState, wind: Wind) -> tuple[np.ndarray, np.ndarray]:
        """The sum of the sail's, the hull's and the navigation's (force, torque)."""
        force, torque = np.zeros(3), np.zeros(3)
        for f, t in (self.sail.forces(state, wind), self.hull.forces(state),
                     self.navigation.forces(state)):
            force, torque = force + f, torque + t
        return force, torque


def _heel(side_force, hull: Hull, arm: float):
    """Heel φ where the heeling moment F·arm·cos²φ meets Δ·g·GM·sin φ: with a = F·arm/(Δ·g·GM),
    sin φ = (√(1 + 4a²) − 1)/(2a) (the positive root of a·s² + s − a = 0)."""
    a = np.abs(side_force) * arm / (hull.displacement * G * hull.gm)
    s = np.where(a > 1e-12, (np.sqrt(1.0 + 4.0 * a * a) - 1.0) / (2.0 * np.maximum(a, 1e-12)),
                 a)
    return np.arcsin(_clip(s, 0.0, 1.0))


def _net_drive(boat: Boat, twa, wind_speed: float, speed, sheet, flat, iterations: int = 3):
    """Net force along the course [N] (drive − resistance − keel induced drag) and the leeway
    [rad], broadcasting ``twa`` [rad, course-relative], ``speed``, ``sheet``, ``flat``;
    −inf where the keel stalls or the heel passes the max heel."""
    hull, sail = boat.hull, boat.sail
    twa, speed, sheet, flat = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64)
                                                    for x in (twa, speed, sheet, flat)))
    # course along −z (ψ_course = 0); the wind comes from angle TWA off the course
    true_wind = wind_vector(wind_speed, np.degrees(twa) + 180.0)
    vel = heading_vector(np.zeros_like(speed)) * speed[..., None]
    va = apparent_wind(true_wind, vel)
    q_w = 0.5 * RHO_WATER * speed * speed * hull.keel_area
    arm = sail.ce_height + hull.clr_depth
    leeway = np.zeros_like(speed)
    for _ in range(iterations):
        # the bow points to windward of the course by the leeway; the upright sail's force
        # (aero_force without windage) and the heeled one's share all but the heel
        q_a, e_d, c_sail = sail._aero(va, leeway, sheet, flat)
        upright = sail._aero_total(q_a, e_d, c_sail, 0.0, windage=False)
        # the sail's side force across the hull sets the heel
        side_sail = _dot_starboard(upright, *_sin_cos(leeway))
        heel = _heel(side_sail, hull, arm)
        f = sail._aero_total(q_a, e_d, c_sail, heel, windage=True)
        across = f[..., 0]  # course-perpendicular: starboard of the course is +x
        cl = -across / np.maximum(q_w, 1e-12)
        leeway = _clip(cl / hull.keel_slope, -0.5, 0.5)
    drive = -f[..., 2]  # along the course (−z)
    induced = q_w * cl * cl / (math.pi * hull.keel_aspect)
    net = drive - hull.resistance(speed) - induced
    bad = (np.abs(cl) > hull.keel_cl_max) | (heel > hull.max_heel)
    return np.where(bad, -np.inf, net), leeway


def _best(boat: Boat, twa, wind_speed, speed, sheets, flats):
    """max over trims of the net drive, for twa and speed of equal shape (…,)."""
    net, _ = _net_drive(boat, np.asarray(twa)[..., None, None], wind_speed,
                        np.asarray(speed)[..., None, None], sheets[:, None], flats[None, :])
    return net.reshape(net.shape[:-2] + (-1,)).max(axis=-1)


def steady_speed(boat: Boat, twa, wind_speed: float, sheets=None, flats=None,
                 speeds=None, bisections: int = 24) -> np.ndarray:
    """Steady boat speed [m/s] for course-relative true wind angles ``twa`` [rad] (see
    ``speed_polar``)."""
    twa = np.atleast_1d(np.asarray(twa, dtype=np.float64))
    sail, hull = boat.sail, boat.hull
    if sheets is None:
        sheets = np.linspace(sail.min_angle, sail.max_angle, 30)
    if flats is None:
        flats = np.linspace(0.2, 1.0, 5)
    if speeds is None:
        speeds = np.linspace(0.02, 2.0, 60) * hull.hull_speed
    if wind_speed <= 0.0:
        return np.zeros_like(twa)
    g = _best(boat, twa[:, None], wind_speed, speeds[None, :], sheets, flats)  # (n_twa, n_v)
    ok = g >= 0.0
    any_ok = ok.any(axis=1)
    top = np.where(any_ok, len(speeds) - 1 - np.argmax(ok[:, ::-1], axis=1), 0)
    lo = speeds[top]
    hi = speeds[np.minimum(top + 1, len(speeds) - 1)]
    capped = top == len(speeds) - 1
    for _ in range(bisections):
        mid = 0.5 * (lo + hi)
        good = _best(boat, twa, wind_speed, mid, sheets, flats) >= 0.0
        lo = np.where(good, mid, lo)
        hi = np.where(good, hi, mid)
    out = np.where(capped, speeds[-1], lo)
    return np.where(any_ok, out, 0.0)


def speed_polar(wind_speeds=(4.0, 8.0, 12.0), angles=None, boat: Boat | None = None,
                threshold: float = 0.05) -> dict:
    """The speed polar: steady boat speed against the true wind angle for each true wind speed,
    the sail trimmed for the most net drive at each angle.

    Method. For a true wind speed V_t and a TWA θ measured off the course (the boat's velocity),
    a boat speed V_s gives the apparent wind; the bow points to windward of the course by the
    leeway λ. For each trim — sheet (boom limit, 30 values from ``min_angle`` to ``max_angle``)
    and flat (a lift factor 0.2…1, 5 values: how far the sail is depowered) — the planar force
    balance is solved by a fixed point (3 iterations from λ = 0): sail force on the apparent
    wind at heading course + λ, heel from the closed-form balance of its heeling moment
    against the righting moment (cos²φ depowering), side force across the course balanced by
    the keel's lift, C_L,keel = side/(½ρ_w·V_s²·A_k), λ = C_L,keel/a. The net drive
    N(V_s) = drive along the course − hull resistance − keel induced drag is maximised over the
    trims (−inf where the keel would stall or the heel pass ``max_heel``). The steady speed is
    the **upper root** of max N: above it every trim decelerates the boat, below it some trim
    accelerates it. It is found by a scan of V_s over (0.02, 2]·hull speed (60 values) and 24
    bisections between the last scan point with N ≥ 0 and the next. Where no V_s has N ≥ 0 the
    speed is 0: the no-go zone (upwind the sail cannot drive; near the wind the keel needs
    speed to hold the side force, so the speed falls to 0 at a fold, not smoothly).

    Returns a dict: ``twa`` [degrees], ``wind_speeds``, ``speed`` [m/s] (one list per wind
    speed), ``no_go`` [degrees] (the smallest TWA from which the speed exceeds ``threshold`` of
    that wind's best speed, refined by bisection to 0.1°), ``upwind`` and ``downwind`` VMG
    (``vmg`` [m/s] = V_s·|cos θ|, ``twa``), ``beam`` (speed at 90°), ``max_speed`` and its TWA,
    ``hull_speed`` [m/s] and the boat's figures."""
    boat = Boat() if boat is None else boat
    # every wind speed checked before any is solved: a bad one is refused at once, not after
    # the polars of the speeds before it (seconds each)
    speeds = [_check("wind_speed", vt) for vt in wind_speeds]
    angles = np.arange(0.0, 180.1, 2.0) if angles is None else np.asarray(angles, float)
    out: dict = {"twa": [float(a) for a in angles], "wind_speeds": speeds,
                 "speed": [], "no_go": [], "upwind": [], "downwind": [], "beam": [],
                 "max_speed": [], "hull_speed": boat.hull.hull_speed,
                 "boat": {"lwl": boat.hull.lwl, "displacement": boat.hull.displacement,
                          "sail_area": boat.sail.area},
                 "method": "trim search (sheet × flat), fixed-point leeway and heel, upper root "
                           "of the net drive by scan and bisection"}
    theta = np.radians(angles)
    for vt in speeds:
        v = steady_speed(boat, theta, vt)
        out["speed"].append([float(x) for x in v])
        best = float(v.max()) if v.size else 0.0
        out["no_go"].append(_no_go(boat, vt, theta, v, threshold * best))
        vmg = v * np.cos(theta)
        iu, idn = int(np.argmax(vmg)), int(np.argmin(vmg))
        out["upwind"].append({"vmg": float(vmg[iu]), "twa": float(angles[iu])})
        out["downwind"].append({"vmg": float(-vmg[idn]), "twa": float(angles[idn])})
        out["beam"].append(float(steady_speed(boat, math.pi / 2, vt)[0]))
        im = int(np.argmax(v))
        out["max_speed"].append({"speed": float(v[im]), "twa": float(angles[im])})
    return out


def _no_go(boat: Boat, vt: float, theta, v, limit: float) -> float:
    """The smallest TWA [degrees] from which the speed stays above ``limit`` up to the beam."""
    theta = np.asarray(theta)
    sel = np.abs(theta) <= math.pi / 2 + 1e-9
    th, sp = np.abs(theta[sel]), np.asarray(v)[sel]
    order = np.argsort(th)
    th, sp = th[order], sp[order]
    above = sp > limit
    if not above.any():
        return 180.0
    # the last angle at or below the limit before the speeds stay above it
    below = np.nonzero(~above)[0]
    if below.size == 0:
        return float(np.degrees(th[0]))
    i = below[-1]
    if i + 1 >= th.size:
        return 180.0
    lo, hi = th[i], th[i + 1]
    while hi - lo > math.radians(0.1):
        mid = 0.5 * (lo + hi)
        if steady_speed(boat, mid, vt)[0] > limit:
            hi = mid
        else:
            lo = mid
    return float(np.degrees(hi))
