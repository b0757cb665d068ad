"""Shadow-map helpers shared by every effect that casts shadows: the light's view and
orthographic projection for a directional light, and the depth target a shadow pass renders
into. What a receiver samples is published in the frame's ``shadows`` slot
(:class:`app.frame.ShadowMap`)."""

from __future__ import annotations

import numpy as np


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
