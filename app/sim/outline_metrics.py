"""Measures of an outline against the analytic silhouette (spec/003 §2.13): numpy only.

Images are (height, width) with row 0 at the top, as ``app.gpu.targets.RenderTarget.read``
returns them; pixel centres are sampled. Cameras are given by their ``view`` and ``proj``
matrices (``app.sim.camera.Camera.view_matrix`` / ``projection_matrix``: column vectors,
M @ v).

* :func:`sphere_coverage`, :func:`boxes_coverage` — the exact silhouette (the set of pixels
  whose view ray hits the sphere or any of the axis-aligned boxes); :func:`table_boxes` are the
  lab table's five boxes (``app.sim.lab_meshes.TABLE``);
* :func:`silhouette_band` — the pixels within a distance of the silhouette curve (the boundary
  between covered and uncovered pixels, as the midpoints of their shared edges), outside it,
  inside it or both: the reference for an outline ``width`` pixels wide;
* :func:`sphere_nv` and :func:`rim_outline_weight` — the sphere's n·v per pixel and the numpy
  twin of ``glsl/shading/rim_outline.glsl``, so the rim silhouettes' reference band is where the
  analytic weight exceeds ½;
* :func:`outline_iou` — intersection over union of an outline mask and a reference band;
* :func:`gap_count` — the gaps of an outline: connected groups (8-neighbour) of at least
  ``min_size`` pixels of a reference band that the mask leaves uncovered. Pass a thin band (the
  first 1.5 pixels outside the silhouette) that any closed outline covers, so a thinner but
  closed outline has no gaps while a torn one (the hull at a hard corner) has some.
"""

from __future__ import annotations

from typing import Iterable, Sequence

import numpy as np

from . import lab_meshes, staircase

RIM_STAIR_STEP = 1.0 / 3.0


def pixel_rays(view: np.ndarray, proj: np.ndarray, size: tuple[int, int]
               ) -> tuple[np.ndarray, np.ndarray]:
    """(origins, unit directions), each (h, w, 3) in world space, through the pixel centres."""
    w, h = int(size[0]), int(size[1])
    x = (2.0 * (np.arange(w) + 0.5) / w) - 1.0
    y = 1.0 - (2.0 * (np.arange(h) + 0.5) / h)
    xx, yy = np.meshgrid(x, y)
    inv = np.linalg.inv(np.asarray(proj, np.float64) @ np.asarray(view, np.float64))

    def unproject(z: float) -> np.ndarray:
        ndc = np.stack([xx, yy, np.full_like(xx, z), np.ones_like(xx)], -1)
        p = ndc @ inv.T
        return p[..., :3] / p[..., 3:4]

    near, far = unproject(-1.0), unproject(1.0)
    d = far - near
    return near, d / np.linalg.norm(d, axis=-1, keepdims=True)


def _sphere_hit(view, proj, size, centre, radius) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    o, d = pixel_rays(view, proj, size)
    oc = o - np.asarray(centre, np.float64)
    b = np.einsum("ijk,ijk->ij", oc, d)
    c = np.einsum("ijk,ijk->ij", oc, oc) - float(radius) ** 2
    disc = b * b - c
    hit = disc >= 0.0
    t = -b - np.sqrt(np.where(hit, disc, 0.0))
    hit &= t > 0.0
    return hit, o + t[..., None] * d, d


def sphere_coverage(view, proj, size, centre, radius) -> np.ndarray:
    """(h, w) bool: the pixels whose ray hits the sphere."""
    return _sphere_hit(view, proj, size, centre, radius)[0]


def sphere_nv(view, proj, size, centre, radius) -> np.ndarray:
    """(h, w) n·v of the sphere's visible point per pixel (NaN off the sphere)."""
    hit, p, d = _sphere_hit(view, proj, size, centre, radius)
    n = (p - np.asarray(centre, np.float64)) / float(radius)
    nv = np.clip(-np.einsum("ijk,ijk->ij", n, d), 0.0, 1.0)
    return np.where(hit, nv, np.nan)


def boxes_coverage(view, proj, size, boxes: Iterable[Sequence], model=None) -> np.ndarray:
    """(h, w) bool: the pixels whose ray hits any of the axis-aligned ``boxes`` ((lo, hi)
    corners in the objects' frame, placed by the 4 × 4 ``model``; default the identity)."""
    o, d = pixel_rays(view, proj, size)
    if model is not None:  # rays into the boxes' frame
        inv = np.linalg.inv(np.asarray(model, np.float64))
        o = o @ inv[:3, :3].T + inv[:3, 3]
        d = d @ inv[:3, :3].T
    safe = np.where(np.abs(d) < 1e-12, 1e-12, d)
    out = np.zeros(o.shape[:2], bool)
    for lo, hi in boxes:
        t1 = (np.asarray(lo, np.float64) - o) / safe
        t2 = (np.asarray(hi, np.float64) - o) / safe
        t_near = np.minimum(t1, t2).max(axis=-1)
        t_far = np.maximum(t1, t2).min(axis=-1)
        out |= (t_near <= t_far) & (t_far > 0.0)
    return out


def table_boxes() -> list[tuple[tuple[float, float, float], tuple[float, float, float]]]:
    """The lab table's top slab and four legs as (lo, hi) corners (app.sim.lab_meshes.table)."""
    t = lab_meshes.TABLE
    w, d, h = t["width"] / 2, t["depth"] / 2, t["height"]
    out = [((-w, h - t["top"], -d), (w, h, d))]
    g = t["leg"] / 2
    for sx in (-1.0, 1.0):
        for sz in (-1.0, 1.0):
            cx = sx * (w - t["inset"] - g)
            cz = sz * (d - t["inset"] - g)
            out.append(((cx - g, 0.0, cz - g), (cx + g, h - t["top"], cz + g)))
    return out


def boundary_distance(inside: np.ndarray, limit: float | None = None) -> np.ndarray:
    """(h, w) Euclidean distance (pixels) from each pixel centre to the silhouette curve: the
    nearest midpoint of an edge shared by a covered and an uncovered pixel (inf when the image
    has none). With ``limit``, only distances below it are found (the rest are inf): the same
    values, from the edge midpoints in a window around each pixel instead of all of them."""
    m = np.asarray(inside, bool)
    vertical = m[:, 1:] != m[:, :-1]  # an edge midpoint at (y, x + 0.5)
    horizontal = m[1:, :] != m[:-1, :]  # … at (y + 0.5, x)
    if limit is not None:
        return _boundary_distance_within(vertical, horizontal, m.shape, float(limit))
    pts = []
    ys, xs = np.nonzero(vertical)
    pts.append(np.stack([ys.astype(float), xs + 0.5], 1))
    ys, xs = np.nonzero(horizontal)
    pts.append(np.stack([ys + 0.5, xs.astype(float)], 1))
    p = np.concatenate(pts)
    h, w = m.shape
    if len(p) == 0:
        return np.full((h, w), np.inf)
    yy, xx = np.mgrid[0:h, 0:w]
    q = np.stack([yy.ravel(), xx.ravel()], 1).astype(float)
    best = np.full(len(q), np.inf)
    for start in range(0, len(p), 512):
        chunk = p[start:start + 512]
        d2 = ((q[:, None, :] - chunk[None, :, :]) ** 2).sum(-1).min(1)
        best = np.minimum(best, d2)
    return np.sqrt(best).reshape(h, w)


def _boundary_distance_within(vertical, horizontal, shape, limit: float) -> np.ndarray:
    """:func:`boundary_distance` below ``limit``: for every offset of an edge midpoint from a
    pixel centre that is nearer than ``limit`` (a window of ±⌈limit⌉ + 1 pixels), the pixels
    with an edge there take that offset's length if it is their nearest so far."""
    h, w = shape
    best = np.full((h, w), np.inf)
    r = int(np.ceil(limit)) + 1
    # vertical midpoint (y, x + 0.5) seen from pixel (py, px): offset (y − py, x − px + 0.5);
    # horizontal midpoint (y + 0.5, x): offset (y − py + 0.5, x − px)
    for edges, half in ((vertical, (0.0, 0.5)), (horizontal, (0.5, 0.0))):
        eh, ew = edges.shape
        padded = np.zeros((eh + 2 * r, ew + 2 * r), bool)
        padded[r:r + eh, r:r + ew] = edges
        for oy in range(-r, r + 1):
            for ox in range(-r, r + 1):
                d2 = (oy + half[0]) ** 2 + (ox + half[1]) ** 2
                if d2 >= limit * limit:
                    continue
                # pixel (py, px) has an edge at index (py + oy, px + ox)
                hit = padded[r + oy:r + oy + h, r + ox:r + ox + w]
                best[hit] = np.minimum(best[hit], d2)
    return np.sqrt(best)


def silhouette_band(inside: np.ndarray, width: float, side: str = "outside") -> np.ndarray:
    """(h, w) bool: the pixels within ``width`` pixels of the silhouette curve on ``side``
    ("outside", "inside" or "both"); the first pixel row each side is at distance 0.5."""
    if side not in ("outside", "inside", "both"):
        raise ValueError(f"side must be outside, inside or both, got {side!r}")
    m = np.asarray(inside, bool)
    near = boundary_distance(m, limit=float(width)) < float(width)
    if side == "outside":
        return near & ~m
    if side == "inside":
        return near & m
    return near


def rim_outline_weight(mode: str, nv, r: float) -> np.ndarray:
    """The twin of RimOutlineWeight (glsl/shading/rim_outline.glsl): ``mode`` "threshold",
    "soft" or "50x2" on n·v with band ``r``."""
    x = np.clip(1.0 - np.clip(np.asarray(nv, np.float64), 0.0, 1.0)
                / float(np.clip(r, 1e-3, 1.0)), 0.0, 1.0)
    if mode == "threshold":
        return staircase.threshold_step(x, 0.0)
    if mode == "soft":
        return staircase.soft_staired_value(x * (1.0 + RIM_STAIR_STEP), RIM_STAIR_STEP,
                                            0.5 * RIM_STAIR_STEP)
    if mode == "50x2":
        return staircase.soft_silhouette(x)
    raise ValueError(f"rim mode must be threshold, soft or 50x2, got {mode!r}")


def outline_iou(mask: np.ndarray, reference_band: np.ndarray) -> float:
    """Intersection over union of two (h, w) bool masks (1 when both are empty)."""
    a, b = np.asarray(mask, bool), np.asarray(reference_band, bool)
    union = int((a | b).sum())
    return 1.0 if union == 0 else float((a & b).sum()) / union


def _components(m: np.ndarray) -> list[int]:
    """Sizes of the 8-connected components of a bool image (a flood fill; small images)."""
    seen = np.zeros_like(m, bool)
    h, w = m.shape
    sizes = []
    for y0, x0 in zip(*np.nonzero(m)):
        if seen[y0, x0]:
            continue
        stack = [(int(y0), int(x0))]
        seen[y0, x0] = True
        n = 0
        while stack:
            y, x = stack.pop()
            n += 1
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    yy, xx = y + dy, x + dx
                    if 0 <= yy < h and 0 <= xx < w and m[yy, xx] and not seen[yy, xx]:
                        seen[yy, xx] = True
                        stack.append((yy, xx))
        sizes.append(n)
    return sizes


def gap_count(mask: np.ndarray, reference_band: np.ndarray, min_size: int = 2) -> int:
    """The gaps of an outline: 8-connected groups of at least ``min_size`` pixels of
    ``reference_band`` that ``mask`` does not cover (see the module docstring)."""
    hole = np.asarray(reference_band, bool) & ~np.asarray(mask, bool)
    return sum(1 for s in _components(hole) if s >= int(min_size))
