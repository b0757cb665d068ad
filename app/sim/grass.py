"""Grass of the toon village (spec/003 §2.9) — the numpy twins of ``glsl/grass/``: the wind
equations, the geometry-shader blade, the billboard frames, the placement on the terrain, the
generated tuft textures, the instanced blade mesh, the culling tiles and the triangle budgets.
No GL here; ``app/effects/grass`` uploads and draws what this module computes.

What a *blade* is, per method (the three methods are compared at equal ``grass.blades``):

* ``geometry`` — one pyramid per input triangle (spec/003 §2.9 a): **one blade per root
  triangle**, 6(S − 1) + 3 triangles for S sections;
* ``billboard`` — one crossed-billboard unit (spec/003 §2.9 b) shows one tuft texture, and each
  of the three generated tufts is painted with :data:`BLADES_PER_TUFT` blades, so N blades take
  ⌈N / BLADES_PER_TUFT⌉ units (whatever the number of crossed planes: the planes show the same
  tuft again from other angles, for volume, not more blades); 2 triangles per plane;
* ``instanced`` — one instance of the procedural blade mesh (Wohllaib 2021, Ghost of
  Tsushima's grass): **one blade per instance**, 2·segments − 1 triangles.

Units. The thesis's inspector values are Unity units of Unity's built-in plane, 10 units across
with 10 × 10 cells (the "plane with 200 triangles" of spec/003 §2.9 a). We take one Unity unit as
:data:`UNITY_UNIT` = 0.1 m (that plane as 1 m × 1 m, a cell of 0.1 m): Height 4.87 (Fig. 93)
becomes a 0.487 m blade on a root triangle with 0.1 m legs, and the billboard's quad side
(0.25 + Scale)·10 units (the repository's ``_Scale``) becomes (0.25 + Scale) m. Lengths below
are metres, world axes (+y up).

Wind. One wind for all three: the frame's ``wind`` slot ((x, z) m/s) when an effect filled it,
else ``grass.wind_direction`` and ``grass.wind_intensity``. The thesis's intensity w_i ∈ [0, 1]
(``_WindIntensity``) is taken from the speed as w_i = min(|wind| / :data:`FULL_WIND`, 1): a gale
of 20 m/s (Beaufort 8) bends the grass as far as the thesis's maximum intensity.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .maths import TWO_PI, compass_xz, merged_runs, rotation_y, wrap_two_pi
from .maths import safe_normalize as _normalize

Array = NDArray[np.float64]

#: metres per Unity unit of the thesis's test plane (see the module docstring)
UNITY_UNIT = 0.1
#: the geometry-shader blade's Height of spec/003 Fig. 93 (4.87 Unity units) [m]
GS_HEIGHT = round(4.87 * UNITY_UNIT, 6)
#: the legs of a root triangle: half a cell of Unity's 10 × 10 plane (1 unit) [m]
GS_ROOT_LEG = 1.0 * UNITY_UNIT
#: sections of the geometry-shader blade: the repository's range 1–4
GS_SECTIONS = (1, 4)
#: blades painted in each generated tuft texture (a billboard unit counts as this many blades)
BLADES_PER_TUFT = 8
#: the wind speed taken as the thesis's maximum intensity w_i = 1 [m/s]
FULL_WIND = 20.0
METHODS = ("geometry", "billboard", "instanced")
#: Billboard Y (spec/003 Fig. 98): the camera's up, the world's (0, 1, 0), their normalised mean
BILLBOARD_Y = ("camera", "world", "average")
#: plane angles of a unit: the document's θ_k = k·180°/n, or the repository's GrassGenerator
#: −90° + Δ/2 + k·Δ with Δ = 180°/n (−60°, 0°, 60° for three planes: Fig. 102's Angle −60)
ANGLE_LAYOUTS = ("document", "repository")
#: the repository's tints of the three ripenesses (GrassGenerator.cs): green (white), yellow,
#: brown — Unity's Color.white, Color.yellow, (1, 0.75, 0.25)
RIPENESS_TINTS = np.array([[1.0, 1.0, 1.0], [1.0, 0.92, 0.016], [1.0, 0.75, 0.25]])
#: the culling tiles of the instanced blades [m]
TILE = 8.0


def wind_intensity(speed: ArrayLike) -> Array:
    """The thesis's w_i ∈ [0, 1] of a wind speed [m/s]: min(speed / FULL_WIND, 1)."""
    return np.clip(np.asarray(speed, np.float64) / FULL_WIND, 0.0, 1.0)


def compass_direction(degrees: float) -> Array:
    """The (x, 0, z) unit vector a wind blowing toward ``degrees`` moves along (0° = north = −z,
    90° = east = +x: the wind effect's convention; the thesis's (1, 0, 0) is 90°)."""
    x, z = compass_xz(degrees)
    return np.array([x, 0.0, z])


@dataclass(frozen=True)
class GrassWind:
    """The wind the grass bends in: its direction (x, 0, z), the thesis's intensity w_i and the
    speed in m/s (the instanced blades' gusts travel at it)."""

    direction: tuple[float, float, float]
    intensity: float
    speed: float

    @property
    def velocity(self) -> tuple[float, float]:
        return (self.direction[0] * self.speed, self.direction[2] * self.speed)


def grass_wind(slot: Any, direction_deg: float, intensity: float) -> GrassWind:
    """The slot's wind ((x, z) m/s) when filled, else the grass's own direction and intensity
    (its speed then taken back through the same mapping)."""
    if slot is not None:
        w = np.asarray(slot, np.float64).reshape(2)
        if not np.all(np.isfinite(w)):
            raise ValueError(f"wind slot {slot!r} is not finite: allowed (x, z) m/s")
        speed = float(np.hypot(w[0], w[1]))
        d = (w[0] / speed, 0.0, w[1] / speed) if speed > 1e-9 else (1.0, 0.0, 0.0)
        return GrassWind(tuple(float(c) for c in d), float(wind_intensity(speed)), speed)
    d = compass_direction(direction_deg)
    i = float(np.clip(intensity, 0.0, 1.0))
    return GrassWind(tuple(float(c) for c in d), i, i * FULL_WIND)


def gs_phase(px: ArrayLike, pz: ArrayLike) -> Array:
    """spec/003 eq. 7.1: φ = |P_x + P_z| mod 2π (P the blade's centroid in object space)."""
    s = np.abs(np.asarray(px, np.float64) + np.asarray(pz, np.float64))
    return wrap_two_pi(s)


def gs_omega(phi: ArrayLike) -> Array:
    """spec/003 eq. 7.2: ω = 1 + φ/2π, in [1, 2)."""
    return 1.0 + np.asarray(phi, np.float64) / TWO_PI


def gs_amplitude(h: ArrayLike, wi: ArrayLike, omega: ArrayLike) -> Array:
    """spec/003 eq. 7.3: A = h·w_i·(ω − 1) (h the height above the root)."""
    return np.asarray(h, np.float64) * np.asarray(wi, np.float64) * (np.asarray(omega) - 1.0)


def gs_wind(h: ArrayLike, direction: ArrayLike, wi: float, phi: ArrayLike, omega: ArrayLike,
            t: float) -> Array:
    """spec/003 eq. 7.4: w = w_d·h·w_i·(1 + A·sin(ωt + φ)), y zeroed; (..., 3). The amplitude
    grows with h, so a root (h = 0) never moves. ``direction`` is w_d (its xz normalised)."""
    d = np.asarray(direction, np.float64) * np.array([1.0, 0.0, 1.0])
    d = _normalize(d, np.array([1.0, 0.0, 0.0]))
    h = np.asarray(h, np.float64)
    amp = gs_amplitude(h, wi, omega)
    k = h * wi * (1.0 + amp * np.sin(np.asarray(omega) * t + np.asarray(phi)))
    return np.asarray(k)[..., None] * d


def gs_triangles_per_blade(sections: int) -> int:
    """The triangle budget of one input triangle: 6 per intermediate section, 3 to the apex."""
    return 6 * (int(sections) - 1) + 3


def gs_max_vertices(sections: int) -> int:
    """max_vertices of the geometry shader for S sections (each triangle its own strip)."""
    return 3 * gs_triangles_per_blade(sections)


def _outward(tris: Array, axis: Array) -> Array:
    """Face normals cross(b − a, c − a), flipped to point away from ``axis`` points."""
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n = _normalize(n, np.array([0.0, 1.0, 0.0]))
    out = tris.mean(axis=1) - axis
    return np.where((np.sum(n * out, axis=-1) < 0.0)[:, None], -n, n)


def gs_blade(tri: ArrayLike, height: float, sections: int, direction: ArrayLike, wi: float,
             t: float, shrink: bool = True, repository_height: bool = False
             ) -> tuple[Array, Array]:
    """The twin of ``glsl/grass/blades_gs.geom`` for one root triangle (3, 3): the emitted
    triangles (6(S − 1) + 3, 3, 3) in the shader's order and their face normals.

    The base is shrunk halfway to the centroid first when ``shrink`` (the repository). Each
    section moves the ring's vertices toward its centroid by (centroid − vertex)/S and up by
    height/S; the last closes with three triangles to the apex. The rings are built at rest and
    each vertex is then displaced by the wind w of spec/003 eq. 7.4 at its own height above the
    root (so the base never moves and the apex moves by w(height)). ``repository_height`` adds
    ω Unity units to the height (the repository's (_Height + ω)/_Sections)."""
    tri = np.asarray(tri, np.float64).reshape(3, 3)
    s = int(sections)
    if not GS_SECTIONS[0] <= s <= GS_SECTIONS[1]:
        raise ValueError(f"sections={sections!r}: allowed an integer "
                         f"{GS_SECTIONS[0]}..{GS_SECTIONS[1]}")
    p = tri.mean(axis=0)
    phi = gs_phase(p[0], p[2])
    omega = gs_omega(phi)
    base = (p + tri) / 2.0 if shrink else tri.copy()
    h_total = float(height) + (float(omega) * UNITY_UNIT if repository_height else 0.0)
    step = np.array([0.0, h_total / s, 0.0])
    rings = [base]
    for _ in range(1, s):
        ring = rings[-1]
        rings.append(ring + (ring.mean(axis=0) - ring) / s + step)
    apex = rings[-1].mean(axis=0) + step
    moved = [r + gs_wind(k * h_total / s, direction, wi, phi, omega, t)
             for k, r in enumerate(rings)]
    moved[0] = rings[0]  # h = 0: w = 0 exactly
    tip = apex + gs_wind(h_total, direction, wi, phi, omega, t)
    tris, axis = [], []
    for k in range(1, s):
        lo, up = moved[k - 1], moved[k]
        mid = (lo.mean(axis=0) + up.mean(axis=0)) / 2.0
        for i in range(3):
            j = (i + 1) % 3
            tris += [[lo[i], up[j], up[i]], [lo[i], lo[j], up[j]]]
            axis += [mid, mid]
    lo = moved[-1]
    mid = (lo.mean(axis=0) + tip) / 2.0
    for i in range(3):
        tris.append([lo[i], lo[(i + 1) % 3], tip])
        axis.append(mid)
    arr = np.asarray(tris)
    return arr, _outward(arr, np.asarray(axis))


def billboard_up(mode: str, camera_up: ArrayLike) -> Array:
    """The plane's y vector for Billboard Y ``mode``: the camera's up u, the world's (0, 1, 0),
    or ŷ = u + (0, 1, 0) (spec/003 eq. 7.7) normalised (spec/003 eq. 7.8)."""
    u = _normalize(camera_up)
    if mode == "camera":
        return u
    if mode == "world":
        return np.array([0.0, 1.0, 0.0])
    if mode == "average":
        return _normalize(u + np.array([0.0, 1.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    raise ValueError(f"billboard y {mode!r}: allowed {', '.join(BILLBOARD_Y)}")


def plane_angles(n: int, layout: str = "document") -> Array:
    """θ_k of the n planes of a unit [degrees], 180°/n apart (module constant ANGLE_LAYOUTS)."""
    n = int(n)
    if not 1 <= n <= 4:
        raise ValueError(f"planes={n!r}: allowed an integer 1..4")
    step = 180.0 / n
    k = np.arange(n, dtype=np.float64)
    if layout == "document":
        return k * step
    if layout == "repository":
        return -90.0 + step / 2.0 + k * step
    raise ValueError(f"angle layout {layout!r}: allowed {', '.join(ANGLE_LAYOUTS)}")


@dataclass(frozen=True)
class BillboardFrame:
    """One plane's world frame: its right r' (spec/003 eq. 7.10), up y and normal n'."""

    right: Array
    up: Array
    normal: Array


def billboard_frame(centre: ArrayLike, camera_pos: ArrayLike, camera_up: ArrayLike,
                    camera_right: ArrayLike, mode: str, theta_deg: float = 0.0
                    ) -> BillboardFrame:
    """The twin of ``BillboardFrame`` in ``glsl/grass/billboard.vert``. The billboard faces the
    camera's *position* (spec/003 Fig. 96b): v = normalize(camera − P_c); y from
    :func:`billboard_up`; r = normalize(y × v) — the camera's right for a unit in the middle of
    the view (the r of spec/003 eq. 7.5), the camera's right itself when y ∥ v (a camera
    straight above with y = (0, 1, 0)); r' = R_y(θ)·r (spec/003 eq. 7.10); n' = r' × y
    (spec/003 eq. 7.11, spec/003 eq. 7.12: the thesis's r' × u), which for θ = 0 is v with its
    component along y removed."""
    c = np.asarray(centre, np.float64)
    back = np.cross(np.asarray(camera_right, np.float64), np.asarray(camera_up, np.float64))
    v = _normalize(np.asarray(camera_pos, np.float64) - c, _normalize(back))  # r × u = −forward
    y = billboard_up(mode, camera_up)
    r = _normalize(np.cross(y, v), _normalize(camera_right))
    r2 = rotation_y(math.radians(theta_deg)) @ r
    return BillboardFrame(r2, y, np.cross(r2, y))


def billboard_vertex(centre: ArrayLike, corner: ArrayLike, size: float,
                     frame: BillboardFrame) -> Array:
    """spec/003 eq. 7.5 and spec/003 eq. 7.6: x' = P_c + s·x·r', y' = P_c + s·y·ŷ — the corner
    (x, y) ∈ [−½, ½]² of the quad, s its side [m]."""
    x, y = float(corner[0]), float(corner[1])
    return np.asarray(centre, np.float64) + size * x * frame.right + size * y * frame.up


def bb_phase(sin_seed: ArrayLike) -> Array:
    """spec/003 eq. 7.13: φ = seed_sin (the unit's |x + z|, GrassGenerator.cs)."""
    return np.asarray(sin_seed, np.float64)


def bb_omega() -> float:
    """spec/003 eq. 7.14: ω = 1."""
    return 1.0


def bb_amplitude(intensity: ArrayLike, seed: ArrayLike) -> Array:
    """spec/003 eq. 7.15: A = I + seed."""
    return np.asarray(intensity, np.float64) + np.asarray(seed, np.float64)


def bb_sine(intensity: ArrayLike, seed: ArrayLike, sin_seed: ArrayLike, t: float) -> Array:
    """spec/003 eq. 7.16 and spec/003 eq. 7.17: s = (A/2)·sin(ωt + φ) = ((I + seed)/2)·
    sin(t + seed_sin). The document's scale factor is illegible; the repository's 0.5."""
    return 0.5 * bb_amplitude(intensity, seed) * np.sin(bb_omega() * t + bb_phase(sin_seed))


def bb_wind_offset(v: ArrayLike, direction: ArrayLike, intensity: float, seed: ArrayLike,
                   sin_seed: ArrayLike, t: float, size: float, bend: float,
                   steady: float) -> Array:
    """The offset of a billboard vertex at texture height v ∈ [0, 1] (..., 3):
    w_d·I·bend·size·v²·(steady + s). ``steady`` 1 is the document's (1 + s) (the geometry
    grass's form, spec/003 eq. 7.4), 3 the repository's h²·w_i·dir·(3 + s); ``bend`` the tip's
    offset per unit intensity in quad sides. Every plane of a unit shares seed and seed_sin,
    so their offsets are identical (spec/003 §2.9 b)."""
    d = _normalize(np.asarray(direction, np.float64) * np.array([1.0, 0.0, 1.0]),
                   np.array([1.0, 0.0, 0.0]))
    v = np.asarray(v, np.float64)
    k = intensity * bend * size * v * v * (steady + bb_sine(intensity, seed, sin_seed, t))
    return np.asarray(k)[..., None] * d


def ripeness_weights(wellness: float) -> Array:
    """GrassGenerator.cs's chances of green, yellow and brown: smoothstep(wellness), 0.1 and
    1 − smoothstep(wellness), normalised."""
    w = float(np.clip(wellness, 0.0, 1.0))
    green = w * w * (3.0 - 2.0 * w)
    p = np.array([green, 0.1, 1.0 - green])
    return p / p.sum()


def variety_weights(variety: float) -> Array:
    """GrassGenerator.cs's chances of the three tuft textures A, B, C: 0.5 + 0.5·variety, then
    1 − A/2 each for B and C, normalised."""
    v = float(np.clip(variety, 0.0, 1.0))
    a = 0.5 + 0.5 * v
    p = np.array([a, 1.0 - a / 2.0, 1.0 - a / 2.0])
    return p / p.sum()


@dataclass
class Units:
    """The crossed-billboard units: centre (on the ground, (U, 3)), _Seed ∈ [0, 1], _SinSeed,
    texture index (0..2) and tint (U, 3) of each."""

    roots: Array
    seed: Array
    sin_seed: Array
    texture: Array
    tint: Array

    def __len__(self) -> int:
        return len(self.roots)

    def instance_data(self) -> NDArray[np.float32]:
        """(U, 10) float32 rows: centre xyz, seed, seed_sin, texture, 0, tint rgb."""
        u = len(self)
        out = np.zeros((u, 10), np.float32)
        out[:, 0:3] = self.roots
        out[:, 3] = self.seed
        out[:, 4] = self.sin_seed
        out[:, 5] = self.texture
        out[:, 7:10] = self.tint
        return out


def units_for(blades: int) -> int:
    """Units that show ``blades`` blades: ⌈blades / BLADES_PER_TUFT⌉."""
    return -(-int(blades) // BLADES_PER_TUFT)


def make_units(roots: ArrayLike, seed: int, variety: float, wellness: float) -> Units:
    """Units at ``roots`` with the GrassGenerator's per-unit values: _Seed uniform in [0, 1]
    (one draw per unit, shared by all its planes), _SinSeed = |x + z| of its centre, the texture
    by Variety and the tint by Wellness (the repository's chances)."""
    r = np.asarray(roots, np.float64).reshape(-1, 3)
    rng = np.random.default_rng([int(seed), 0xB111])
    n = len(r)
    s = rng.random(n)
    tex = rng.choice(3, size=n, p=variety_weights(variety)) if n else np.zeros(0, int)
    ripe = rng.choice(3, size=n, p=ripeness_weights(wellness)) if n else np.zeros(0, int)
    return Units(r, s, np.abs(r[:, 0] + r[:, 2]), tex.astype(np.float64), RIPENESS_TINTS[ripe])


def meadow_cells(terrain: Any, cell: float | None = None) -> tuple[Array, float]:
    """Lower corners (C, 2) of the square cells of side ``cell`` that may hold grass: the
    terrain's grass_density sampled at half a cell, dilated by one cell (a sliver of meadow
    narrower than half a cell between zero samples may be missed: candidates are only drawn
    there). Returns the corners and the cell side."""
    x0, z0, x1, z1 = (float(b) for b in terrain.bounds)
    if not (x1 > x0 and z1 > z0):
        raise ValueError(f"terrain bounds {terrain.bounds!r}: allowed x_min < x_max, z_min < z_max")
    if cell is None:
        cell = max(1.0, max(x1 - x0, z1 - z0) / 400.0)
    nx = max(1, int(math.ceil((x1 - x0) / cell)))
    nz = max(1, int(math.ceil((z1 - z0) / cell)))
    sx = np.linspace(x0, x0 + nx * cell, 2 * nx + 1)
    sz = np.linspace(z0, z0 + nz * cell, 2 * nz + 1)
    xx, zz = np.meshgrid(sx, sz)
    d = np.asarray(terrain.grass_density(xx, zz), np.float64) > 0.0
    any_ = np.zeros((nz, nx), bool)
    for oz in range(3):
        for ox in range(3):
            any_ |= d[oz:oz + 2 * nz:2, ox:ox + 2 * nx:2]
    grown = any_.copy()
    grown[1:] |= any_[:-1]
    grown[:-1] |= any_[1:]
    grown[:, 1:] |= any_[:, :-1]
    grown[:, :-1] |= any_[:, 1:]
    jz, ix = np.nonzero(grown)
    return np.stack([x0 + ix * cell, z0 + jz * cell], axis=1), float(cell)


def sample_roots(terrain: Any, count: int, seed: int) -> Array:
    """``count`` roots (count, 3) by rejection sampling: points uniform over the meadow's cells
    (:func:`meadow_cells`), each kept with probability terrain.grass_density(x, z); y is
    terrain.height. Deterministic for a seed. A terrain with no grass gives no roots."""
    count = int(count)
    if count < 0:
        raise ValueError(f"blade count {count!r}: allowed an integer ≥ 0")
    if count == 0:
        return np.zeros((0, 3))
    corners, cell = meadow_cells(terrain)
    if len(corners) == 0:
        return np.zeros((0, 3))
    rng = np.random.default_rng([int(seed), 0x6A55])
    parts: list[Array] = []
    have = 0
    tries = 0
    while have < count and tries < 200:
        tries += 1
        m = int(min(4_000_000, max(4096, (count - have) * 1.6)))
        c = corners[rng.integers(0, len(corners), m)]
        p = c + rng.random((m, 2)) * cell
        keep = rng.random(m) < np.asarray(terrain.grass_density(p[:, 0], p[:, 1]), np.float64)
        if keep.any():
            parts.append(p[keep])
            have += int(keep.sum())
    if have == 0:
        return np.zeros((0, 3))
    xz = np.concatenate(parts)[:count]
    y = np.asarray(terrain.height(xz[:, 0], xz[:, 1]), np.float64)
    return np.stack([xz[:, 0], y, xz[:, 1]], axis=1)


def _on_ground(terrain: Any, xz: Array) -> Array:
    y = np.asarray(terrain.height(xz[..., 0], xz[..., 1]), np.float64)
    return np.stack([xz[..., 0], y, xz[..., 1]], axis=-1)


def scatter_triangles(terrain: Any, roots: ArrayLike, seed: int,
                      leg: float = GS_ROOT_LEG) -> Array:
    """One root triangle per blade (N, 3, 3): the thesis's half cell (a right triangle with
    legs ``leg``), turned by a random angle about y, centroid at the root, corners on the
    ground."""
    r = np.asarray(roots, np.float64).reshape(-1, 3)
    rng = np.random.default_rng([int(seed), 0x7121])
    a = rng.random(len(r)) * TWO_PI
    shape = np.array([[0.0, 0.0], [leg, 0.0], [0.0, leg]]) - np.array([leg, leg]) / 3.0
    c, s = np.cos(a)[:, None], np.sin(a)[:, None]
    x = shape[None, :, 0] * c - shape[None, :, 1] * s
    z = shape[None, :, 0] * s + shape[None, :, 1] * c
    xz = np.stack([r[:, None, 0] + x, r[:, None, 2] + z], axis=-1)
    return _on_ground(terrain, xz)


def grid_triangles(terrain: Any, count: int, seed: int) -> Array:
    """The thesis's own failure as input (spec/003 §2.9 a: "blades placed regularly, depends
    on the mesh"): the triangles (count, 3, 3) of a regular grid mesh over the meadow, each cell
    split along its diagonal, keeping those whose centroid has grass_density ≥ ½; the cell is
    sized so that about ``count`` remain, and the excess is dropped at random."""
    count = int(count)
    if count <= 0:
        return np.zeros((0, 3, 3))
    corners, cell = meadow_cells(terrain)
    if len(corners) == 0:
        return np.zeros((0, 3, 3))
    lo = corners.min(axis=0)
    hi = corners.max(axis=0) + cell
    area = len(corners) * cell * cell
    a = math.sqrt(2.0 * area / count)
    tri = np.zeros((0, 3, 3))
    for _ in range(8):
        nx = max(1, int((hi[0] - lo[0]) / a))
        nz = max(1, int((hi[1] - lo[1]) / a))
        if nx * nz > 12_000_000:
            break
        gx = lo[0] + np.arange(nx) * a
        gz = lo[1] + np.arange(nz) * a
        xx, zz = np.meshgrid(gx, gz)
        p00 = np.stack([xx, zz], -1).reshape(-1, 2)
        p10, p01, p11 = p00 + (a, 0.0), p00 + (0.0, a), p00 + (a, a)
        cand = np.concatenate([np.stack([p00, p01, p11], 1), np.stack([p00, p11, p10], 1)])
        c = cand.mean(axis=1)
        keep = np.asarray(terrain.grass_density(c[:, 0], c[:, 1]), np.float64) >= 0.5
        tri = cand[keep]
        if len(tri) >= count:
            break
        a *= math.sqrt(max(len(tri), 1) / count) * 0.97
    if len(tri) > count:
        rng = np.random.default_rng([int(seed), 0x621D])
        tri = tri[np.sort(rng.choice(len(tri), count, replace=False))]
    return _on_ground(terrain, tri)


def _bezier2(p0: Array, p1: Array, p2: Array, t: Array) -> Array:
    s = 1.0 - t
    return (s * s)[:, None] * p0 + (2 * s * t)[:, None] * p1 + (t * t)[:, None] * p2


#: the blades' width at the root in each tuft, in texture widths
TUFT_WIDTH = (0.07, 0.08, 0.10)


def tuft_texture(kind: int, size: int = 128, seed: int = 5) -> NDArray[np.float32]:
    """Tuft ``kind`` (0 tall and straight, 1 a curved fan, 2 short and wide) as a size × size
    RGBA float32 image of :data:`BLADES_PER_TUFT` tapered blades with an anti-aliased alpha
    (linear colour; row j is v = (j + ½)/size, bottom first, as GL stores it). The roots stand
    on the bottom row; no blade reaches the top 4 % (the repository cuts alpha at v > 0.95)."""
    if kind not in (0, 1, 2):
        raise ValueError(f"tuft kind {kind!r}: allowed 0, 1, 2")
    rng = np.random.default_rng([seed, kind])
    n = BLADES_PER_TUFT
    px = (np.arange(size) + 0.5) / size
    alpha = np.zeros((size, size))
    colour = np.zeros((size, size, 3))
    samples = 24
    t = np.linspace(0.0, 1.0, samples)
    for b in range(n):
        root_x = 0.5 + (b - (n - 1) / 2.0) / n * (0.55 if kind != 1 else 0.35) \
            + rng.uniform(-0.03, 0.03)
        width = TUFT_WIDTH[kind]
        if kind == 0:
            height, lean = rng.uniform(0.72, 0.94), rng.uniform(-0.12, 0.12)
        elif kind == 1:
            height = rng.uniform(0.55, 0.85)
            lean = (root_x - 0.5) * 1.4 + rng.uniform(-0.06, 0.06)
        else:
            height, lean = rng.uniform(0.40, 0.66), rng.uniform(-0.25, 0.25)
        p0 = np.array([root_x, 0.0])
        p2 = np.array([np.clip(root_x + lean, 0.1, 0.9), height])
        p1 = np.array([root_x + lean * 0.2, height * 0.6])
        curve = _bezier2(p0, p1, p2, t)
        half = 0.5 * width * (1.0 - t) ** 0.9 + 1e-4
        # only the pixels of the blade's box (grown by its half width and two pixels)
        grow = half.max() + 2.0 / size
        i0, i1 = (np.searchsorted(px, curve[:, 0].min() - grow),
                  np.searchsorted(px, curve[:, 0].max() + grow))
        j0, j1 = (np.searchsorted(px, curve[:, 1].min() - grow),
                  np.searchsorted(px, curve[:, 1].max() + grow))
        gx, gy = np.meshgrid(px[i0:i1], px[j0:j1])
        pix = np.stack([gx.ravel(), gy.ravel()], axis=1)
        a, bvec = curve[:-1], curve[1:] - curve[:-1]
        rel = pix[:, None, :] - a[None]
        seg_len2 = np.maximum(np.sum(bvec * bvec, axis=1), 1e-12)
        u = np.clip(np.sum(rel * bvec[None], axis=2) / seg_len2[None], 0.0, 1.0)
        d = np.linalg.norm(rel - u[..., None] * bvec[None], axis=2)
        w = half[:-1][None] + u * (half[1:] - half[:-1])[None]
        cover = np.clip((w - d) * size + 0.5, 0.0, 1.0)
        k = np.argmax(cover, axis=1)
        rows = np.arange(len(pix))
        blade_a = cover[rows, k].reshape(gx.shape)
        along = ((k + u[rows, k]) / (samples - 1)).reshape(gx.shape)
        shade = rng.uniform(0.8, 1.15)
        base = np.array([0.10, 0.28, 0.035]) * shade
        tip = np.array([0.30, 0.55, 0.09]) * shade
        c = base + along[..., None] * (tip - base)
        box_a = alpha[j0:j1, i0:i1]
        over = blade_a > box_a
        colour[j0:j1, i0:i1] = np.where(over[..., None], c, colour[j0:j1, i0:i1])
        alpha[j0:j1, i0:i1] = np.maximum(box_a, blade_a)
    out = np.zeros((size, size, 4), np.float32)
    out[..., :3] = colour
    out[..., 3] = alpha
    out[px > 0.96, :, 3] = 0.0
    return out


def tuft_atlas(size: int = 128) -> NDArray[np.float32]:
    """The three tufts side by side (size × 3·size RGBA): texture k spans u ∈ [k/3, (k+1)/3]."""
    return np.concatenate([tuft_texture(k, size) for k in range(3)], axis=1)


def side_coverage(alpha: ArrayLike, angles_deg: ArrayLike, cutoff: float = 0.2,
                  width: int = 256) -> float:
    """Screen coverage of a unit of planes at ``angles_deg`` seen from the side, far away (an
    orthographic view along the plane at θ = 0's normal, its bottom and top spanning the
    image's height): the union of each plane's alpha > cutoff squeezed to |cos θ| of its width
    about the centre (mirrored when cos θ < 0). The numpy twin of the bench's rendered figure."""
    a = np.asarray(alpha, np.float64) > cutoff  # (H, W) rows bottom first
    h, w = a.shape
    covered = np.zeros((h, width), bool)
    xs = (np.arange(width) + 0.5) / width - 0.5  # screen x in quad sides
    for th in np.radians(np.asarray(angles_deg, np.float64)):
        c = math.cos(th)
        if abs(c) < 1e-3:
            continue
        u = xs / c + 0.5
        inside = (u >= 0.0) & (u < 1.0)
        col = np.clip((u * w).astype(int), 0, w - 1)
        covered |= a[:, col] & inside[None, :]
    return float(covered.mean())


def blade_strip(segments: int) -> NDArray[np.float32]:
    """The instanced blade mesh as a triangle strip (2·segments + 1, 2): (t along the blade,
    side −1/+1), the tip a single vertex (side 0) — 2·segments − 1 triangles."""
    s = int(segments)
    if not 1 <= s <= 16:
        raise ValueError(f"blade segments {segments!r}: allowed an integer 1..16")
    rows = []
    for i in range(s):
        t = i / s
        rows += [(t, -1.0), (t, 1.0)]
    rows.append((1.0, 0.0))
    return np.asarray(rows, np.float32)


def blade_triangles(segments: int) -> int:
    return 2 * int(segments) - 1


def cubic_bezier(p0: ArrayLike, p1: ArrayLike, p2: ArrayLike, p3: ArrayLike,
                 t: ArrayLike) -> Array:
    """B(t) = (1−t)³p0 + 3(1−t)²t p1 + 3(1−t)t² p2 + t³p3 (..., 3)."""
    t = np.asarray(t, np.float64)[..., None]
    s = 1.0 - t
    return (s ** 3 * np.asarray(p0) + 3 * s * s * t * np.asarray(p1)
            + 3 * s * t * t * np.asarray(p2) + t ** 3 * np.asarray(p3))


@dataclass
class Tiles:
    """Blades sorted into square tiles of side TILE: ``order`` sorts the roots, tile k holds
    sorted blades start[k] .. start[k] + count[k], inside the box lo[k] .. hi[k]."""

    order: NDArray[np.int64]
    start: NDArray[np.int64]
    count: NDArray[np.int64]
    lo: Array
    hi: Array


def make_tiles(roots: ArrayLike, reach: float, tile: float = TILE) -> Tiles:
    """Tiles of the roots, each box grown by ``reach`` (the tallest blade and its bend)."""
    r = np.asarray(roots, np.float64).reshape(-1, 3)
    if len(r) == 0:
        z = np.zeros(0, np.int64)
        return Tiles(z, z, z, np.zeros((0, 3)), np.zeros((0, 3)))
    ij = np.floor(r[:, [0, 2]] / tile).astype(np.int64)
    ij -= ij.min(axis=0)
    key = ij[:, 1] * (int(ij[:, 0].max()) + 1) + ij[:, 0]
    order = np.argsort(key, kind="stable")
    ks = key[order]
    bounds = np.flatnonzero(np.diff(ks)) + 1
    start = np.concatenate([[0], bounds]).astype(np.int64)
    count = np.diff(np.concatenate([start, [len(ks)]])).astype(np.int64)
    rs = r[order]
    lo = np.minimum.reduceat(rs, start, axis=0) - reach
    hi = np.maximum.reduceat(rs, start, axis=0) + reach
    return Tiles(order, start, count, lo, hi)


def frustum_planes(view_proj: ArrayLike) -> Array:
    """The six planes (6, 4) a·x + b·y + c·z + d ≥ 0 inside the frustum of a view-projection
    (M @ v convention; Gribb and Hartmann's rows), normalised."""
    m = np.asarray(view_proj, np.float64)
    planes = np.array([m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2],
                       m[3] - m[2]])
    return planes / np.linalg.norm(planes[:, :3], axis=1, keepdims=True)


def tile_distances(tiles: Tiles, camera_pos: ArrayLike) -> Array:
    """Per tile: the distance from ``camera_pos`` to the nearest point of its box (0 inside)."""
    cam = np.asarray(camera_pos, np.float64)
    nearest = np.clip(cam[None, :], tiles.lo, tiles.hi)
    return np.linalg.norm(nearest - cam[None, :], axis=1)


def tile_lods(tiles: Tiles, view_proj: ArrayLike, camera_pos: ArrayLike, lod_distance: float,
              draw_distance: float) -> NDArray[np.int64]:
    """Per tile: 0 near (full segments), 1 far (the LOD mesh), −1 culled — outside the frustum
    (the box entirely behind one plane) or farther than ``draw_distance`` (the box's nearest
    point)."""
    if len(tiles.start) == 0:
        return np.zeros(0, np.int64)
    planes = frustum_planes(view_proj)
    pos_corner = np.where(planes[None, :, :3] >= 0.0, tiles.hi[:, None, :], tiles.lo[:, None, :])
    inside = np.all(np.sum(planes[None, :, :3] * pos_corner, axis=2) + planes[None, :, 3]
                    >= 0.0, axis=1)
    dist = tile_distances(tiles, camera_pos)
    lod = np.where(dist <= lod_distance, 0, 1)
    return np.where(inside & (dist <= draw_distance), lod, -1).astype(np.int64)


def draw_runs(tiles: Tiles, lods: ArrayLike, lod: int,
              distances: ArrayLike | None = None) -> list[tuple[int, int]]:
    """(first blade, count) runs of the tiles with LOD ``lod``, consecutive ones merged; with
    ``distances`` (:func:`tile_distances`) the runs go front to back — nearest tile first, two
    tiles merged only when they are neighbours in that order and in the buffer — so the
    depth test rejects what nearer blades hide before it is shaded."""
    picked = np.flatnonzero(np.asarray(lods) == lod)
    if distances is not None and len(picked):
        picked = picked[np.argsort(np.asarray(distances)[picked], kind="stable")]
    return merged_runs(tiles.start, tiles.count, picked)


def triangles(method: str, blades: int, sections: int = 3, planes: int = 3,
              segments: int = 6) -> int:
    """Triangles drawn for ``blades`` blades, every blade drawn (no culling)."""
    if method == "geometry":
        return int(blades) * gs_triangles_per_blade(sections)
    if method == "billboard":
        return units_for(blades) * int(planes) * 2
    if method == "instanced":
        return int(blades) * blade_triangles(segments)
    raise ValueError(f"grass method {method!r}: allowed {', '.join(METHODS)}")
