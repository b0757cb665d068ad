"""The surfaces lab's analytic scene (spec/003 §2.4–2.8): a room-sized box with test spheres,
cylinders, boxes (an occluder hovering over the floor, a crate standing on it) and alpha-
textured quads (fence, leaves, smoke, a blue α = 0.5 pane, two intersecting panes).

One description serves the GL lab (:func:`mesh` builds a :class:`~app.sim.lab_meshes.LabMesh`
of each primitive) and the numpy references (:func:`ray_cast` and :func:`occluded` intersect
the same primitives exactly), so a shadow map, a probe or a transparency method is measured
against the very scene it draws. No GL here.

Units are metres; y is up; the floor is y = 0. The room's faces look inward.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from . import lab_meshes
from .lab_meshes import LabMesh

#: alpha textures of the quads (:func:`alpha_texture`)
ALPHA_KINDS = ("solid", "gradient", "fence", "leaves", "smoke")


@dataclass(frozen=True)
class Sphere:
    name: str
    centre: tuple[float, float, float]
    radius: float
    albedo: tuple[float, float, float] = (0.8, 0.8, 0.8)
    metallic: float = 0.0
    smoothness: float = 0.5
    ior: float = 1.52


@dataclass(frozen=True)
class Box:
    """An axis-aligned box ``centre`` ± ``half``."""

    name: str
    centre: tuple[float, float, float]
    half: tuple[float, float, float]
    albedo: tuple[float, float, float] = (0.7, 0.7, 0.7)


@dataclass(frozen=True)
class Cylinder:
    """An upright capped cylinder standing on ``base`` (the centre of its bottom cap)."""

    name: str
    base: tuple[float, float, float]
    radius: float
    height: float
    albedo: tuple[float, float, float] = (0.7, 0.7, 0.7)


@dataclass(frozen=True)
class Quad:
    """A two-sided rectangle ``centre`` ± ``u`` ± ``v`` (half-extent vectors); uv (0, 0) at
    centre − u − v, (1, 1) at centre + u + v. Its alpha is ``alpha_texture(alpha)`` ×
    ``opacity``."""

    name: str
    centre: tuple[float, float, float]
    u: tuple[float, float, float]
    v: tuple[float, float, float]
    albedo: tuple[float, float, float] = (0.8, 0.8, 0.8)
    alpha: str = "solid"
    opacity: float = 1.0


@dataclass(frozen=True)
class Room:
    """The room's box (its inside is seen): floor at lo.y, the box-projected probe's bounds."""

    lo: tuple[float, float, float] = (-4.0, 0.0, -4.0)
    hi: tuple[float, float, float] = (4.0, 3.0, 4.0)
    albedo: tuple[float, float, float] = (0.5, 0.48, 0.44)

    @property
    def centre(self) -> np.ndarray:
        return (np.asarray(self.lo, float) + np.asarray(self.hi, float)) / 2


@dataclass
class SurfacesScene:
    room: Room = field(default_factory=Room)
    spheres: list[Sphere] = field(default_factory=list)
    boxes: list[Box] = field(default_factory=list)
    cylinders: list[Cylinder] = field(default_factory=list)
    quads: list[Quad] = field(default_factory=list)
    #: where the reflection probe is rendered from (the room's centre by default)
    probe_position: tuple[float, float, float] = (0.0, 1.5, 0.0)

    def solids(self) -> list:
        return [*self.spheres, *self.boxes, *self.cylinders]

    def objects(self) -> list:
        return [*self.solids(), *self.quads]

    def get(self, name: str):
        for obj in self.objects():
            if obj.name == name:
                return obj
        names = ", ".join(o.name for o in self.objects())
        raise KeyError(f"no object {name!r} in the surfaces scene: allowed {names}")


def default_scene() -> SurfacesScene:
    """The lab's layout: three test spheres in a row (a metal mirror, glass, a dielectric), two
    cylinders, an occluder slab 1.2 m over the floor, a crate on the floor (its contact line
    shows Peter Panning), and the alpha quads of §2.4."""
    return SurfacesScene(
        spheres=[Sphere("mirror", (-1.6, 0.6, 0.0), 0.6, (0.95, 0.93, 0.88), 1.0, 1.0),
                 Sphere("glass", (0.0, 0.6, 0.6), 0.6, (0.9, 0.95, 1.0), 0.0, 1.0, 1.52),
                 Sphere("dielectric", (1.6, 0.6, 0.0), 0.6, (0.75, 0.2, 0.15), 0.0, 0.5)],
        boxes=[Box("occluder", (0.6, 1.2, -1.6), (0.6, 0.05, 0.45), (0.6, 0.62, 0.7)),
               Box("crate", (-1.6, 0.4, -2.2), (0.4, 0.4, 0.4), (0.55, 0.38, 0.2))],
        cylinders=[Cylinder("pillar", (2.7, 0.0, -2.4), 0.3, 1.8, (0.7, 0.7, 0.72)),
                   Cylinder("post", (-2.8, 0.0, 1.6), 0.2, 1.2, (0.5, 0.55, 0.4))],
        quads=[Quad("fence", (-2.6, 0.6, -0.6), (0.0, 0.0, 0.7), (0.0, 0.6, 0.0),
                    (0.55, 0.4, 0.25), "fence"),
               Quad("leaves", (2.7, 0.9, 0.9), (0.0, 0.0, 0.6), (0.0, 0.6, 0.0),
                    (0.25, 0.55, 0.2), "leaves"),
               Quad("smoke", (0.0, 1.5, -3.0), (0.9, 0.0, 0.0), (0.0, 1.0, 0.0),
                    (0.8, 0.8, 0.82), "smoke"),
               Quad("blue", (-1.0, 0.8, 2.0), (0.8, 0.0, 0.0), (0.0, 0.7, 0.0),
                    (0.2, 0.35, 0.9), "solid", 0.5),
               Quad("cross_a", (1.4, 0.7, 2.1), (0.55, 0.0, 0.35), (0.0, 0.6, 0.0),
                    (0.9, 0.25, 0.2), "solid", 0.5),
               Quad("cross_b", (1.4, 0.7, 2.1), (0.55, 0.0, -0.35), (0.0, 0.6, 0.0),
                    (0.2, 0.8, 0.3), "solid", 0.5)])


def alpha_texture(kind: str, size: int = 256) -> np.ndarray:
    """A size² RGBA float32 texture (row 0 at v = 0): white RGB (the quad's albedo tints it)
    and the alpha of ``kind`` — solid 1; gradient α = u (the cutoff test's ramp, spec/003 §2.4);
    fence: bars and rails, α ∈ {0, 1}; leaves: soft-edged leaf blobs (α ramps 0 → 1 over a
    few texels, the case where ``alpha == 0`` leaves stray fragments); smoke: a smooth puff."""
    if kind not in ALPHA_KINDS:
        raise ValueError(f"alpha texture {kind!r}: allowed {', '.join(ALPHA_KINDS)}")
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    if kind == "solid":
        a = np.ones_like(x)
    elif kind == "gradient":
        a = x.copy()
    elif kind == "fence":
        bars = (np.abs(((x * 5.0) % 1.0) - 0.5) < 0.16)
        rails = (np.abs(y - 0.3) < 0.05) | (np.abs(y - 0.75) < 0.05)
        a = (bars | rails).astype(np.float64)
    elif kind == "leaves":
        rng = np.random.default_rng(3)
        a = np.zeros_like(x)
        for cx, cy, r, t in zip(rng.uniform(0.1, 0.9, 18), rng.uniform(0.1, 0.9, 18),
                                rng.uniform(0.08, 0.16, 18), rng.uniform(0, np.pi, 18)):
            dx, dy = x - cx, y - cy
            c, s = np.cos(t), np.sin(t)
            e = ((c * dx + s * dy) / r) ** 2 + ((-s * dx + c * dy) / (0.45 * r)) ** 2
            a = np.maximum(a, np.clip((1.0 - e) * 6.0, 0.0, 1.0))
    else:  # smoke
        r2 = (x - 0.5) ** 2 + (y - 0.45) ** 2
        wisp = 0.5 + 0.5 * np.sin(9.0 * x + 5.0 * y) * np.sin(7.0 * y - 3.0 * x)
        a = np.clip(np.exp(-r2 / 0.06) * (0.6 + 0.4 * wisp), 0.0, 1.0)
    out = np.ones((size, size, 4), np.float32)
    out[..., 3] = a
    return out


def _cylinder(c: Cylinder, segments: int = 48) -> LabMesh:
    b = lab_meshes._Builder()
    base = np.asarray(c.base, float)
    t = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    ring = np.stack([np.cos(t), np.zeros_like(t), -np.sin(t)], 1)
    p = np.stack([base + ring * c.radius, base + ring * c.radius + [0, c.height, 0]])
    n = np.stack([ring, ring])
    uv = np.stack([np.stack([t / (2 * np.pi), np.zeros_like(t)], 1),
                   np.stack([t / (2 * np.pi), np.ones_like(t)], 1)])
    b.grid(p, n, uv)
    for y, sign in ((0.0, -1.0), (c.height, 1.0)):
        centre = base + [0, y, 0]
        rim = centre + ring[:-1] * c.radius
        pts = np.vstack([centre, rim])
        k = np.arange(segments)
        tri = np.stack([np.zeros(segments, int), 1 + k, 1 + (k + 1) % segments], 1)
        if sign < 0:
            tri = tri[:, [0, 2, 1]]
        uvs = 0.5 + 0.5 * np.vstack([[0, 0], ring[:-1][:, [0, 2]]])
        b.add(pts, np.tile([0, sign, 0], (len(pts), 1)), uvs, tri)
    return b.mesh(c.name)


def mesh(obj) -> LabMesh:
    """The triangle mesh of one primitive (world space, no model matrix needed): spheres of
    24 × 48, boxes with hard edges, capped cylinders, one-sided quads (draw them without face
    culling), the room as its six faces turned inward."""
    if isinstance(obj, Sphere):
        lifted = np.asarray(obj.centre, float) - (0.0, obj.radius, 0.0)
        return replace(lab_meshes.transformed(lab_meshes.sphere(obj.radius), 1.0, lifted),
                       name=obj.name)
    b = lab_meshes._Builder()
    if isinstance(obj, Box):
        c, h = np.asarray(obj.centre, float), np.asarray(obj.half, float)
        b.box(c - h, c + h)
        return b.mesh(obj.name)
    if isinstance(obj, Cylinder):
        return _cylinder(obj)
    if isinstance(obj, Quad):
        c, u, v = (np.asarray(a, float) for a in (obj.centre, obj.u, obj.v))
        b.quad(c - u - v, c + u - v, c + u + v, c - u + v)
        return b.mesh(obj.name)
    if isinstance(obj, Room):
        b.box(obj.lo, obj.hi)
        m = b.mesh("room")
        return LabMesh("room", m.positions, -m.normals, -m.smooth_normals, m.uvs,
                       m.tangents * np.array([-1, -1, -1, 1], np.float32),
                       m.indices[:, [0, 2, 1]].copy())
    raise TypeError(f"no mesh for {type(obj).__name__}: allowed Sphere, Box, Cylinder, Quad, Room")


def _hit_sphere(o, d, s: Sphere):
    """Nearest t > 0 of |o + t d − C| = r for any direction length: a t² + 2 b t + c = 0."""
    oc = o - np.asarray(s.centre)
    a = np.einsum("...i,...i", d, d)
    b = np.einsum("...i,...i", oc, d)
    c = np.einsum("...i,...i", oc, oc) - s.radius ** 2
    disc = b * b - a * c
    root = np.sqrt(np.maximum(disc, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (-b - root) / a, (-b + root) / a
    t = np.where(t0 > 0, t0, t1)
    return np.where((disc >= 0) & (a > 0) & (t > 0), t, np.inf)


def _slab(o, d, lo, hi):
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / np.where(np.abs(d) < 1e-20, 1e-20, d)
        t0, t1 = (lo - o) * inv, (hi - o) * inv
    return np.minimum(t0, t1).max(-1), np.maximum(t0, t1).min(-1)


def _hit_box(o, d, bx: Box):
    c, h = np.asarray(bx.centre), np.asarray(bx.half)
    tn, tf = _slab(o, d, c - h, c + h)
    t = np.where(tn > 0, tn, tf)
    return np.where((tf >= np.maximum(tn, 0)) & (t > 0), t, np.inf)


def _hit_cylinder(o, d, cy: Cylinder):
    base = np.asarray(cy.base)
    q = o - base
    a = d[..., 0] ** 2 + d[..., 2] ** 2
    b = q[..., 0] * d[..., 0] + q[..., 2] * d[..., 2]
    c = q[..., 0] ** 2 + q[..., 2] ** 2 - cy.radius ** 2
    disc = b * b - a * c
    best = np.full(a.shape, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        for sign in (-1.0, 1.0):
            t = (-b + sign * np.sqrt(np.maximum(disc, 0))) / a
            y = q[..., 1] + t * d[..., 1]
            ok = (disc >= 0) & (a > 1e-20) & (t > 0) & (y >= 0) & (y <= cy.height)
            best = np.where(ok & (t < best), t, best)
        for cap in (0.0, cy.height):
            t = (cap - q[..., 1]) / d[..., 1]
            px, pz = q[..., 0] + t * d[..., 0], q[..., 2] + t * d[..., 2]
            ok = (t > 0) & (px * px + pz * pz <= cy.radius ** 2)
            best = np.where(ok & (t < best), t, best)
    return best


def _hit_quad(o, d, qd: Quad):
    c, u, v = (np.asarray(a, float) for a in (qd.centre, qd.u, qd.v))
    n = np.cross(u, v)
    denom = d @ n
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((c - o) @ n) / denom
    p = o + t[..., None] * d - c
    su, sv = (p @ u) / (u @ u), (p @ v) / (v @ v)
    ok = (np.abs(denom) > 1e-12) & (t > 0) & (np.abs(su) <= 1) & (np.abs(sv) <= 1)
    return np.where(ok, t, np.inf)


def _hit(o, d, obj):
    if isinstance(obj, Sphere):
        return _hit_sphere(o, d, obj)
    if isinstance(obj, Box):
        return _hit_box(o, d, obj)
    if isinstance(obj, Cylinder):
        return _hit_cylinder(o, d, obj)
    return _hit_quad(o, d, obj)


def ray_cast(scene: SurfacesScene, origins, directions, quads: bool = False, room: bool = True):
    """The nearest hit of each ray: (t (...), index (...)) — index into ``scene.objects()`` (or
    ``scene.solids()`` when ``quads`` is false), −1 for the room's inside faces, −2 for a miss
    (t = inf). Directions need not be unit length (t is in their units)."""
    o = np.asarray(origins, np.float64)
    d = np.asarray(directions, np.float64)
    o, d = np.broadcast_arrays(o, d)
    objs = scene.objects() if quads else scene.solids()
    best = np.full(o.shape[:-1], np.inf)
    index = np.full(o.shape[:-1], -2, np.int64)
    for i, obj in enumerate(objs):
        t = _hit(o, d, obj)
        closer = t < best
        best = np.where(closer, t, best)
        index = np.where(closer, i, index)
    if room:
        _, tf = _slab(o, d, np.asarray(scene.room.lo, float), np.asarray(scene.room.hi, float))
        closer = (tf > 0) & (tf < best)
        best = np.where(closer, tf, best)
        index = np.where(closer, -1, index)
    return best, index


def occluded(scene: SurfacesScene, points, to_light, max_t=np.inf, eps: float = 1e-4,
             room: bool = False) -> np.ndarray:
    """True where the segment from each point toward the light (``to_light``: a direction for
    a directional light, or the vector to the light with ``max_t`` = 1) hits a solid first —
    the exact visibility the shadow maps are measured against. ``eps`` starts the ray just off
    the surface. The room's walls block only with ``room``."""
    p = np.asarray(points, np.float64)
    d = np.asarray(to_light, np.float64)
    t, index = ray_cast(scene, p + eps * d / np.linalg.norm(d, axis=-1, keepdims=True), d,
                        room=room)
    return (index != -2) & (t < max_t)
