"""A rigid body for floating objects, integrated by semi-implicit (symplectic) Euler in fixed
substeps (numpy only).

State (world frame, y up): ``position`` — where the body frame's origin is; ``orientation`` —
the unit quaternion (w, x, y, z) taking body axes to world axes; ``velocity`` — of the centre of
mass; ``angular_velocity`` — world frame.  The centre of mass sits at ``com`` in the body frame
(for the boat: above the keel, the ballast's height), ``inertia_body`` is the inertia tensor about
it in body axes.

Integration (``step``): a frame of ``dt`` is cut into ``n = ceil(dt / max_substep)`` equal
substeps (≤ 1/240 s by default, so the result hardly depends on the frame rate).  Per substep h,
with the force and torque evaluated at the start of it:

* velocities first: v ← v + h·(F/m + g); angular momentum L ← L + h·τ (world frame);
* then positions with the new velocities: x_com ← x_com + h·v; ω = I_w⁻¹·L with
  I_w = R·I_body·Rᵀ taken at the midpoint orientation exp(½·h·ω₀)·q; q ← exp(h·ω)·q,
  renormalised.

Added mass and radiation damping (optional, :class:`Hydrodynamics`): the water a body shakes
moves with it, so a generalised force f = (F, τ) (body axes, about the centre of mass, gravity
included) accelerates (M + A) and not M alone, and the radiated waves take −B·ν, ν = (v, ω) in
body axes.  The step hands the rigid integrator the force M·(M + A)⁻¹·(f − B·ν) in place of f:
its accelerations are then (M + A)⁻¹·(f − B·ν), the linear seakeeping equation of motion
(Newman 1977, "Marine Hydrodynamics", §6.14) with A and B held at one frequency (see
``docs/theory/000-maritime.md#added-mass``).  The velocity-dependent gyroscopic terms of A
(Munk's moment) are left out: they are second order in the small motions A is computed for.

This is symplectic Euler (Hairer, Lubich & Wanner 2006, "Geometric Numerical Integration", §VI.3):
for a spring it keeps the energy error bounded (no secular drift) while ω·h < 2.  Integrating the
angular *momentum* rather than ω is how the gyroscopic term ω × Iω is handled stably: it never
appears explicitly (it is the change of I_w as the body turns), so |L| is exactly conserved by a
torque-free step and ω stays bounded by |L|/I_min — the explicit ω-form gains energy without
bound for a fast tumbling asymmetric body.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..errors import ParamError
from .vec import cross, length

G = 9.81  # [m/s²]
#: the longest substep [s] (240 Hz)
MAX_SUBSTEP = 1.0 / 240.0

ForceFn = Callable[["RigidBody", float], tuple[np.ndarray, np.ndarray]]


class Hydrodynamics:
    """Frequency-independent added mass ``added_mass`` [kg, kg·m, kg·m²] and radiation damping
    ``damping`` [kg/s, kg·m/s, kg·m²/s], 6×6 each, in body axes about the centre of mass, over
    the generalised velocity ν = (vx, vy, vz, ωx, ωy, ωz); ``source`` says where they came from."""

    def __init__(self, added_mass, damping, source: str = ""):
        self.added_mass = np.asarray(added_mass, float).reshape(6, 6).copy()
        self.damping = np.asarray(damping, float).reshape(6, 6).copy()
        self.source = source
        for name, m in (("added_mass", self.added_mass), ("damping", self.damping)):
            if not np.all(np.isfinite(m)):
                raise ParamError(f"hydrodynamics.{name}: not finite: allowed finite numbers")



def _components(q):
    """A single float64 quaternion or vector as Python floats (numpy scalars cost several times
    more per operation; the same operations in the same order give the same result), anything
    else as it is."""
    if isinstance(q, np.ndarray) and q.ndim == 1 and q.dtype == np.float64:
        return q.tolist()
    return q


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a·b (apply b, then a)."""
    return np.array(_product(_components(a), _components(b)))


def _product(a, b) -> tuple:
    """:func:`quat_multiply` of two quaternions' components, as components."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def quat_from_axis_angle(axis, angle: float) -> np.ndarray:
    axis = np.asarray(axis, float)
    n = length(axis)
    if n == 0.0 or angle == 0.0:
        return np.array([1.0, 0.0, 0.0, 0.0])
    s = math.sin(0.5 * angle) / n
    x, y, z = axis[:3].tolist()  # Python floats: the same products, cheaper than numpy scalars
    return np.array([math.cos(0.5 * angle), x * s, y * s, z * s])


def quat_from_rotvec(rv) -> np.ndarray:
    """exp of the rotation vector ``rv`` (axis × angle)."""
    rv = np.asarray(rv, float)
    angle = length(rv)
    if angle < 1e-12:
        q = np.array([1.0, 0.5 * rv[0], 0.5 * rv[1], 0.5 * rv[2]])
        return q / length(q)
    return quat_from_axis_angle(rv / angle, angle)


def _rotvec_components(rv: np.ndarray) -> tuple:
    """:func:`quat_from_rotvec` of a float64 vector (3,), as components: the same operations
    (√(v·v) by the same dot product, the same sines), without its conversions and calls."""
    angle = math.sqrt(rv.dot(rv))
    if angle < 1e-12:
        return tuple(quat_from_rotvec(rv).tolist())
    axis = rv / angle
    n = math.sqrt(axis.dot(axis))
    if n == 0.0:
        return (1.0, 0.0, 0.0, 0.0)
    s = math.sin(0.5 * angle) / n
    x, y, z = axis.tolist()
    return (math.cos(0.5 * angle), x * s, y * s, z * s)


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    return _matrix(_components(q))


def _matrix(q) -> np.ndarray:
    """:func:`quat_to_matrix` of a quaternion's components."""
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def quat_from_matrix(m) -> np.ndarray:
    """The unit quaternion (w ≥ 0) of a rotation matrix (Shepperd's method)."""
    m = np.asarray(m, float)
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = np.array([0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s,
                      (m[1, 0] - m[0, 1]) / s])
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(max(1.0 + m[i, i] - m[j, j] - m[k, k], 1e-300))
        q = np.empty(4)
        q[0] = (m[k, j] - m[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + k] = (m[k, i] + m[i, k]) / s
    q /= length(q)
    return q if q[0] >= 0 else -q


def quat_slerp(a: np.ndarray, b: np.ndarray, t: float) -> np.ndarray:
    """Spherical interpolation from a (t = 0) to b (t = 1), the short way round."""
    d = float(np.dot(a, b))
    if d < 0.0:
        b, d = -b, -d
    if d > 0.9995:
        q = a + t * (b - a)
        return q / length(q)
    th = math.acos(min(d, 1.0))
    s = math.sin(th)
    return (math.sin((1 - t) * th) * a + math.sin(t * th) * b) / s


def quat_between(u, v) -> np.ndarray:
    """The shortest rotation taking direction u to direction v."""
    u = np.asarray(u, float) / length(u)
    v = np.asarray(v, float) / length(v)
    c = float(np.dot(u, v))
    if c < -1.0 + 1e-12:
        axis = cross(u, [1.0, 0.0, 0.0])
        if length(axis) < 1e-6:
            axis = cross(u, [0.0, 0.0, 1.0])
        return quat_from_axis_angle(axis, math.pi)
    q = np.array([1.0 + c, *cross(u, v).tolist()])
    return q / length(q)



class RigidBody:
    """A rigid body (see the module docstring for the state and the integrator)."""

    def __init__(self, mass: float, inertia_body, position=(0.0, 0.0, 0.0), orientation=None,
                 velocity=(0.0, 0.0, 0.0), angular_velocity=(0.0, 0.0, 0.0),
                 com=(0.0, 0.0, 0.0), gravity=(0.0, -G, 0.0), max_substep: float = MAX_SUBSTEP,
                 hydrodynamics: Hydrodynamics | None = None):
        if not (math.isfinite(mass) and mass > 0):
            raise ParamError(f"boat.mass: {mass!r} is not allowed: allowed a positive mass [kg]")
        if not max_substep > 0:
            raise ParamError(f"max_substep: {max_substep!r} is not allowed: allowed > 0 s")
        self.mass = float(mass)
        self.inertia_body = np.asarray(inertia_body, float).reshape(3, 3)
        self.inertia_body_inv = np.linalg.inv(self.inertia_body)
        self.com = np.asarray(com, float).copy()
        self.gravity = np.asarray(gravity, float).copy()
        self.max_substep = float(max_substep)
        if orientation is None:
            q = np.array([1.0, 0.0, 0.0, 0.0])
        else:
            o = np.asarray(orientation, float)
            q = quat_from_matrix(o) if o.shape == (3, 3) else o / np.linalg.norm(o)
        self.orientation = q
        self.rotation = quat_to_matrix(q)
        self.com_world = np.asarray(position, float) + self.rotation @ self.com
        self.velocity = np.asarray(velocity, float).copy()
        self.momentum = self.inertia_world() @ np.asarray(angular_velocity, float)
        self.time = 0.0
        self.hydrodynamics = hydrodynamics

    @property
    def hydrodynamics(self) -> Hydrodynamics | None:
        """Added mass and radiation damping (None: none, the body alone)."""
        return self._hydrodynamics

    @hydrodynamics.setter
    def hydrodynamics(self, value: Hydrodynamics | None) -> None:
        self._hydrodynamics = value
        self._filter = None
        if value is not None:
            rigid = np.zeros((6, 6))
            rigid[:3, :3] = self.mass * np.eye(3)
            rigid[3:, 3:] = self.inertia_body
            total = rigid + value.added_mass
            if np.any(np.linalg.eigvalsh(0.5 * (total + total.T)) <= 0):
                raise ParamError("hydrodynamics.added_mass: M + A is not positive definite: "
                                 "allowed an added mass that leaves the body a positive mass")
            # M·(M + A)⁻¹, the force the rigid integrator needs for (M + A)⁻¹·f
            self._filter = rigid @ np.linalg.inv(total)

    def _hydrodynamic(self, force: np.ndarray, torque: np.ndarray) -> tuple[np.ndarray,
                                                                            np.ndarray]:
        """The force and torque (world, gravity included) the rigid step must apply so that the
        body accelerates as (M + A)⁻¹·(f − B·ν) (the module docstring)."""
        rot = self.rotation
        omega = rot @ (self.inertia_body_inv @ (rot.T @ self.momentum))
        f = np.concatenate([rot.T @ force, rot.T @ torque])
        nu = np.concatenate([rot.T @ self.velocity, rot.T @ omega])
        assert self._filter is not None and self._hydrodynamics is not None
        g = self._filter @ (f - self._hydrodynamics.damping @ nu)
        return rot @ g[:3], rot @ g[3:]

    @property
    def position(self) -> np.ndarray:
        """World position of the body frame's origin."""
        return self.com_world - self.rotation @ self.com

    @position.setter
    def position(self, value) -> None:
        self.com_world = np.asarray(value, float) + self.rotation @ self.com

    def set_orientation(self, q, keep: str = "origin") -> None:
        """Set the orientation, keeping the origin (``keep="origin"``) or the centre of mass
        (``"com"``) where it is; the angular velocity is kept."""
        omega = self.angular_velocity
        origin = self.position
        self.orientation = np.asarray(q, float) / length(q)
        self.rotation = quat_to_matrix(self.orientation)
        if keep == "origin":
            self.position = origin
        self.momentum = self.inertia_world() @ omega

    @property
    def angular_velocity(self) -> np.ndarray:
        """ω [rad/s], world frame: I_w⁻¹·L."""
        return self.rotation @ (self.inertia_body_inv @ (self.rotation.T @ self.momentum))

    @angular_velocity.setter
    def angular_velocity(self, value) -> None:
        self.momentum = self.inertia_world() @ np.asarray(value, float)

    def inertia_world(self) -> np.ndarray:
        """I_w = R·I_body·Rᵀ about the centre of mass."""
        return self.rotation @ self.inertia_body @ self.rotation.T

    def to_world(self, points_body) -> np.ndarray:
        """Body-frame points (..., 3) → world."""
        return np.asarray(points_body, float) @ self.rotation.T + self.position

    def point_velocity(self, points_world) -> np.ndarray:
        """Velocity of world points (..., 3) moving with the body: v + ω × (p − x_com)."""
        r = np.asarray(points_world, float) - self.com_world
        return self.velocity + cross(self.angular_velocity, r)

    def kinetic_energy(self) -> float:
        """½·m·v² + ½·ω·L [J]."""
        return 0.5 * self.mass * float(self.velocity @ self.velocity) \
            + 0.5 * float(self.angular_velocity @ self.momentum)

    def potential_energy(self, g=None) -> float:
        """Gravitational potential energy −m·g·x_com [J] (zero at y = 0 for g along −y)."""
        g = self.gravity if g is None else np.asarray(g, float)
        return -self.mass * float(g @ self.com_world)

    def finite(self) -> bool:
        return bool(np.all(np.isfinite(self.com_world)) and np.all(np.isfinite(self.velocity))
                    and np.all(np.isfinite(self.momentum))
                    and np.all(np.isfinite(self.orientation)))

    def copy(self) -> "RigidBody":
        b = RigidBody.__new__(RigidBody)
        b.__dict__ = {k: (v.copy() if isinstance(v, np.ndarray) else v)
                      for k, v in self.__dict__.items()}
        return b

    def substeps(self, dt: float) -> int:
        """How many equal substeps a frame of ``dt`` is cut into: ceil(dt / max_substep)."""
        return max(1, math.ceil(dt / self.max_substep - 1e-9))

    def step(self, dt: float, force_fn: ForceFn | None = None, substeps: int | None = None,
             hydrodynamics: bool = True) -> None:
        """Advance by ``dt`` [s] in ``substeps`` (default :meth:`substeps`) symplectic Euler
        substeps.  ``force_fn(body, t)`` → (force (3,) [N], torque about the centre of mass
        (3,) [N·m]), world frame, at the body's state and time t; gravity is added here.
        ``hydrodynamics=False``: this step without the added mass and damping."""
        if dt <= 0:
            return
        n = self.substeps(dt) if substeps is None else max(1, int(substeps))
        h = dt / n
        zero = np.zeros(3)
        hydro = self._filter is not None and hydrodynamics
        for _ in range(n):
            if force_fn is None:
                force, torque = zero, zero
            else:
                force, torque = force_fn(self, self.time)
            if not hydro:
                self.velocity = self.velocity + h * (np.asarray(force) / self.mass
                                                     + self.gravity)
                self.momentum = self.momentum + h * np.asarray(torque)
            else:
                force, torque = self._hydrodynamic(
                    np.asarray(force) + self.mass * self.gravity, np.asarray(torque, float))
                self.velocity = self.velocity + h * force / self.mass
                self.momentum = self.momentum + h * torque
            self.com_world = self.com_world + h * self.velocity
            # ω at the half-step orientation (midpoint): second order in h, so the energy of
            # a torque-free tumbling body drifts far less than with ω at the start.  (The
            # quaternion algebra on components, the matrix products and norms by the very
            # numpy calls of angular_velocity, quat_from_rotvec, quat_multiply, quat_to_matrix
            # and length: the same operations, without their conversions every substep.)
            rotation, momentum, inv = self.rotation, self.momentum, self.inertia_body_inv
            orientation = self.orientation.tolist()
            omega = rotation @ (inv @ (rotation.T @ momentum))
            half = _matrix(_product(_rotvec_components(0.5 * h * omega), orientation))
            omega = half @ (inv @ (half.T @ momentum))
            q = np.array(_product(_rotvec_components(omega * h), orientation))
            self.orientation = q / math.sqrt(q.dot(q))
            self.rotation = _matrix(self.orientation.tolist())
            self.time += h
