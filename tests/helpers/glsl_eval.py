"""Evaluate a GLSL function at numpy points: one point per pixel of a float target."""

from __future__ import annotations

import moderngl
import numpy as np

from app.gpu.device import Gpu


def evaluate_points(gpu: Gpu, points: np.ndarray, frag: str, uniforms: dict, textures=(),
                    defines=None) -> np.ndarray:
    """Run ``glsl/<frag>.frag`` (a full-screen probe reading ``uPoints``) over ``points`` (n, 3);
    returns (n, 4) float32. ``textures``: (uniform, texture) pairs bound from unit 1."""
    pts = np.asarray(points, dtype=np.float32).reshape(-1, 3)
    n = len(pts)
    w = min(n, 256)
    h = (n + w - 1) // w
    padded = np.zeros((h * w, 4), np.float32)
    padded[:n, :3] = pts
    src = gpu.texture("probe", "points", (w, h), 4, padded.tobytes(),
                      filter=(moderngl.NEAREST, moderngl.NEAREST))
    target = gpu.target("probe", "out", (w, h), depth=False)
    prog = gpu.program("probe", frag, defines or {}, vert="common/fullscreen.vert",
                       frag=f"{frag}.frag")
    src.use(0)
    prog.set("uPoints", 0)
    for unit, (name, tex) in enumerate(textures, start=1):
        tex.use(unit)
        prog.set(name, unit)
    prog.set_many(uniforms)
    target.use()
    prog.vao().render(moderngl.TRIANGLES, vertices=3)
    raw = np.frombuffer(target.fbo.read(components=4, dtype="f4"),
                        dtype=np.float32).reshape(h * w, 4)
    gpu.free(src)
    gpu.free(target)
    return raw[:n]
