"""Bump (normal) mapping — numpy twin of ``glsl/common/bump.glsl`` (spec/003 §2.2).

One function per GLSL function, vectorised over leading axes (float64 inside):

* :func:`unpack_normal_xy` — ``2·tex − 1`` from (r, g), or (a, g) in the DXT5nm layout
  (spec/003 eq. 3.1);
* :func:`normal_from_xy` — z exact ``sqrt(1 − x² − y²)`` (spec/003 eq. 3.3) or the cheap
  ``1 − ½(x² + y²)`` (spec/003 eq. 3.4);
* :func:`unpack_normal` — both, with Bumpiness scaling x and y first (as the thesis's
  GetBumpMappedNormal does);
* :func:`tangent_frame` — ``b = w·normalize(n × t)`` (spec/003 eq. 3.6) and ``M = [t b n]``
  (spec/003 eq. 3.7), re-normalised, t made orthogonal to n;
* :func:`tangent_to_world` — ``n_worldᵗ = n_localᵗ·Mᵗ`` (spec/003 eq. 3.10, spec/003 eq. 3.11);
* :func:`bumped_normal` — the GLSL ``BumpedNormal``: sample the map (bilinear, wrap: see
  :func:`app.sim.surface_maps.sample_bilinear`), unpack, carry to world space.

:func:`approx_z_error` is what spec/003 eq. 3.4 implies against spec/003 eq. 3.3:
``1 − s/2 − sqrt(1 − s)`` with s = x² + y² (0 at s = 0, 0.043 at s = ½, ½ at s = 1).

Failure cases guarded as in the shader: s clamped to 1 before the square root, the approximate
z kept at or above 0, a degenerate tangent replaced by a perpendicular, a zero normal read as
(0, 0, 1), w = 0 read as +1.
"""

from __future__ import annotations

import numpy as np

from app.sim.maths import normalize as _normalize
from app.sim.surface_maps import sample_bilinear

EXACT = 0
APPROX = 1


def unpack_normal_xy(tex: np.ndarray, dxt5nm: bool = False) -> np.ndarray:
    """x, y (…, 2) of texels ``tex`` (…, 4) in [0, 1]: ``2·tex − 1`` of (r, g) or (a, g);
    spec/003 eq. 3.1."""
    tex = np.asarray(tex, dtype=np.float64)
    xy = tex[..., [3, 1]] if dxt5nm else tex[..., [0, 1]]
    return 2.0 * xy - 1.0


def normal_from_xy(xy: np.ndarray, unpack: int = EXACT) -> np.ndarray:
    """(x, y, z) with z exact (``unpack`` 0: spec/003 eq. 3.3) or approximated (``unpack`` 1:
    spec/003 eq. 3.4)."""
    xy = np.asarray(xy, dtype=np.float64)
    s = np.sum(xy * xy, axis=-1)
    if int(unpack) == APPROX:
        z = np.maximum(1.0 - 0.5 * s, 0.0)  # spec/003 eq. 3.4
    else:
        z = np.sqrt(1.0 - np.minimum(s, 1.0))  # spec/003 eq. 3.3
    return np.concatenate([xy, z[..., None]], axis=-1)


def unpack_normal(tex: np.ndarray, unpack: int = EXACT, dxt5nm: bool = False,
                  bumpiness: float = 1.0) -> np.ndarray:
    """A texel as a tangent-space normal, x and y scaled by ``bumpiness`` before z is made."""
    return normal_from_xy(unpack_normal_xy(tex, dxt5nm) * bumpiness, unpack)


def approx_z_error(s: np.ndarray | float) -> np.ndarray:
    """z of spec/003 eq. 3.4 minus z of spec/003 eq. 3.3 at s = x² + y² in [0, 1]."""
    s = np.asarray(s, dtype=np.float64)
    return (1.0 - 0.5 * s) - np.sqrt(1.0 - s)


def tangent_frame(n: np.ndarray, tangent: np.ndarray) -> np.ndarray:
    """The per-fragment frame (…, 3, 3) with columns t, b, n (``M[..., :, 0]`` is t) of world
    normals ``n`` (…, 3) and tangents ``tangent`` (…, 4), w the handedness."""
    n = np.asarray(n, dtype=np.float64)
    tangent = np.asarray(tangent, dtype=np.float64)
    shape = np.broadcast_shapes(n.shape[:-1], tangent.shape[:-1])
    n = np.broadcast_to(n, shape + (3,))
    tangent = np.broadcast_to(tangent, shape + (4,))
    ln = np.linalg.norm(n, axis=-1, keepdims=True)
    big = ln > 1e-12
    N = np.where(big, n / np.where(big, ln, 1.0), np.array([0.0, 0.0, 1.0]))
    t = tangent[..., :3]
    T = t - N * np.sum(N * t, axis=-1, keepdims=True)
    bad = np.sum(T * T, axis=-1, keepdims=True) < 1e-12
    if bad.any():
        alt = np.where(np.abs(N[..., :1]) < 0.9, np.array([1.0, 0.0, 0.0]),
                       np.array([0.0, 1.0, 0.0]))
        alt = alt - N * np.sum(N * alt, axis=-1, keepdims=True)
        T = np.where(bad, alt, T)
    T = _normalize(T)
    w = np.where(tangent[..., 3:4] < 0.0, -1.0, 1.0)
    B = w * _normalize(np.cross(N, T))  # spec/003 eq. 3.6
    return np.stack([T, B, N], axis=-1)  # spec/003 eq. 3.7


def tangent_to_world(n_local: np.ndarray, frame: np.ndarray) -> np.ndarray:
    """``n_localᵗ·Mᵗ`` = x·t + y·b + z·n, normalised (spec/003 eq. 3.10, spec/003 eq. 3.11)."""
    n_local = np.asarray(n_local, dtype=np.float64)
    return _normalize(np.einsum("...ij,...j->...i", frame, n_local))


def bumped_normal(normal_map: np.ndarray, uv: np.ndarray, n: np.ndarray, tangent: np.ndarray,
                  unpack: int = EXACT, dxt5nm: bool = False,
                  bumpiness: float = 1.0) -> np.ndarray:
    """The GLSL ``BumpedNormal``: world normals (…, 3) at ``uv`` (…, 2) of ``normal_map``
    (H, W, 4) in [0, 1] (a uint8 texture divided by 255), for world vertex normals ``n`` and
    tangents ``tangent`` (…, 4)."""
    tex = sample_bilinear(normal_map, uv)
    return tangent_to_world(unpack_normal(tex, unpack, dxt5nm, bumpiness),
                            tangent_frame(n, tangent))
