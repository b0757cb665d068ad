"""The ground fog plane (spec/003 §2.11 a, ``Custom/Fog``): where it lies over a terrain, its
mesh, its generated texture and its ground mask.

Where: a flat plane at the land's median height (the ``terrain`` slot's heights above its sea
level: the island's plateau, 1.6 m) plus ``fog.plane_height`` — "slightly above the terrain",
low so that it cuts the houses as little as possible (Fig. 119) — spanning the land's bounding
box. Over ground that drops away below it (the beach, the sea, a hollow) it would float in mid
air: a ground mask, baked from the terrain's heights, fades it out where the ground lies more
than 0.5–1.5 m below the plane. Where the ground rises above it (the hill), the depth test hides
it, as in the thesis.

The mask's second channel is the layer's depth there — how far the ground lies below the plane,
over ``DEPTH_RANGE`` metres — which ``fog.plane_hug`` reads (beyond the thesis): the wisps thin
where the ground comes up to the plane, so the fog lies in the hollows and fades out before it
meets a slope instead of cutting it along a hard line.

The mesh is a grid of about 4 m cells (the global fog's factor of the plane is per vertex, as
every surface's). The texture (:func:`app.sim.fog.fog_texture`) and mask are made on the CPU
and rebuilt only when their inputs change.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

#: grid cell of the plane's mesh [m]
CELL = 4.0
#: samples per side of the ground mask
MASK_SIZE = 96
#: the texture's size [texels]
TEXTURE_SIZE = 256
#: the mask fades from 1 where the ground is this far below the plane or nearer...
MASK_NEAR = 0.5
#: ...to 0 where it is this far below [m]
MASK_FAR = 1.5
#: the plane spans the land's bounding box plus this margin [m]
MARGIN = 4.0
#: the mask's second channel: the ground's depth below the plane over this range [m]
DEPTH_RANGE = 2.0


@dataclass(frozen=True)
class PlaneLayout:
    """Where the plane lies: its height and its rectangle (x0, z0, x1, z1) [m], the mask over
    that rectangle (MASK_SIZE² floats in [0, 1], row 0 at z0), the land's median height and
    the ground's depth below the plane over the mask's samples [m] (negative: the ground rises
    above it; None: a flat ground ``y`` below, no terrain)."""

    y: float
    rect: tuple[float, float, float, float]
    mask: np.ndarray
    ground: float
    depth: np.ndarray | None = None

    def mask_texture(self) -> np.ndarray:
        """(MASK_SIZE, MASK_SIZE, 2) in [0, 1]: R the mask, G the depth / DEPTH_RANGE."""
        depth = self.depth if self.depth is not None else np.full(self.mask.shape, self.y
                                                                  - self.ground)
        return np.stack([self.mask, np.clip(depth / DEPTH_RANGE, 0.0, 1.0)], -1)


def plane_layout(terrain, offset: float) -> PlaneLayout:
    """The plane over ``terrain`` (the Terrain protocol of app.frame), ``offset`` metres above
    the land's median height. With no land above the sea level (or no terrain at all), a
    40 m square at the sea level + ``offset``, unmasked."""
    if terrain is None:
        return PlaneLayout(offset, (-20.0, -20.0, 20.0, 20.0), np.ones((MASK_SIZE, MASK_SIZE)),
                           0.0)
    x0, z0, x1, z1 = (float(v) for v in terrain.bounds)
    sea = float(terrain.sea_level)
    n = 128
    xs = np.linspace(x0, x1, n)
    zs = np.linspace(z0, z1, n)
    gx, gz = np.meshgrid(xs, zs, indexing="xy")
    h = np.asarray(terrain.height(gx, gz), np.float64)
    land = h > sea
    if not land.any():
        return PlaneLayout(sea + offset, (-20.0, -20.0, 20.0, 20.0),
                           np.ones((MASK_SIZE, MASK_SIZE)), sea)
    ground = float(np.median(h[land]))
    y = ground + offset
    rect = (max(x0, float(gx[land].min()) - MARGIN), max(z0, float(gz[land].min()) - MARGIN),
            min(x1, float(gx[land].max()) + MARGIN), min(z1, float(gz[land].max()) + MARGIN))
    mx = np.linspace(rect[0], rect[2], MASK_SIZE)
    mz = np.linspace(rect[1], rect[3], MASK_SIZE)
    mgx, mgz = np.meshgrid(mx, mz, indexing="xy")
    below = y - np.asarray(terrain.height(mgx, mgz), np.float64)
    t = np.clip((MASK_FAR - below) / (MASK_FAR - MASK_NEAR), 0.0, 1.0)
    return PlaneLayout(y, rect, t * t * (3.0 - 2.0 * t), ground, below)


def plane_grid(rect: tuple[float, float, float, float], cell: float = CELL) -> tuple[np.ndarray,
                                                                                   np.ndarray]:
    """(vertices (n, 2) float32 world xz, triangle indices uint32) of a grid over ``rect``."""
    x0, z0, x1, z1 = rect
    nx = max(1, int(np.ceil((x1 - x0) / cell)))
    nz = max(1, int(np.ceil((z1 - z0) / cell)))
    gx, gz = np.meshgrid(np.linspace(x0, x1, nx + 1), np.linspace(z0, z1, nz + 1), indexing="xy")
    verts = np.stack([gx.ravel(), gz.ravel()], -1).astype("f4")
    r, c = np.meshgrid(np.arange(nz), np.arange(nx), indexing="ij")
    a = r * (nx + 1) + c
    b = a + nx + 1
    idx = np.stack([a, b, a + 1, a + 1, b, b + 1], -1).reshape(-1).astype("u4")
    return verts, idx


def upload_texture(gpu, owner: str, name: str, rgba: np.ndarray, repeat: bool):
    """An 8-bit texture of ``rgba`` (h, w, 4 or h, w) in [0, 1], mipmapped and trilinear (a
    repeating one 8× anisotropic: the fog effect sets its anisotropy from the context)."""
    data = np.clip(np.round(np.asarray(rgba) * 255.0), 0, 255).astype("u1")
    comps = 1 if data.ndim == 2 else data.shape[2]
    h, w = data.shape[:2]
    tex = gpu.texture(owner, name, (w, h), comps, np.ascontiguousarray(data).tobytes(),
                      dtype="f1", repeat=repeat)
    tex.build_mipmaps()
    tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    if repeat:
        tex.anisotropy = 8.0
    return tex
