"""Numpy twin of glsl/common/shadow.glsl and the shadow casters (spec/003 §2.8, the toon
village's Unity shadows): cascade splits, the stable (bounding-sphere, texel-snapped) fit of a
directional light's orthographic map, the caster biases, the receiver filters (hard, the
thesis's four-tap soft, PCSS, VSM) and the dithered semitransparent-shadow patterns. No GL here.

Conventions (shared with the GLSL): ``toward_light`` is the unit vector from a surface toward
the light; a map stores depth in [0, 1] (0 at the light's near plane); a receiver is lit where
its own depth ≤ the stored one. Biases are applied by the caster, as Unity's
``UnityClipSpaceShadowCasterPos`` (normal bias) and ``UnityApplyLinearShadowBias`` (linear
bias) do: both are given in units of :data:`NORMAL_BIAS_TEXELS` / :data:`LINEAR_BIAS_TEXELS`
texels of the map (a texel's world size is the cascade's width / the map's size), so one
setting suits every cascade and map size.
"""

from __future__ import annotations

import numpy as np

#: texels per unit of each bias setting: one unit of normal bias is 4 texels (times sin(l, n)),
#: one of linear bias 10 texels, so the thesis's settings behave as in its figures (Fig. 86:
#: 0.3 + 0.01 clean; Fig. 87: linear 0.6 Peter Panning) at any map size
NORMAL_BIAS_TEXELS = 4.0
LINEAR_BIAS_TEXELS = 10.0


def cascade_splits(near: float, far: float, count: int, lam: float = 0.5) -> np.ndarray:
    """The far ends of ``count`` cascades over [near, far] by the practical split scheme
    (Zhang et al.): z_i = λ · n (f/n)^(i/N) + (1 − λ) (n + (f − n) i/N), i = 1..N
    (spec/003 §2.8: the thesis's "Cascade Splits"; λ = 1 is logarithmic, 0 uniform).
    ``count`` 0 or 1 is one map over the whole range."""
    if count < 0 or count > 4:
        raise ValueError(f"cascade count {count}: allowed 0..4")
    if not (0.0 <= lam <= 1.0):
        raise ValueError(f"cascade split lambda {lam}: allowed [0, 1]")
    if not (near > 0.0 and far >= near):
        raise ValueError(f"cascade range [{near}, {far}]: allowed 0 < near <= far")
    n = max(count, 1)
    i = np.arange(1, n + 1, dtype=np.float64) / n
    log = near * (far / near) ** i
    uni = near + (far - near) * i
    return lam * log + (1.0 - lam) * uni


def split_fractions(near: float, far: float, count: int, lam: float) -> np.ndarray:
    """Each cascade's share of [near, far] (Unity's "Cascade Splits" percentages)."""
    ends = cascade_splits(near, far, count, lam)
    starts = np.concatenate([[near], ends[:-1]])
    return (ends - starts) / max(far - near, 1e-12)


def frustum_corners(view: np.ndarray, fov_deg: float, aspect: float, z0: float,
                    z1: float) -> np.ndarray:
    """(8, 3) world corners of the camera frustum slice between view depths z0 and z1."""
    inv = np.linalg.inv(view)
    t = np.tan(np.radians(fov_deg) / 2.0)
    pts = []
    for z in (z0, z1):
        for sx in (-1, 1):
            for sy in (-1, 1):
                pts.append([sx * t * aspect * z, sy * t * z, -z, 1.0])
    return (inv @ np.array(pts).T).T[:, :3]


def bounding_sphere(view: np.ndarray, fov_deg: float, aspect: float, z0: float,
                    z1: float) -> tuple[np.ndarray, float]:
    """The sphere around a frustum slice, centred on the view axis so that it depends only on
    the slice (not on the camera's rotation): its radius is rounded up to 1/16 m steps, so the
    map's texel size never changes as the camera turns (the stable fit)."""
    t = np.tan(np.radians(fov_deg) / 2.0)
    k2 = t * t * (1.0 + aspect * aspect)  # (corner offset / depth)²
    # centre at depth c on the axis, equidistant from the near and far corners
    c = 0.5 * (z0 + z1) * (1.0 + k2) if z1 > z0 else z0
    c = min(c, z1)
    r = float(np.sqrt(max((z1 - c) ** 2 + k2 * z1 * z1, (c - z0) ** 2 + k2 * z0 * z0)))
    r = float(np.ceil(max(r, 1e-3) * 16.0) / 16.0)
    inv = np.linalg.inv(view)
    centre = (inv @ np.array([0.0, 0.0, -c, 1.0]))[:3]
    return centre, r


def light_basis(toward_light) -> np.ndarray:
    """Rows right, up, back (= toward_light) of the light's view; +y up unless the light is
    (nearly) overhead, then +z — never a degenerate basis."""
    b = np.asarray(toward_light, np.float64)
    b = b / np.linalg.norm(b)
    up = np.array([0.0, 1.0, 0.0]) if abs(b[1]) < 0.99 else np.array([0.0, 0.0, 1.0])
    r = np.cross(up, b)
    r /= np.linalg.norm(r)
    u = np.cross(b, r)
    return np.stack([r, u, b])


def ortho_fit(toward_light, centre, radius: float, size: int, stable: bool = True,
              depth_pad: float = 20.0) -> np.ndarray:
    """World → clip matrix of an orthographic map of ``size`` texels over the sphere
    (``centre``, ``radius``); with ``stable`` the centre, in light space, snaps to whole texels
    (spec/003 §2.8: Unity's "Stable Fit"), so a moving camera moves the map by whole texels
    and its shadows do not shimmer. ``depth_pad`` metres extend the depth range toward the light
    (casters outside the sphere still cast: Unity's near-plane offset)."""
    basis = light_basis(toward_light)
    c = basis @ np.asarray(centre, np.float64)
    if stable:
        texel = 2.0 * radius / size
        c[:2] = np.floor(c[:2] / texel + 0.5) * texel
    near, far = -(radius + depth_pad), radius  # along −back, light-space z of the slab
    view = np.identity(4)
    view[:3, :3] = basis
    view[:3, 3] = -c
    proj = np.identity(4)
    proj[0, 0] = proj[1, 1] = 1.0 / radius
    # light-space z runs toward the light: z = radius + pad is the near plane (depth 0)
    proj[2, 2] = -2.0 / (far - near)
    proj[2, 3] = -(far + near) / (far - near)
    return proj @ view


def tight_fit(toward_light, corners: np.ndarray, size: int,
              depth_pad: float = 20.0) -> np.ndarray:
    """The unstable fit: the light-space box of the slice's corners (it changes with every
    camera rotation, so the texels swim — what the stable fit cures)."""
    basis = light_basis(toward_light)
    p = corners @ basis.T
    lo, hi = p.min(0), p.max(0)
    c = (lo + hi) / 2
    half = max(float((hi - lo)[:2].max()) / 2, 1e-3)
    r = max(float((hi - lo)[2]) / 2, half)
    centre = basis.T @ c
    m = ortho_fit(toward_light, centre, half, size, stable=False, depth_pad=depth_pad + r - half)
    return m


def project(m: np.ndarray, points) -> np.ndarray:
    """(…, 3) map coordinates (u, v, depth) in [0, 1] of world points under clip matrix m."""
    p = np.asarray(points, np.float64)
    h = np.concatenate([p, np.ones(p.shape[:-1] + (1,))], -1) @ m.T
    ndc = h[..., :3] / h[..., 3:4]
    return ndc * 0.5 + 0.5


def normal_bias_offset(normal, toward_light, normal_bias: float, texel_world: float):
    """The caster's inward push −n · sin(l, n) · normal_bias · texel (spec/003 §2.8:
    UnityClipSpaceShadowCasterPos; sin from cos = n·l, clamped so it is never NaN)."""
    normal_bias = normal_bias * NORMAL_BIAS_TEXELS
    n = np.asarray(normal, np.float64)
    cos = np.clip(np.sum(n * np.asarray(toward_light, np.float64), -1, keepdims=True), -1, 1)
    sin = np.sqrt(np.maximum(1.0 - cos * cos, 0.0))
    return -n * sin * normal_bias * texel_world


def linear_bias_offset(toward_light, linear_bias: float, texel_world: float):
    """The caster's push away from the light, linear_bias · texel along −l (spec/003 §2.8:
    UnityApplyLinearShadowBias, here in world units along the light direction)."""
    return -np.asarray(toward_light, np.float64) * linear_bias * LINEAR_BIAS_TEXELS * texel_world


def hard(depths: np.ndarray, uv, depth) -> np.ndarray:
    """One comparison with the nearest texel: 1 lit, 0 shadowed (rows at v)."""
    n = depths.shape[0]
    uv = np.asarray(uv, np.float64)
    x = np.clip((uv[..., 0] * n).astype(np.int64), 0, n - 1)
    y = np.clip((uv[..., 1] * n).astype(np.int64), 0, n - 1)
    return (np.asarray(depth) <= depths[y, x]).astype(np.float64)


def four_tap(depths: np.ndarray, uv, depth):
    """The thesis's soft shadow: the mean of the hard comparisons at the four diagonal
    neighbours (±1, ±1) texels of the sample (spec/003 §2.8)."""
    t = 1.0 / depths.shape[0]
    uv = np.asarray(uv, np.float64)
    return sum(hard(depths, uv + np.array([dx, dy]) * t, depth)
               for dx in (-1, 1) for dy in (-1, 1)) / 4.0


def pcss_penumbra(receiver, blocker, light_size: float) -> np.ndarray:
    """PCSS's penumbra width w = light_size · (d_r − d_b) / d_b (spec/003 §2.8, Fernando
    2005: similar triangles between the light, the blocker and the receiver); no blocker
    (d_b ≤ 0 or ≥ d_r) → 0."""
    r, b = np.asarray(receiver, np.float64), np.asarray(blocker, np.float64)
    ok = (b > 0) & (b < r)
    return np.where(ok, light_size * (r - b) / np.where(ok, b, 1.0), 0.0)


def pcss_penumbra_parallel(receiver_m, blocker_m, tan_radius: float) -> np.ndarray:
    """PCSS's penumbra width (m) under a directional light of angular radius θ (``tan_radius``
    = tan θ): the light's disc seen from the receiver spans 2 tan θ, so a blocker edge D =
    d_r − d_b metres above it (along the light) blurs over w = 2 D tan θ — the similar
    triangles of :func:`pcss_penumbra` with the light at infinity (Fernando 2005), in world
    units: independent of how the orthographic map is fitted. No blocker (d_b ≥ d_r) → 0."""
    d = np.asarray(receiver_m, np.float64) - np.asarray(blocker_m, np.float64)
    return 2.0 * tan_radius * np.maximum(d, 0.0)


def disc_taps(n: int = 32) -> np.ndarray:
    """(n, 2) offsets, in units of the disc's radius, of shadow.glsl's ``ShadowDiscAt``: tap k
    at radius √((k + ½)/n), angle k × the golden angle (a Fibonacci spiral: each tap stands for
    an equal area of the disc)."""
    k = np.arange(n) + 0.5
    r = np.sqrt(k / n)
    a = (k - 0.5) * np.pi * (3.0 - np.sqrt(5.0))
    return np.stack([r * np.cos(a), r * np.sin(a)], -1)


def blocker_search(depths: np.ndarray, uv, depth, radius_texels: int) -> float:
    """Mean depth of the texels nearer than ``depth`` in a (2r+1)² window (−1 if none)."""
    n = depths.shape[0]
    x0 = int(np.clip(uv[0] * n, 0, n - 1))
    y0 = int(np.clip(uv[1] * n, 0, n - 1))
    win = depths[max(0, y0 - radius_texels):y0 + radius_texels + 1,
                 max(0, x0 - radius_texels):x0 + radius_texels + 1]
    near = win[win < depth]
    return float(near.mean()) if near.size else -1.0


def chebyshev(mean, mean_sq, depth, bleed: float = 0.2, min_variance: float = 1e-6):
    """VSM visibility: Chebyshev's upper bound p = σ² / (σ² + (t − μ)²) for t > μ (1 where
    t ≤ μ), σ² = E[x²] − E[x]², then the light-bleeding reduction p' = clamp((p − b)/(1 − b))
    (spec/003 §2.8, Donnelly & Lauritzen 2006, then Lauritzen 2007 for the reduction)."""
    mu = np.asarray(mean, np.float64)
    var = np.maximum(np.asarray(mean_sq, np.float64) - mu * mu, min_variance)
    d = np.asarray(depth, np.float64) - mu
    p = var / (var + d * d)
    p = np.clip((p - bleed) / max(1.0 - bleed, 1e-6), 0.0, 1.0)
    return np.where(d <= 0, 1.0, p)


def point_encode(distance, linear_bias: float, light_range: float):
    """What a point light's cube map stores: (|l| + linear_bias) / range (spec/003 §2.8,
    UnityEncodeCubeShadowDepth of _LightPositionRange.w): 0 at the light, 1 at the range."""
    if light_range <= 0:
        raise ValueError(f"point light range {light_range}: allowed > 0")
    return (np.asarray(distance, np.float64) + linear_bias) / light_range


BAYER4 = np.array([[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]], np.int64)


def dither_patterns() -> np.ndarray:
    """The 17 4×4 patterns (Unity's _DitherMaskLOD): pattern k has k opaque dots, the texels
    whose ordered-dither (Bayer 4×4) threshold is below k — each pattern contains the previous
    one. (17, 4, 4) of 0/1, indexed [k, y mod 4, x mod 4]."""
    k = np.arange(17)[:, None, None]
    return (BAYER4[None] < k).astype(np.int64)


def dither_index(alpha) -> np.ndarray:
    """The pattern of opacity α: round(16 α) clamped to 0..16 (spec/003 §2.8, the thesis's
    "texture number 16·α")."""
    a = np.clip(np.nan_to_num(np.asarray(alpha, np.float64)), 0.0, 1.0)
    return np.floor(a * 16.0 + 0.5).astype(np.int64)


def dither_keep(alpha, x, y) -> np.ndarray:
    """True where the caster's fragment at pixel (x, y) survives (casts) at opacity α."""
    k = dither_index(alpha)
    return BAYER4[np.asarray(y) % 4, np.asarray(x) % 4] < k
