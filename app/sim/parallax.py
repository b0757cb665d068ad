"""Parallax mapping — numpy twin of ``glsl/common/parallax.glsl`` (spec/003 §2.3).

The same methods with the same sampling (bilinear with wrap-around, the texel centres of
:func:`app.sim.surface_maps.sample_bilinear`) on a height array (H, W) in [0, 1], vectorised over
points (``uv`` (…, 2), views (…, 3) that broadcast with it), float64 inside:

=========  ===========================  ==================================================
mode       function                     what
=========  ===========================  ==================================================
0 off      —                            uv unchanged
1 bare     :func:`parallax_bare`        ``uv − (1 − h(uv))·scale·v_xy`` (spec/003 eq. 3.14,
                                        spec/003 eq. 3.15), offset-limited
2 steep    :func:`parallax_steep`       n layers from height 1 down, first layer the field
                                        reaches
3 occl.    :func:`parallax_occlusion`   steep, then interpolated between the last two samples
4 ref.     :func:`parallax_reference`   1024 layers and 12 bisections (beyond the thesis)
=========  ===========================  ==================================================

Geometry: the polygon is the top of the relief (height 1 lies on it, height 0 ``scale`` below,
in UV units) for every method, so they differ only in how they find the intersection; ``v`` is
the unit tangent-space direction from the surface to the eye, its z clamped to
:data:`MIN_VZ`. :func:`view_at` makes ``v`` from an elevation (0° grazing, 90° head-on) and an
azimuth.

:func:`parallax_error` measures a method against the reference for the bench: the UV offset
error in texels (wrapped: the map tiles) over a grid of points, its mean and 99th percentile,
and with an ``albedo`` the colour error as well. The thesis's claim (spec/003 §2.3): n between
10 and 20 is adequate; at 45°–90° n = 12 and n = 32 look alike, near 0° ("the critical angle")
they do not.

Failure cases guarded as in the shader: v.z clamped, a zero view read as the normal, layers
clamped to [1, 256], layer heights computed as (n − i)/n so the search always ends at layer 0,
the occlusion weight's denominator positive.
"""

from __future__ import annotations

import hashlib

import numpy as np

from app.sim.surface_maps import sample_bilinear

OFF, BARE, STEEP, OCCLUSION, REFERENCE = 0, 1, 2, 3, 4
METHODS = {"off": OFF, "bare": BARE, "steep": STEEP, "occlusion": OCCLUSION,
           "reference": REFERENCE}
MIN_VZ = 0.02
MAX_LAYERS = 256
REFERENCE_LAYERS = 1024
REFERENCE_BISECTIONS = 12


def tangent_space_view(to_eye: np.ndarray, frame: np.ndarray) -> np.ndarray:
    """``M·v`` with M's rows t, b, n (spec/003 eq. 3.16, spec/003 eq. 3.17); ``frame`` is
    :func:`app.sim.bump.tangent_frame`'s (…, 3, 3) with columns t, b, n."""
    return np.einsum("...ji,...j->...i", np.asarray(frame, np.float64),
                     np.asarray(to_eye, np.float64))


def view_at(angle_deg: float, azimuth_deg: float = 0.0) -> np.ndarray:
    """The unit tangent-space view at an elevation above the surface (90° = along the normal)
    and an azimuth from +u toward +v."""
    e, a = np.radians(angle_deg), np.radians(azimuth_deg)
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def parallax_height(height: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """The height field at uv (bilinear, wrap)."""
    return sample_bilinear(height, uv)


def parallax_view(view_ts: np.ndarray) -> np.ndarray:
    """The unit view, z kept at or above :data:`MIN_VZ`; a zero view is (0, 0, 1)."""
    v = np.asarray(view_ts, dtype=np.float64)
    ln = np.linalg.norm(v, axis=-1, keepdims=True)
    big = ln > 1e-12
    v = np.where(big, v / np.where(big, ln, 1.0), np.array([0.0, 0.0, 1.0]))
    return np.concatenate([v[..., :2], np.maximum(v[..., 2:], MIN_VZ)], axis=-1)


def _broadcast(uv: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    uv = np.asarray(uv, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    shape = np.broadcast_shapes(uv.shape[:-1], v.shape[:-1])
    return np.broadcast_to(uv, shape + (2,)), np.broadcast_to(v, shape + (3,))


def parallax_bare(height: np.ndarray, uv: np.ndarray, v: np.ndarray,
                  scale: float) -> np.ndarray:
    """``P = (1 − h(uv))·scale·v`` (spec/003 eq. 3.14), ``uv − P_xy`` (spec/003 eq. 3.15)."""
    uv, v = _broadcast(uv, v)
    p = (1.0 - parallax_height(height, uv))[..., None] * scale * v
    return uv - p[..., :2]


def _delta(v: np.ndarray, scale: float, n: int) -> np.ndarray:
    return scale * v[..., :2] / (v[..., 2:] * float(n))


def _search(height: np.ndarray, uv: np.ndarray, delta: np.ndarray,
            n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The first i in [0, n] with h(uv − i·Δ) ≥ (n − i)/n, and h − layer at i (a) and at i − 1
    (b; 0 where i = 0)."""
    a = parallax_height(height, uv) - 1.0
    b = np.zeros_like(a)
    idx = np.zeros(a.shape, dtype=np.int64)
    active = a < 0.0
    for i in range(1, n + 1):
        if not active.any():
            break
        pts = np.nonzero(active)
        h = parallax_height(height, uv[pts] - float(i) * delta[pts])
        b[pts] = a[pts]
        a[pts] = h - float(n - i) / float(n)
        idx[pts] = i
        active[pts] = a[pts] < 0.0
    return idx, a, b


def _layers(layers: int) -> int:
    return int(np.clip(int(layers), 1, MAX_LAYERS))


def _steep(height, uv, v, scale: float, n: int):
    """The search over ``n`` layers: (uv, the UV step per layer, i, a, b) (see ``_search``)."""
    uv, v = _broadcast(uv, v)
    delta = _delta(v, scale, n)
    return (uv, delta, *_search(height, uv, delta, n))


def parallax_steep(height: np.ndarray, uv: np.ndarray, v: np.ndarray, scale: float,
                   layers: int) -> np.ndarray:
    """Steep parallax: the UV of the first of ``layers`` layers the height field reaches."""
    uv, delta, i, _, _ = _steep(height, uv, v, scale, _layers(layers))
    return uv - i[..., None] * delta


def parallax_occlusion(height: np.ndarray, uv: np.ndarray, v: np.ndarray, scale: float,
                       layers: int) -> np.ndarray:
    """Parallax occlusion: the steep search, then ``mix(uv_i, uv_(i−1), a/(a − b))``."""
    uv, delta, i, a, b = _steep(height, uv, v, scale, _layers(layers))
    cur = uv - i[..., None] * delta
    denom = np.where(i > 0, a - b, 1.0)
    w = np.where(i > 0, a / denom, 0.0)[..., None]
    return cur + w * delta


def parallax_reference(height: np.ndarray, uv: np.ndarray, v: np.ndarray,
                       scale: float) -> np.ndarray:
    """The ground truth: the search with 1024 layers, then 12 bisections of the last step."""
    n = REFERENCE_LAYERS
    uv, delta, i, _, _ = _steep(height, uv, v, scale, n)
    lo = np.maximum(i - 1, 0).astype(np.float64)
    hi = i.astype(np.float64)
    for _ in range(REFERENCE_BISECTIONS):
        mid = 0.5 * (lo + hi)
        below = parallax_height(height, uv - mid[..., None] * delta) >= (n - mid) / n
        hi = np.where(below, mid, hi)
        lo = np.where(below, lo, mid)
    t = np.where(i > 0, 0.5 * (lo + hi), 0.0)
    return uv - t[..., None] * delta


def parallax_uv(height: np.ndarray, uv: np.ndarray, view_ts: np.ndarray, mode: int | str,
                layers: int = 12, scale: float = 0.05) -> np.ndarray:
    """The GLSL ``ParallaxUV`` with ``uParallaxMode`` = ``mode`` (a number or a name of
    :data:`METHODS`), ``uParallaxLayers`` = ``layers`` and ``uParallaxScale`` = ``scale``."""
    m = METHODS[mode] if isinstance(mode, str) else int(mode)
    uv = np.asarray(uv, dtype=np.float64)
    if m <= OFF:
        return np.broadcast_to(uv, np.broadcast_shapes(
            uv.shape, np.asarray(view_ts).shape[:-1] + (2,))).copy()
    v = parallax_view(view_ts)
    if m == BARE:
        return parallax_bare(height, uv, v, scale)
    if m == STEEP:
        return parallax_steep(height, uv, v, scale, layers)
    if m == OCCLUSION:
        return parallax_occlusion(height, uv, v, scale, layers)
    return parallax_reference(height, uv, v, scale)


def error_grid(grid: int = 64) -> np.ndarray:
    """The points parallax_error measures at: grid × grid UVs off the texel centres."""
    c = (np.arange(grid) + 0.37) / grid
    v, u = np.meshgrid(c, c, indexing="ij")
    return np.stack([u, v], axis=-1)


def wrapped_texels(uv: np.ndarray, ref: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """|uv − ref| in texels of a (width, height) map that tiles (the shorter way round)."""
    d = np.asarray(uv, np.float64) - np.asarray(ref, np.float64)
    d -= np.round(d)
    return np.linalg.norm(d * np.asarray(size, np.float64), axis=-1)


_REFERENCE_MEMO: dict[tuple, np.ndarray] = {}


def _reference_uv(height: np.ndarray, uv: np.ndarray, v: np.ndarray, scale: float) -> np.ndarray:
    key = (hashlib.sha1(np.ascontiguousarray(height).tobytes()).hexdigest(), height.shape,
           hashlib.sha1(np.ascontiguousarray(uv).tobytes()).hexdigest(),
           tuple(np.round(v, 12)), float(scale))
    if key not in _REFERENCE_MEMO:
        if len(_REFERENCE_MEMO) > 32:
            _REFERENCE_MEMO.clear()
        _REFERENCE_MEMO[key] = parallax_reference(height, uv, v, scale)
    return _REFERENCE_MEMO[key]


def parallax_error(method: int | str, layers: int, angle_deg: float, height: np.ndarray, *,
                   scale: float = 0.05, azimuth_deg: float = 30.0, grid: int = 64,
                   albedo: np.ndarray | None = None) -> dict[str, float]:
    """A method's error against the reference at a view elevation ``angle_deg`` (0° grazing):
    ``mean_px`` and ``p99_px``, the UV offset error in texels of ``height`` over
    :func:`error_grid`; with ``albedo`` (H, W, C) also ``mean_colour`` and ``p99_colour``, the
    largest channel's absolute difference of the albedo sampled at the two UVs (in [0, 1])."""
    height = np.asarray(height, dtype=np.float64)
    uv = error_grid(grid)
    v = parallax_view(view_at(angle_deg, azimuth_deg))
    ref = _reference_uv(height, uv, v, scale)
    got = parallax_uv(height, uv, v, method, layers, scale)
    err = wrapped_texels(got, ref, (height.shape[1], height.shape[0]))
    out = {"mean_px": float(err.mean()), "p99_px": float(np.percentile(err, 99))}
    if albedo is not None:
        diff = np.abs(sample_bilinear(albedo, got) - sample_bilinear(albedo, ref))
        diff = diff.max(axis=-1) if diff.ndim > err.ndim else diff
        out["mean_colour"] = float(diff.mean())
        out["p99_colour"] = float(np.percentile(diff, 99))
    return out
