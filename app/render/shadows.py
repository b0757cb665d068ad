"""Shadow-map helpers shared by every effect that casts shadows: the light's view and
orthographic projection for a directional light, and the depth target a shadow pass renders
into. What a receiver samples is published in the frame's ``shadows`` slot
(:class:`app.frame.ShadowMap`).

The receivers' filter is ``glsl/common/shadow_pcf.glsl`` (percentage-closer filtering, spec/002
§3.2); :func:`configure_compare` sets a depth texture up for its hardware comparisons, and
:func:`compare_bilinear`, :func:`pcf_weights` and :func:`pcf_visibility` are its numpy twin
(on a depth map read back as an array)."""

from __future__ import annotations

import numpy as np

#: the PCF kernel of glsl/common/shadow_pcf.glsl: (2 r + 1)² taps, Gaussian σ in texels
PCF_RADIUS = 2
PCF_SIGMA = 1.0
#: how a receiver compares depths: in hardware (sampler2DShadow) or by hand (sampler2D)
COMPARE_MODES = ("hardware", "manual")


def look_at(eye, target, up) -> np.ndarray:
    """World → view matrix (right-handed, looking down −z) of a camera at ``eye`` looking at
    ``target``; ``up`` parallel to the view falls back to +x."""
    f = np.asarray(target, float) - np.asarray(eye, float)
    f /= np.linalg.norm(f)
    r = np.cross(f, up)
    if np.linalg.norm(r) < 1e-6:
        r = np.cross(f, [1.0, 0.0, 0.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    m = np.identity(4)
    m[0, :3], m[1, :3], m[2, :3] = r, u, -f
    m[:3, 3] = -m[:3, :3] @ np.asarray(eye, float)
    return m


def ortho(half: float, near: float, far: float) -> np.ndarray:
    """Orthographic projection of the square [−half, half]² between ``near`` and ``far``."""
    m = np.identity(4)
    m[0, 0] = m[1, 1] = 1.0 / half
    m[2, 2] = -2.0 / (far - near)
    m[2, 3] = -(far + near) / (far - near)
    return m


def directional_view_proj(toward_light, centre, half: float, distance: float,
                          depth: float) -> np.ndarray:
    """World → clip matrix of a directional light's shadow map covering the square of
    ``half``-width about ``centre``: the light's camera sits ``distance`` toward the light from
    the centre and sees ``depth`` metres from 1 m in front of it."""
    centre = np.asarray(centre, float)
    eye = centre + np.asarray(toward_light, float) * distance
    return ortho(half, 1.0, depth) @ look_at(eye, centre, np.array([0.0, 1.0, 0.0]))


def depth_target(gpu, owner: str, name: str, size: int):
    """(depth texture, framebuffer) of a ``size``² shadow map, allocated under ``owner``."""
    tex = gpu.depth_texture(owner, name, (size, size))
    return tex, gpu.framebuffer(owner, name, [], tex)


def configure_compare(tex, mode: str = "hardware") -> None:
    """Set a depth texture up for the receivers' comparisons: ``hardware`` — compare mode on
    (``'<='``: lit where the reference depth ≤ the stored one) with LINEAR filtering, so a
    ``sampler2DShadow`` read is one bilinear comparison; ``manual`` — compare mode off, NEAREST,
    for a ``sampler2D`` that reads depths (``texelFetch``) and compares them itself."""
    import moderngl

    if mode not in COMPARE_MODES:
        raise ValueError(f"shadow compare mode {mode!r}: allowed {', '.join(COMPARE_MODES)}")
    if mode == "hardware":
        tex.compare_func = "<="
        tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
    else:
        tex.compare_func = ""
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
    tex.repeat_x = tex.repeat_y = False  # clamp to the edge: the filter never wraps


def pcf_weights(radius: int = PCF_RADIUS, sigma: float = PCF_SIGMA) -> np.ndarray:
    """(2 r + 1)² Gaussian weights exp(−(x² + y²) / 2σ²), indexed [y + r, x + r], unnormalised
    (``ShadowPcfWeight``)."""
    k = np.arange(-radius, radius + 1, dtype=np.float64)
    return np.exp(-0.5 * (k[:, None] ** 2 + k[None, :] ** 2) / (sigma * sigma))


def compare_bilinear(depths: np.ndarray, uv: np.ndarray, depth) -> np.ndarray:
    """``ShadowCompareBilinear``: the bilinear blend of the four texels' (depth ≤ stored)
    results at ``uv`` (…, 2), texel indices clamped to the map; ``depths`` (n, n), row 0 at
    v = 0."""
    n = depths.shape[0]
    st = np.asarray(uv, dtype=np.float64) * n - 0.5
    i = np.floor(st).astype(np.int64)
    f = st - i

    def lit(dx, dy):
        x = np.clip(i[..., 0] + dx, 0, n - 1)
        y = np.clip(i[..., 1] + dy, 0, n - 1)
        return (depth <= depths[y, x]).astype(np.float64)

    fx, fy = f[..., 0], f[..., 1]
    return ((lit(0, 0) * (1 - fx) + lit(1, 0) * fx) * (1 - fy)
            + (lit(0, 1) * (1 - fx) + lit(1, 1) * fx) * fy)


def pcf_visibility(depths: np.ndarray, uv: np.ndarray, depth, radius: int = PCF_RADIUS,
                   sigma: float = PCF_SIGMA) -> np.ndarray:
    """``ShadowPcf``: the normalised Gaussian sum of bilinear comparisons about ``uv``."""
    w = pcf_weights(radius, sigma)
    texel = 1.0 / depths.shape[0]
    uv = np.asarray(uv, dtype=np.float64)
    total = np.zeros(uv.shape[:-1])
    for y in range(-radius, radius + 1):
        for x in range(-radius, radius + 1):
            total += w[y + radius, x + radius] * compare_bilinear(
                depths, uv + np.array([x, y]) * texel, depth)
    return total / float(w.sum())


def slope_bias(bias: float, n_dot_l) -> np.ndarray:
    """``ShadowSlopeBias``: bias · (1 + 4 (1 − N·L))."""
    return bias * (1.0 + 4.0 * (1.0 - np.asarray(n_dot_l, dtype=np.float64)))
