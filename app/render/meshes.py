"""Triangle meshes built with numpy (positions, normals, indices) and drawn with one VAO each.

Object space is what procedural solid textures are anchored to (spec/004 §1.6: the vertex
shader passes the untransformed position), so each mesh is centred on its origin.

Tessellation from the projected size (:func:`auto_tessellation`): a curved mesh's segment
counts are chosen so that an edge spans about ``edge_px`` pixels on screen, from a few levels
(``TESSELLATION_LEVELS``, each twice the one before), so a small object is not shaded in 2×2
quads of sub-pixel triangles and the mesh is rebuilt only when its level changes. The
silhouette of a circle of radius r pixels drawn with n segments is off by its sagitta,
r (1 − cos π/n) ≈ edge² / (8 r) pixels: edges of 6 px on a circle of 25 px miss by 0.2 px.
``FIXED_TESSELLATION`` is the former fixed choice, kept for comparison.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class MeshData:
    name: str
    positions: np.ndarray  # (n, 3) float32
    normals: np.ndarray  # (n, 3) float32
    indices: np.ndarray  # (m,) uint32, triangles

    def interleaved(self) -> bytes:
        return np.hstack([self.positions, self.normals]).astype("f4").tobytes()


def cube(size: float = 1.0) -> MeshData:
    """A cube of side ``size`` with flat faces (24 vertices), like Unity's default cube."""
    h = size / 2
    pos, nor, idx = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            n = np.zeros(3)
            n[axis] = sign
            u = np.zeros(3)
            u[(axis + 1) % 3] = 1.0
            v = np.cross(n, u)
            base = len(pos)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos.append(n * h + u * a * h + v * b * h)
                nor.append(n)
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return MeshData("cube", np.array(pos, "f4"), np.array(nor, "f4"), np.array(idx, "u4"))


def uv_sphere(radius: float = 0.5, rings: int = 48, segments: int = 96) -> MeshData:
    """A sphere of diameter 1 by default, like Unity's default sphere."""
    theta = np.linspace(0, math.pi, rings + 1)[:, None]
    phi = np.linspace(0, 2 * math.pi, segments + 1)[None, :]
    n = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta) * np.ones_like(phi),
                  np.sin(theta) * np.sin(phi)], -1)
    n = n.reshape(-1, 3)
    # the grid's triangles wind as d(row) × d(col), which for θ down and φ toward +z points
    # inward: reversed, so the outside is counter-clockwise (front) and survives back-face culling
    indices = _grid_indices(rings, segments).reshape(-1, 3)[:, ::-1].reshape(-1)
    return MeshData("sphere", (n * radius).astype("f4"), n.astype("f4"),
                    np.ascontiguousarray(indices))


def torus(major: float = 0.36, minor: float = 0.16, rings: int = 48,
          segments: int = 96) -> MeshData:
    """A torus about the y axis: the third, doubly curved surface of the materials scene."""
    u = np.linspace(0, 2 * math.pi, segments + 1)[None, :]  # around the axis
    v = np.linspace(0, 2 * math.pi, rings + 1)[:, None]  # around the tube
    centre = np.stack([np.cos(u), np.zeros_like(u), np.sin(u)], -1)
    n = np.stack([np.cos(v) * np.cos(u), np.sin(v) * np.ones_like(u), np.cos(v) * np.sin(u)], -1)
    p = centre * major + n * minor
    return MeshData("torus", p.reshape(-1, 3).astype("f4"), n.reshape(-1, 3).astype("f4"),
                    _grid_indices(rings, segments))


#: the segment counts auto tessellation chooses from (rings of a sphere are half of these)
TESSELLATION_LEVELS = (12, 24, 48, 96, 192)
#: (rings, segments) of the fixed tessellation: the meshes' former defaults
FIXED_TESSELLATION = {"sphere": (48, 96), "torus": (48, 96)}
#: the object-space sizes auto tessellation measures: bounding radius and the circles it divides
_SPHERE_RADIUS, _TORUS_MAJOR, _TORUS_MINOR = 0.5, 0.36, 0.16
BOUNDING_RADIUS = {"sphere": _SPHERE_RADIUS, "torus": _TORUS_MAJOR + _TORUS_MINOR}


def tessellation_level(circumference_px: float, edge_px: float,
                       levels: tuple[int, ...] = TESSELLATION_LEVELS) -> int:
    """The finest of ``levels`` whose edges span at least ``edge_px`` pixels on a circle of
    ``circumference_px`` (the coarsest level when even it has shorter edges)."""
    want = circumference_px / max(float(edge_px), 1e-6)
    chosen = levels[0]
    for n in levels:
        if n <= want:
            chosen = n
    return chosen


def pixels_per_unit(distance: float, fov_degrees: float, height_px: int) -> float:
    """Pixels per object unit at ``distance`` in front of a camera of vertical field of view
    ``fov_degrees`` and an image ``height_px`` high."""
    return height_px / (2.0 * max(distance, 1e-6) * math.tan(math.radians(fov_degrees) / 2))


def auto_tessellation(name: str, distance: float, fov_degrees: float, height_px: int,
                      edge_px: float, scale: float = 1.0) -> tuple[int, int]:
    """(rings, segments) of the sphere or torus ``name`` whose centre is ``distance`` from the
    camera, so that edges span ≥ ``edge_px`` pixels. The size is taken at the object's nearest
    point (centre distance less its bounding radius), so the near side is never the coarse
    one; a camera inside the bounding sphere gets the finest level."""
    near = distance - BOUNDING_RADIUS[name] * scale
    if near <= 1e-3 * scale:
        top = TESSELLATION_LEVELS[-1]
        return (top // 2, top) if name == "sphere" else (top, top)
    ppu = pixels_per_unit(near, fov_degrees, height_px) * scale
    if name == "sphere":
        segments = tessellation_level(2 * math.pi * _SPHERE_RADIUS * ppu, edge_px)
        return segments // 2, segments  # a meridian's edges as long as the equator's
    segments = tessellation_level(2 * math.pi * (_TORUS_MAJOR + _TORUS_MINOR) * ppu, edge_px)
    rings = tessellation_level(2 * math.pi * _TORUS_MINOR * ppu, edge_px)
    return rings, segments


def slice_quad(y: float = 0.0, half: float = 0.5) -> MeshData:
    """A square in the plane y = const of object space: the thesis's cross-section (fig. 7)."""
    p = np.array([[-half, y, -half], [half, y, -half], [half, y, half], [-half, y, half]], "f4")
    n = np.tile(np.array([0, 1, 0], "f4"), (4, 1))
    return MeshData("slice", p, n, np.array([0, 2, 1, 0, 3, 2], "u4"))


def _grid_indices(rows: int, cols: int) -> np.ndarray:
    r, c = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    a = r * (cols + 1) + c
    b = a + cols + 1
    quads = np.stack([a, b, a + 1, a + 1, b, b + 1], -1)
    return quads.reshape(-1).astype("u4")


class Mesh:
    """GPU buffers of a :class:`MeshData`, allocated through the owner's account."""

    def __init__(self, gpu, owner: str, data: MeshData):
        self.data = data
        self.vbo = gpu.buffer(owner, f"{data.name} vertices", data.interleaved())
        self.ibo = gpu.buffer(owner, f"{data.name} indices", data.indices.tobytes())

    def draw(self, program) -> None:
        vao = program.vao([(self.vbo, "3f 3f", "in_position", "in_normal")], index_buffer=self.ibo)
        vao.render()
