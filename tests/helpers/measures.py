"""Measures the tests take of images, textures and meshes (not twins of any shader)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike


def ring_centroid(alpha: np.ndarray) -> tuple[float, float]:
    """The alpha-weighted centroid of an image (h, w) in window pixels (y up)."""
    h, w = alpha.shape
    total = float(alpha.sum())
    if total <= 0.0:
        return float("nan"), float("nan")
    ys, xs = np.mgrid[0:h, 0:w]
    cx = float((alpha * (xs + 0.5)).sum() / total)
    cy_top = float((alpha * (ys + 0.5)).sum() / total)
    return cx, h - cy_top



def focal_length_px(height: float, fov_deg: float) -> float:
    """The focal length in pixels of a perspective view ``height`` pixels tall."""
    return 0.5 * float(height) / math.tan(math.radians(fov_deg) * 0.5)



def disparity_px(depth: ArrayLike, ipd: float, height: float, fov_deg: float) -> np.ndarray:
    """Horizontal disparity (left eye's x − right eye's x, pixels) of a point at planar
    ``depth`` metres in a parallel-axis pair ``ipd`` apart: ipd·f/depth (0 at infinity)."""
    z = np.asarray(depth, np.float64)
    return float(ipd) * focal_length_px(height, fov_deg) / z



def texture_centroid(alpha: np.ndarray) -> np.ndarray:
    """The circular centroid (u, v) in [0, 1) of a tileable texture's alpha (each axis's mean
    angle of the alpha mass): the measure the plane's scroll moves (spec/003 §6 criterion 34)."""
    a = np.asarray(alpha, np.float64)
    h, w = a.shape
    out = []
    for axis, n in ((1, w), (0, h)):
        ang = 2.0 * math.pi * (np.arange(n) + 0.5) / n
        mass = a.sum(axis=1 - axis)
        z = np.sum(mass * np.exp(1j * ang))
        out.append((math.atan2(z.imag, z.real) / (2.0 * math.pi)) % 1.0)
    return np.array(out)



def edges_shared(mesh) -> np.ndarray:
    """How many triangles of ``mesh`` (an app.sim.hull.HullMesh) share each distinct undirected
    edge (2 everywhere when closed)."""
    t = mesh.triangles
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    e.sort(axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return counts
